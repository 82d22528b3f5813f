#pragma once
// The update planner: which action each object's tree gets this frame, decided from what the
// trees were after the last update and what moved since, before any vertex is read. A pure
// function of its inputs, so the update matrix (which objects moved x their class x the
// policy) is unit-tested without trees or a renderer (tests/update_plan_test.cpp), as Embree's
// verify suite tests its update modes; SceneAccel (engine/src/update/) only carries a plan out.
//
// Per motion class (anim/motion_class.h):
//
//   static      every static object's triangles are in one world-space tree, the static group,
//               built at the first update and rebuilt only when an object joins or leaves it
//               (or its triangles were replaced); otherwise kept.
//   rigid       built once, in object space; afterwards only its instance transform moves.
//   deformable  refitted when it changed; judge_refit then keeps the refit or rebuilds: when
//               the refitted tree's SAH cost exceeds the cost at its last build by more than
//               UpdatePolicy::rebuild_threshold (a refit keeps the topology chosen for the old
//               shape, so quality decays), or when a refit cannot keep the tree correct (a
//               triangle left out as degenerate at the build has gained area).
//   exploding   rebuilt whenever it changed, with a cost ratio of its own.
//
// That is UpdateMethod::threshold. The default, UpdateMethod::automatic, plans the same
// actions, but SceneAccel judges a deformable object's refit, and picks the builder of every
// deformable or exploding rebuild, from measured costs (update_cost.h). The fixed methods
// refit, fast and sah plan a refit, or a rebuild with the Morton or binned SAH builder, for
// every changed deformable or exploding object.
//
// An object whose class changes keeps its tree when the tree's space stays the same (world
// space for static-group members aside: deformable and exploding trees are in world space,
// rigid ones in object space); otherwise it is built afresh ("class changed").

#include "dynrt/anim/motion_class.h"
#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/update_cost.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dynrt {

/// How objects are updated (RenderOptions carries it; the library API has its own).
struct UpdatePolicy {
    /// Builds of static, rigid and deformable objects.
    bvh::BuildConfig build;
    /// Cost ratio of the per-frame rebuilds of exploding objects: a tree built every frame and
    /// traced once pays its build in every frame, which favours shallower trees than the ratio
    /// that minimises trace time alone.
    float exploding_cost_ratio = 0.3f;
    /// Rebuild a deformable object when its refitted SAH cost exceeds (1 + threshold) times
    /// the cost at its last build. 0 rebuilds on any degradation; +inf never.
    double rebuild_threshold = 0.3;
    /// How deformable and exploding objects are updated (update_cost.h).
    UpdateMethod method = UpdateMethod::automatic;
    /// Static objects are merged into one world-space tree (the static group) while it would
    /// hold at most this many triangles. Past it, static copies of a shared mesh (Mesh,
    /// SharedArray: a forest of one tree, a glTF mesh many nodes reference) stay instances of
    /// one tree in object space, as rigid objects are, so that each copy costs bytes, not
    /// triangles; the others are merged still.
    std::size_t static_group_limit = std::size_t(1) << 24;
    /// The static group's tree with compact leaves (bvh::BuildConfig::compact_leaves): its
    /// leaves keep the triangles' indices and read the corners from the scene's own vertices,
    /// about 40 bytes a triangle fewer, the same images bit for bit (`--leaves compact`). From
    /// 2^20 triangles on it is built for memory too (bvh::BuildConfig::leaf_size_min 4, from
    /// 2^23 8: each about half the build's nodes at its peak). Other trees keep full blocks
    /// unless compact_moving_objects says otherwise (build.compact_leaves is ignored).
    bool compact_static_group = false;
    /// Deformable and exploding objects' trees with compact leaves too (`--leaves compact`):
    /// they read the posed vertices in place, about 40 bytes a triangle fewer, and a mesh with
    /// index triples keeps no copy of its triangles (36 more); the same images bit for bit.
    /// Their ObjectState::world_positions must then stay valid and unchanged until the next
    /// update, as world_normals must (the Renderer's posed scene does; the library API does
    /// not set it). A refit of such a tree cannot tell whether any vertex moved (the leaves
    /// keep none to compare with), so it counts as a refit where full blocks would find nothing
    /// moved and skip the object. Rigid objects' trees keep full blocks.
    bool compact_moving_objects = false;
    /// The static group's tree with quantised nodes (bvh::BuildConfig::quantized_nodes): its
    /// child boxes in 8-bit planes, 128 bytes a node instead of 256, the same images bit for
    /// bit (`--nodes quantized`). Other trees, which may be refitted, keep float nodes.
    bool quantized_static_group = false;
    /// A budget for the process's resident memory, in bytes (0: none; `--memory-budget`): the
    /// static group is then built with the fastest layout whose build is predicted to stay
    /// within it (engine/src/update/static_group_layout.h), and compact_static_group and
    /// quantized_static_group are ignored. The choice and its prediction are reported
    /// (UpdateStats::static_layout).
    std::size_t memory_budget = 0;
};

