#pragma once
// The acceleration structure of a scene over the frames of a sequence: one bottom-level tree
// per object, kept from frame to frame and brought up to date by the action the update planner
// chose for it (dynrt/engine/update_plan.h: what each class gets, and why), and a top level
// over the objects, rebuilt every frame in which a tree or a transform changed (kept when
// nothing did: a still forest of copies would rebuild it over every instance). SceneAccel
// carries a plan out, each object's step in object_tree.h (gather its triangles, build or
// refit, judge the refit), times each stage and reports it; beside the trees it keeps the cost model's
// memory (cost_memory.h) and what shading reads of the objects (shading_geometry.h).
//
// Static objects share one tree (the static group), built in world space at the first
// update, so a scene of static objects traces exactly one tree over all its triangles.
//
// Instancing: objects that hold copies of one mesh (Mesh's arrays are shared, SharedArray) and
// stay rigid carry one tree, built for the first of them in object space; the others' instances
// point at it, each with its own transform, so a copy costs bytes, not triangles. Static copies
// join them once merging every static triangle would pass UpdatePolicy::static_group_limit
// (a forest of a billion instanced triangles cannot be one world-space tree).
//
// An object whose ObjectState::changed is false costs nothing, so a frame that repeats the
// previous one does no update work at all. Hits report the object index (scene order) and the
// triangle index within the object.

#include "dynrt/anim/motion_class.h"
#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/update_plan.h"
#include "dynrt/scene/scene.h"
#include "update/cost_memory.h"
#include "update/object_tree.h"
#include "update/shading_geometry.h"

#include <glm/mat4x4.hpp>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dynrt {

/// The vertices of static and rigid objects, read only when their trees are built.
class FixedPositions {
public:
    virtual ~FixedPositions() = default;
    /// A rigid object's object-space positions: world = ObjectState::transform * these.
    virtual std::span<const glm::vec3> object_space(std::size_t object) const = 0;
    /// A static object's world-space positions: a span into storage of its own, or into
    /// `scratch`, which it may fill.
    virtual std::span<const glm::vec3> world(std::size_t object,
                                             std::vector<glm::vec3>& scratch) const = 0;
    /// A rigid object's unit vertex normals in object space, indexed as object_space(), or
    /// empty (flat shading). Read at every update; must stay valid until the next one.
    virtual std::span<const glm::vec3> object_space_normals(std::size_t /*object*/) const { return {}; }
    /// A static object's world-space unit vertex normals, indexed as world(): in storage of
    /// its own, which must stay valid until the next update (shading borrows it, and takes it
    /// again at every update), or made in `scratch` (then copied when the static group is
    /// built); empty for flat shading.
    virtual std::span<const glm::vec3> world_normals(std::size_t /*object*/,
                                                     std::vector<glm::vec3>& /*scratch*/) const {
        return {};
    }
};

class SceneAccel {
public:
    /// Carries out the update planner's plan (update_plan.h) for `objects` (one per scene
    /// object, scene order), rebuilds the top level and records the work in `stats` (class
    /// counts, refit / rebuild / top-level ms, skipped objects, rebuilds and why) and the
    /// trees' shape in `shape`. Gathering the triangles from the vertices is added to
    /// update_ms (it is evaluating the scene, as posing is), not to the tree's times. The first
    /// call after construction or clear() builds every tree; objects added to the end of the
    /// scene since the last call are new to the planner.
    /// Throws SceneError for non-finite static positions (from `fixed`).
    void update(const Scene& scene, std::span<const ObjectState> objects,
                const FixedPositions& fixed, const UpdatePolicy& policy, UpdateStats& stats,
                TreeShape& shape);

    /// Forgets every tree: the next update builds from scratch (another scene, or the same
    /// scene after its objects were edited).
    void clear();

    /// Forgets one object's tree (its mesh's triangles were replaced): the next update builds
    /// it afresh, or the static group when the object is static.
    void invalidate(std::size_t object);

    /// Frees object `object`'s storage (its triangles, tree, normals and costs), keeping what
    /// the planner knows of it (its class, that its empty tree is built), so that an object
    /// left without triangles costs no memory and no work in later updates. Precondition: the
    /// last update saw the object with no triangles (a removed mesh's slot, emptied).
    void release(std::size_t object);

