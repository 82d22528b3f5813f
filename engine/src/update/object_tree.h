#pragma once
// One object's tree over the frames of a sequence, and the one step that brings it up to date:
// the action the update planner chose for it (update_plan.h) carried out, with the refit or
// rebuild judged by the policy's method (judge_refit, or the measured costs of update_cost.h).
// SceneAccel holds one ObjectTree per object and one for the static group, and builds the top
// level over them.

#include "dynrt/anim/motion_class.h"
#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/block_triangles.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/update_plan.h"
#include "dynrt/scene/scene.h"
#include "update/cost_memory.h"

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dynrt {

/// What a tree with compact leaves reads its corners from (the static group under
/// UpdatePolicy::compact_static_group), held as long as the tree: the meshes' views, the
/// scene's arrays they view (held, so that a later edit of the scene copies them instead of
/// changing them under the tree) and vertices made under a transform.
struct LeafGeometry {
    LeafGeometry() = default;
    // Moved with its tree (the views' storage moves along); a copy's tree would still view
    // the original's meshes.
    LeafGeometry(LeafGeometry&&) = default;
    LeafGeometry& operator=(LeafGeometry&&) = default;
    LeafGeometry(const LeafGeometry&) = delete;
    LeafGeometry& operator=(const LeafGeometry&) = delete;

    std::vector<bvh::TriangleSource::IndexedMesh> meshes;
    std::vector<SharedArray<glm::vec3>> scene_positions;
    std::vector<SharedArray<glm::uvec3>> scene_corners;
    std::vector<std::vector<glm::vec3>> made;

    /// Holds `mesh`'s corners and `world`, its world-space vertices: the mesh's own array, or
    /// `made` (taken), or storage the caller keeps only until the next update (copied).
    /// Returns the vertices held.
    std::span<const glm::vec3> hold(const Mesh& mesh, std::span<const glm::vec3> world,
                                    std::vector<glm::vec3>& made);
    /// Heap bytes held of its own (the scene's arrays not counted).
    std::size_t bytes() const;
};

struct ObjectTree {
    /// A copy of the triangles the tree was built or refitted from, in the mesh's order (world
    /// space for deformable and exploding objects, object space for rigid ones), for a mesh
    /// with index triples. A soup's tree is built and refitted from its vertices in place and
    /// its triangles read back from the blocks (read_triangles_from_blocks), as the static
    /// group's are; either keeps this copy only where the tree has no blocks (binary-only).
    std::vector<bvh::Triangle> triangles;
    bvh::TriangleBvh tree;
    /// After read_triangles_from_blocks(): where the tree's blocks hold its triangles. A refit
    /// rewrites the blocks in place and keeps every triangle's lane, so the index stays true;
    /// only its copies of the degenerate triangles the build left out may go stale, and no ray
    /// hits those.
    bvh::BlockTriangles in_blocks;
    /// With compact leaves (tree.wide.compact): what they read (the static group's meshes, or
    /// a moving object's mesh over its posed vertices, moving_source).
    LeafGeometry leaf_geometry;
    /// The index triples last checked for a soup's (held, so that an edit of the scene's copies
    /// them rather than changing them under this record), and whether they were: a soup is
    /// found once, not by a pass over its triples every frame.
    SharedArray<glm::uvec3> soup_checked;
    bool soup_checked_is_soup = false;
    anim::MotionClass motion_class = anim::MotionClass::static_;
    /// Rigid objects: object to world this frame, and its inverse (the identity otherwise).
    glm::mat4 object_to_world{1.0f};
    glm::mat4 world_to_object{1.0f};
    /// SAH cost at the last build, and now (after refits).
    double built_sah = 0.0;
    double sah = 0.0;
    bvh::BvhStats shape;
    /// The tree matches the triangles (TreeHistory::built).
    bool built = false;
    /// built_sah, sah and shape describe the current tree (false right after a build).
    bool measured = false;
    /// Static objects: where their triangles start in the static group.
    std::uint32_t group_first = 0;
    /// An update has seen the object (so motion_class is the last update's).
    bool known = false;
    /// Rigid objects: the object-space vertices and corners its tree was built from, by
    /// address, so that another object holding the very same arrays carries this tree
    /// instead of building its own (shares_tree_of).
    const glm::vec3* built_from_positions = nullptr;
    const glm::uvec3* built_from_corners = nullptr;
    /// Rigid objects holding the same arrays as an earlier built one: that object's index,
    /// whose tree this object's instance carries (its own tree and triangles stay empty);
    /// -1 for an object with a tree of its own.
    std::int64_t shares_tree_of = -1;
    /// The builder of its current tree, and what its builds and refits measured.
    bvh::BuildMethod built_with = bvh::BuildMethod::binned_sah;
    ObjectCosts costs;

    /// For a tree just built from `source` (or a binary-only tree just refitted to it):
    /// triangle() reads its blocks through an index (4 bytes a triangle) instead of a copy of
    /// the triangles (36 bytes), or with compact leaves reads what they read (leaf_geometry,
    /// nothing more held). Where the tree has no blocks to read (a binary-only build) the
    /// copy is gathered from `source` into `triangles` after all.
    void read_triangles_from_blocks(const bvh::TriangleSource& source);
    /// Triangles the tree was built from.
    std::size_t triangle_count() const {
        if (tree.wide.compact) return tree.wide.source.size();
        return in_blocks.indexed() ? in_blocks.size() : triangles.size();
    }
    /// Triangle `prim` (< triangle_count()) as the tree was built from it, bit for bit.
    bvh::Triangle triangle(std::uint32_t prim) const {
        if (tree.wide.compact) return tree.wide.source[prim];
        return in_blocks.indexed() ? in_blocks.at(tree, prim) : triangles[prim];
    }
    /// Asks the cache for triangle `prim`'s lines, before triangle() reads it.
    void prefetch_triangle(std::uint32_t prim) const;
    /// Heap bytes of `triangles` or of the index that replaced them (or of leaf_geometry).
    std::size_t triangle_bytes() const;
    /// Whether `mesh` is a soup over `positions` (TriangleSource::is_soup, checked again only
    /// when its index triples are another array than last time).
    bool reads_as_soup(const Mesh& mesh, std::span<const glm::vec3> positions);
    /// What a deformable or exploding object's tree with compact leaves reads: `positions` (its
    /// world-space vertices this update) in place as a soup, or through the mesh's index
    /// triples, held in leaf_geometry.
    bvh::TriangleSource moving_source(const Mesh& mesh, std::span<const glm::vec3> positions);
    /// Points such a tree, kept as it is, at this update's `positions` (equal to the ones it
    /// was built or refitted from, perhaps in other storage).
    void view_moving_positions(const Mesh& mesh, std::span<const glm::vec3> positions);
};

/// Builds `object`'s tree from `source` (its own triangles, or the static group's meshes) with
/// `config`'s builder, and records the time in its costs and in `memory`. Its SAH cost and
/// shape are measured later (measure_tree), outside the build's time.
void build_tree(ObjectTree& object, const bvh::TriangleSource& source, const bvh::BuildConfig& config,
                CostMemory& memory);

/// After a build: records the new tree's SAH cost (what later refits are compared with, and
/// what the automatic method predicts trace times from) and shape; a no-op for a tree measured
/// already.
void measure_tree(ObjectTree& object, const bvh::SahCosts& costs);

/// One object of an update: which it is, the mesh and pose it has now, and what was planned.
struct ObjectUpdate {
    std::size_t index;
    const std::string& name;
    const Mesh& mesh;
    /// The positions its triangles are gathered from: object space for a rigid object, world
    /// space for the others.
    std::span<const glm::vec3> positions;
    ObjectPlan planned;
    /// The builder and its settings for a rebuild (the object's class's, and the method's).
    bvh::BuildConfig config;
    /// Its inputs to the automatic method's choices (CostMemory::trace_cost, from the last
    /// update, taken before this one changes anything); unused by the other methods.
    TraceCost trace;
};

/// Carries out `update.planned.action` on `object` (a rebuild or a refit; keep and
/// move_instance only count as skipped; build_in_static_group is the static group's), and
/// records the work, its times and its choices in `stats`. Throws what the builder throws, the
/// tree then marked not built so that the next update rebuilds it.
void update_tree(ObjectTree& object, const ObjectUpdate& update, const UpdatePolicy& policy,
                 CostMemory& memory, UpdateStats& stats);

}  // namespace dynrt