/// One object at one update, as the planner and SceneAccel read it: what a PosedScene says of
/// it, or what the library API (dynrt/dynrt.h) gathered from its caller.
struct ObjectState {
    anim::MotionClass motion_class = anim::MotionClass::static_;
    /// False when nothing about the object changed since the previous update: it is then
    /// skipped without reading its vertices (unless its tree must be built).
    bool changed = true;
    /// Static and rigid objects: object to world at this update, in double (ignored for the
    /// other classes; read for a static object only when it stays an instance,
    /// UpdatePolicy::static_group_limit).
    glm::dmat4 transform{1.0};
    /// Deformable and exploding objects: world-space positions at this update, indexed as the
    /// mesh's positions (borrowed for the call; ignored for static and rigid objects).
    std::span<const glm::vec3> world_positions;
    /// Deformable and exploding objects: world-space unit vertex normals, indexed alike, or
    /// empty (flat shading). Borrowed until the next update: shading reads them at every trace.
    std::span<const glm::vec3> world_normals;
};

/// What the trees of one object were after the last update: the planner's memory.
struct TreeHistory {
    /// An update has seen the object (so motion_class is the last update's class).
    bool known = false;
    anim::MotionClass motion_class = anim::MotionClass::static_;
    /// Its own tree matches its triangles (never for static objects, which have none).
    bool built = false;
};

/// The same for the static group.
struct StaticGroupHistory {
    /// It has been built once (a later build is a change, not the first build).
    bool known = false;
    /// It matches its members' triangles: false before the first update and after one of its
    /// members' triangles were replaced.
    bool built = false;
};

/// What an object's tree gets this frame.
enum class TreeAction : std::uint8_t {
    /// Nothing: an unchanged object with a tree, or a static object whose group is kept.
    keep,
    /// A rigid object with a tree that moved: only its instance transform is written.
    move_instance,
    /// A deformable object with a tree that changed: its triangles are gathered and the tree
    /// refitted; judge_refit then keeps the refit or rebuilds.
    refit,
    /// Built from its vertices, for `reason`.
    rebuild,
    /// A static object: its triangles go into the static group, rebuilt this frame.
    build_in_static_group,
};

/// "keep", "move instance", "refit", "rebuild", "build in static group".
const char* tree_action_name(TreeAction action);

/// One object's part of a plan.
struct ObjectPlan {
    TreeAction action = TreeAction::keep;
    /// For rebuild and build_in_static_group: why.
    RebuildReason reason = RebuildReason::first_build;
    /// Its class changed into static (it joins the static group) or out of it (it leaves).
    bool joins_static_group = false;
    bool leaves_static_group = false;
};

/// One action per object (scene order) and the static group's. A refit, or an exploding
/// object's rebuild of the tree it has, is skipped after all (counted as kept) when the
/// gathered triangles equal the stored ones: the animation said they changed, the vertices
/// say not. That check reads vertices, so the executor makes it.
struct UpdatePlan {
    std::vector<ObjectPlan> objects;
    /// Whether the static group is rebuilt, and why (first_build or static_group_changed).
    bool rebuild_static_group = false;
    RebuildReason static_group_reason = RebuildReason::first_build;
};

/// Plans the update of `now.size()` objects from their trees' `previous` state (one per
/// object seen before, scene order; objects past its end are new) and the static group's.
/// Reads only motion_class and changed of `now`. `previous.size() <= now.size()` (a scene
/// that lost objects starts afresh, with empty `previous`).
UpdatePlan plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                       std::span<const ObjectState> now);

/// The same into `plan`, whose storage is reused (SceneAccel plans every frame).
void plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                 std::span<const ObjectState> now, UpdatePlan& plan);

/// The same under `method`: refit plans a refit for exploding objects too; fast and sah plan a
/// rebuild (reason update_method) for every changed deformable or exploding object with a
/// tree. threshold and automatic plan as above.
void plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                 std::span<const ObjectState> now, UpdateMethod method, UpdatePlan& plan);

/// After a planned refit: whether its result stands (nullopt) or the object is rebuilt, and
/// why. `sah_at_last_build` is the tree's SAH cost when it was last built.
std::optional<RebuildReason> judge_refit(const bvh::RefitResult& refit, double sah_at_last_build,
                                         const UpdatePolicy& policy);

/// Library API meshes declared Motion::automatic start static and are raised by what their
/// caller changes: a moved transform makes them at least rigid, moved positions at least
/// deformable; a class is never lowered.
anim::MotionClass raise_automatic_class(anim::MotionClass current, bool transform_changed,
                                        bool positions_changed);

/// An automatic deformable mesh whose refits degraded past the threshold this many updates in
/// a row is rebuilt every time anyway: it is then treated as exploding, which skips the refit.
inline constexpr int kDegradedStepsToExploding = 3;

/// The class an automatic mesh gets after an update in which it `changed`, with its streak of
/// updates whose refit degraded (`degraded_steps`, updated here): exploding once the streak
/// reaches kDegradedStepsToExploding, else `motion_class` unchanged. Only deformable meshes
/// that changed count; others keep their streak.
anim::MotionClass class_after_update(anim::MotionClass motion_class, bool changed,
                                     bool refit_degraded, int& degraded_steps);

}  // namespace dynrt