    /// Object `object` is a new one (a freed slot taken by another mesh): its history is
    /// forgotten, so the next update plans it as an object never seen (first build, or the
    /// static group rebuilt when it is static), with fresh costs.
    void renew(std::size_t object);

    /// Heap bytes held: every object's triangles, trees (binary and wide) and normals, the
    /// static group, the top level and the per-object records. Not thread-safe with update().
    std::size_t memory_bytes() const;
    /// Of those, the trees (nodes and leaves of every object and the static group, the top
    /// level) and the triangles they are built from, into `out`'s tree_bytes and
    /// build_triangle_bytes.
    void memory_figures(MemoryStats& out) const;
    /// Per holder of a tree, its tree_bytes and build_triangle_bytes (ObjectMemory; object and
    /// triangles set, names and scene bytes left to the caller): each object with a tree of
    /// its own, then the static objects' shared tree (object -1) when there is one.
    std::vector<ObjectMemory> memory_by_object() const;

    const bvh::TwoLevelBvh& top_level() const { return top_; }

    /// The trace time (primary + shadow rays) of the frame just traced on these trees: the
    /// automatic update method predicts the next frames' trace times from it (update_cost.h).
    void note_trace_ms(double ms) { costs_.note_trace_ms(ms); }

    /// World-space triangle `prim` of `object` at the last update (for shading hits):
    /// transformed from object space for rigid objects, in float, the same for every caller.
    bvh::Triangle world_triangle(std::size_t object, std::uint32_t prim) const;

    /// The objects' corners and vertex normals at the last update, as shading reads them.
    const ShadingGeometry& shading() const { return shading_; }
    /// Whether shading() gives the objects' vertex normals (ShadingGeometry::use_vertex_normals).
    void use_vertex_normals(bool on) { shading_.use_vertex_normals(on); }

    /// Turns a hit on the static group (see below) into the object and triangle it hit; any
    /// other hit is left as it is. Every hit from top_level() goes through it before use.
    void resolve(bvh::InstanceHit& hit) const {
        if (hit.object != static_group_id()) return;
        // Once per hit: the bucket's table narrows the search to the few objects that start
        // within the bucket. A table per triangle was one cache miss per incoherent hit (a
        // seventh of the time of a million random rays into a million triangles).
        const std::uint32_t bucket = hit.hit.prim >> kStaticBucketShift;
        const auto from = static_first_.begin() + static_bucket_slot_[bucket];
        const auto to = static_first_.begin() + static_bucket_slot_[bucket + 1] + 1;
        const std::size_t k = std::size_t(std::upper_bound(from, to, hit.hit.prim) - static_first_.begin()) - 1;
        hit.object = static_objects_[k];
        hit.hit.prim -= static_first_[k];
    }

    /// Triangle `prim` of the tree that instances named `object` carry in top_level() (the
    /// static group's id included), exactly as that tree stores it; none when the tree has no
    /// such triangle. Hits before resolve() name their tree so.
    std::optional<bvh::Triangle> tree_triangle(std::uint32_t object, std::uint32_t prim) const;

    /// Asks the cache for the lines world_triangle(object, prim) reads.
    void prefetch_triangle(std::size_t object, std::uint32_t prim) const;

    /// World-space bounds of the whole scene at the last update.
    bvh::Aabb world_bounds() const;

    /// Per object (scene order), a world-space box around its triangles at the last update
    /// (padded like the top level's boxes for moving objects; empty for an object without
    /// triangles). Static objects share one tree, so this is the only per-object extent of
    /// theirs; adaptive sampling uses it to tell which objects can reach into a cell.
    const std::vector<bvh::Aabb>& object_world_boxes() const { return object_boxes_; }

    /// Appends to `out` up to `max_parts` world-space boxes that together hold object `i`'s
    /// triangles at the last update: the boxes of a cut through its own tree, split largest
    /// surface first (Goldsmith and Salmon's area measure), transformed to world space for a
    /// rigid object. Tighter than its one box, so that exact pixel reuse re-traces only the
    /// rays that pass near its triangles. An object without a tree of its own (static, or
    /// not built) gives its world box; one without triangles gives nothing.
    void object_world_parts(std::size_t i, std::size_t max_parts, std::vector<bvh::Aabb>& out) const;

private:
    struct Update;
    /// Object `i`'s step of update `run`: its class counted, its rigid transform taken, the
    /// planned action carried out on its tree.
    void update_object(std::size_t i, const Update& run, UpdateStats& stats);
    /// The top level over the static group and the other objects' trees, and the objects'
    /// world boxes from it.
    void build_top(UpdateStats& stats);
    /// Measures the trees built this update, the scene's SAH cost for the cost model, and the
    /// whole structure's shape into `shape`.
    void measure(const bvh::SahCosts& costs, TreeShape& shape);
    /// Under a memory budget, sets `config`'s static group layout to the one
    /// choose_static_group_layout picks for the static triangles of `objects`, and reports it.
    void choose_static_layout(const Scene& scene, std::span<const ObjectState> objects, std::size_t budget,
                              bvh::BuildConfig& config, UpdateStats& stats);
    void build_static_group(const Scene& scene, std::span<const ObjectState> objects,
                            const FixedPositions& fixed, const bvh::BuildConfig& config,
                            RebuildReason reason, UpdateStats& stats);
    /// The tree holding object `object`'s triangles (the static group for a static object, the
    /// tree it carries for a copy of another object's mesh), and the index of its triangle 0
    /// there.
    std::pair<const ObjectTree*, std::uint32_t> holder_of(std::size_t object) const;
    /// The states the trees are updated by: `states`, except that static copies of shared
    /// meshes are rigid when the static group would pass the policy's limit (Instancing).
    std::span<const ObjectState> instancing_states(const Scene& scene, std::span<const ObjectState> states,
                                                   const UpdatePolicy& policy);
    /// For a rigid object about to be built from `positions`: an object already built from
    /// the very same arrays, whose tree it can carry.
    std::optional<std::size_t> tree_to_share(std::size_t object, std::span<const glm::vec3> positions,
                                             const Mesh& mesh) const;
    /// Objects carrying object `owner`'s tree carry it no more (it is rebuilt or freed): their
    /// next update builds or finds another.
    void forget_sharers_of(std::size_t owner);
    /// Fills static_bucket_slot_ for the static group's `total` triangles.
    void index_static_buckets(std::size_t total);
    /// The instance id of the static group: one past the last object index, so it collides
    /// with no object (ties between instances go to the lower id).
    std::uint32_t static_group_id() const { return std::uint32_t(objects_.size()); }

    /// Per object (scene order); static objects keep no tree of their own.
    std::vector<ObjectTree> objects_;
    /// All static objects in one world-space tree, built at the first update: their
    /// triangles concatenated in scene order, static_objects_[k]'s from static_first_[k].
    ObjectTree static_group_;
    std::vector<std::uint32_t> static_first_;
    std::vector<std::uint32_t> static_objects_;
    /// Per bucket of 2^kStaticBucketShift triangles of the static group, the k in
    /// static_objects_ of its first triangle's object; one more entry past the last bucket.
    /// (16 KB per million triangles: it stays in cache where a table per triangle did not.)
    static constexpr int kStaticBucketShift = 8;
    std::vector<std::uint32_t> static_bucket_slot_;
    /// The tree behind each instance of the top level, in instance order.
    std::vector<ObjectTree*> instance_trees_;
    bvh::TwoLevelBvh top_;
    std::vector<bvh::Aabb> object_boxes_;
    /// The planner's input and output, reused from frame to frame.
    std::vector<TreeHistory> history_;
    UpdatePlan plan_;
    bool static_group_known_ = false;
    /// Where rigid trees were built from (ObjectTree::built_from_positions), to the object that
    /// built it; checked against that object's record when read.
    struct SourceKey {
        const glm::vec3* positions;
        const glm::uvec3* corners;
        std::size_t vertices;
        bool operator==(const SourceKey&) const = default;
    };
    struct SourceKeyHash {
        std::size_t operator()(const SourceKey& k) const {
            return std::hash<const void*>()(k.positions) ^ (std::hash<const void*>()(k.corners) * 31u) ^ k.vertices;
        }
    };
    std::unordered_map<SourceKey, std::size_t, SourceKeyHash> rigid_trees_;
    /// top_ is over the trees and transforms the objects have now: false from construction
    /// and after anything that touches a tree outside an update.
    bool top_current_ = false;
    /// The states of the last update with static copies made rigid (instancing_states).
    std::vector<ObjectState> instancing_states_;
    /// What the automatic update method remembers across frames.
    CostMemory costs_;
    /// The objects' corners and vertex normals, refreshed by every update.
    ShadingGeometry shading_;
};

}  // namespace dynrt
