#include "update/object_tree.h"

#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/engine/stopwatch.h"
#include "update/held_bytes.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <optional>

namespace dynrt {

namespace {

bool same(const bvh::Triangle& a, const bvh::Triangle& b) {
    return a.v0 == b.v0 && a.v1 == b.v1 && a.v2 == b.v2;
}

/// triangles[t] = the mesh's triangle t over `positions`. Returns whether any triangle differs
/// from what `triangles` held (true when its size changes): the fallback that catches frames
/// whose animation data changed but whose vertices did not, at the price of a compare in the
/// pass that writes them anyway.
bool assemble(const Mesh& mesh, std::span<const glm::vec3> positions,
              std::vector<bvh::Triangle>& triangles) {
    const bool resized = triangles.size() != mesh.triangles.size();
    triangles.resize(mesh.triangles.size());
    std::atomic<bool> changed{resized};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          bool differs = false;
                          for (std::size_t t = range.begin(); t < range.end(); ++t) {
                              const glm::uvec3& i = mesh.triangles[t];
                              const bvh::Triangle tri{positions[i.x], positions[i.y], positions[i.z]};
                              differs |= !same(tri, triangles[t]);
                              triangles[t] = tri;
                          }
                          if (differs) changed.store(true, std::memory_order_relaxed);
                      });
    return changed.load();
}

/// Whether `source`'s triangles differ from those `object`'s tree holds (ObjectTree::triangle,
/// bit for bit as built or refitted); true for a tree not built or of another size. The same
/// fallback as assemble's, for a soup, which keeps no copy to compare with.
bool differs_from_tree(const ObjectTree& object, const bvh::TriangleSource& source) {
    if (!object.built || object.triangle_count() != source.size()) return true;
    std::atomic<bool> differs{false};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, source.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          if (differs.load(std::memory_order_relaxed)) return;
                          for (std::size_t t = range.begin(); t < range.end(); ++t) {
                              if (!same(source[t], object.triangle(std::uint32_t(t)))) {
                                  differs.store(true, std::memory_order_relaxed);
                                  return;
                              }
                          }
                      });
    return differs.load();
}

/// One object's update in progress: its tree, what it was asked, and where its figures go.
///
/// What the build and the refit read: a soup's vertices in place, each triangle's three corners
/// side by side, as a copy would hold them; no copy is kept, its triangles read back from the
/// tree's blocks (4 bytes a triangle instead of 36). A mesh with index triples is gathered
/// into a copy (ObjectTree::triangles) first: read through the triples, a triangle costs a
/// second cache line (the triple, then its vertices), and refitting a 4M-triangle sphere
/// through them took 1.7x as long as from the copy, more than the gather saved. With compact
/// leaves (UpdatePolicy::compact_moving_objects) memory comes first: the mesh is read through
/// its triples, no copy is made, and the tree keeps reading the posed vertices.
class TreeUpdate {
public:
    TreeUpdate(ObjectTree& object, const ObjectUpdate& update, const UpdatePolicy& policy,
               CostMemory& memory, UpdateStats& stats)
        : object_(object), update_(update), policy_(policy), memory_(memory), stats_(stats),
          config_(update.config), soup_(object.reads_as_soup(update.mesh, update.positions)),
          compact_(update.config.compact_leaves && update.config.wide &&
                   update.config.leaf_size_max <= bvh::kWideLeafSizeMax) {}

    void rebuild();
    void refit();

private:
    /// The automatic method chose `choice`'s builder, for the reason `why`.
    void choose(const RebuildChoice& choice, const std::string& why) {
        config_.method = choice.method;
        stats_.choices.push_back(TreeChoice{
            update_.index, update_.name,
            choice.method == bvh::BuildMethod::morton ? "rebuild (fast)" : "rebuild (sah)", why});
    }
    /// The triangles to build or refit from: the soup in place, the posed vertices a compact
    /// tree reads, or the copy gather() made.
    bvh::TriangleSource source() const {
        if (compact_) return object_.moving_source(update_.mesh, update_.positions);
        if (soup_) return bvh::TriangleSource::soup(update_.positions.first(3 * update_.mesh.triangles.size()));
        return bvh::TriangleSource(object_.triangles);
    }
    /// Rebuilds the tree for `reason` (after any choice: the builder is part of the record).
    void build(RebuildReason reason, double refitted_sah = 0.0) {
        stats_.rebuilds.push_back(TreeRebuild{update_.index, update_.name, reason, refitted_sah,
                                              object_.built_sah, bvh::build_method_name(config_.method)});
        ++stats_.objects_rebuilt;
        stats_.triangles_rebuilt += update_.mesh.triangles.size();
        // The tree does not match the triangles until the build completes: should it throw,
        // the next update must rebuild, not refit.
        object_.built = false;
        build_tree(object_, source(), config_, memory_);
        // A soup's triangles are read back from the blocks from now on (but for a binary-only
        // tree, which gathers a copy after all), and compact leaves' from the posed vertices.
        if (soup_ || compact_) object_.read_triangles_from_blocks(source());
        stats_.rebuild_ms += clock_.lap_ms();
    }
    /// Whether the positions moved any triangle from where the tree has it; a mesh with index
    /// triples gathers its copy on the way. Timed as update_ms, evaluating the scene.
    bool moved() {
        // Compact leaves keep nothing to compare with: the tree they would be compared with
        // reads the very vertices (in place) the pose may have rewritten.
        if (compact_) return true;
        clock_.lap_ms();
        bool moved = false;
        if (soup_) {
            moved = differs_from_tree(object_, source());
        } else {
            moved = assemble(update_.mesh, update_.positions, object_.triangles);
            object_.in_blocks = {};  // the copy is what triangle() reads
        }
        stats_.update_ms += clock_.lap_ms();
        return moved;
    }
    /// After a refit into `refit`: the rebuild the policy's method asks for, if any.
    std::optional<RebuildReason> judge(const bvh::RefitResult& refit);

    ObjectTree& object_;
    const ObjectUpdate& update_;
    const UpdatePolicy& policy_;
    CostMemory& memory_;
    UpdateStats& stats_;
    bvh::BuildConfig config_;
    /// The mesh is a soup, read in place (else through a copy).
    const bool soup_;
    /// The tree has or gets compact leaves (it reads the posed vertices; no copy).
    const bool compact_;
    Stopwatch clock_;
};

void TreeUpdate::rebuild() {
    // Only an exploding object's rebuild replaces a tree that matches its class; every other
    // rebuild has none to keep.
    const bool had_tree = update_.planned.reason == RebuildReason::exploding;
    // A soup needs no gather: the comparison is all it would be for, and has nothing to
    // compare with without a tree.
    const bool changed = had_tree || !soup_ ? moved() : true;
    if (had_tree && !changed) {
        // The animation said it changed; its vertices say otherwise.
        ++stats_.objects_skipped;
        return;
    }
    if (policy_.method == UpdateMethod::automatic && had_tree) {
        const RebuildChoice choice =
            choose_rebuild(object_.costs, update_.mesh.triangles.size(), memory_.rates(), update_.trace);
        choose(choice, explain_rebuild(choice));
    }
    build(update_.planned.reason);
}

void TreeUpdate::refit() {
    if (object_.built && !object_.tree.wide.empty() && object_.tree.wide.compact != compact_) {
        // A tree of the other layout (UpdatePolicy::compact_moving_objects changed between
        // updates) is replaced, as if there were none: a refit keeps the layout it has.
        if (!soup_ && !compact_) moved();  // gathers the copy the build reads
        build(RebuildReason::first_build);
        return;
    }
    // A soup finds out whether anything moved as it refits (RefitResult::moved), unless the
    // refit is skipped for a rebuild.
    if (!soup_ && !moved()) {
        ++stats_.objects_skipped;
        return;
    }
    const std::size_t triangles = update_.mesh.triangles.size();
    if (policy_.method == UpdateMethod::automatic) {
        if (const std::optional<RebuildChoice> skip =
                rebuild_instead_of_refit(object_.costs, triangles, memory_.rates(), update_.trace)) {
            if (soup_ && !moved()) {
                ++stats_.objects_skipped;
                return;
            }
            choose(*skip, explain_skipped_refit(object_.costs, *skip));
            build(RebuildReason::refits_cost_more, object_.sah);
            return;
        }
    }
    clock_.lap_ms();
    object_.built = false;  // until the refit completes (see build)
    const bvh::RefitResult refit = bvh::refit(object_.tree, source(), policy_.build.sah_costs());
    object_.built = !refit.needs_rebuild();
    if (soup_ && !refit.needs_rebuild()) {
        if (!refit.moved) {
            // No vertex moved: the refit left the tree as it was, and its pass is what the
            // comparison cost (timed as such, as assemble's).
            stats_.update_ms += clock_.lap_ms();
            ++stats_.objects_skipped;
            return;
        }
        // A binary-only tree reads a copy, to refresh; a wide tree's blocks were rewritten in
        // place, where the index finds them.
        if (!object_.in_blocks.indexed()) object_.read_triangles_from_blocks(source());
    }
    const double refit_ms = clock_.lap_ms();
    stats_.refit_ms += refit_ms;
    object_.costs.refit_ms = refit_ms;
    ++stats_.objects_refitted;
    stats_.triangles_refitted += triangles;
    if (const std::optional<RebuildReason> rebuild = judge(refit)) {
        const bool degraded = *rebuild == RebuildReason::sah_degraded ||
                              *rebuild == RebuildReason::refits_cost_more;
        build(*rebuild, degraded ? refit.sah_cost : 0.0);
    } else {
        object_.sah = refit.sah_cost;
    }
}

std::optional<RebuildReason> TreeUpdate::judge(const bvh::RefitResult& refit) {
    if (refit.needs_rebuild()) return RebuildReason::degenerate_gained_area;
    if (policy_.method == UpdateMethod::threshold) return judge_refit(refit, object_.built_sah, policy_);
    if (policy_.method != UpdateMethod::automatic) return std::nullopt;
    const RefitJudgement judgement =
        judge_refit_cost(refit.sah_cost, object_.built_sah, object_.costs,
                         update_.mesh.triangles.size(), memory_.rates(), update_.trace);
    if (judgement.rebuild) {
        choose(judgement.choice, explain_refit(judgement));
        return RebuildReason::refits_cost_more;
    }
    object_.costs.penalty_ms = judgement.penalty_ms;
    object_.costs.last_extra_ms = judgement.extra_ms;
    stats_.choices.push_back(TreeChoice{update_.index, update_.name, "refit", explain_refit(judgement)});
    return std::nullopt;
}

}  // namespace

void build_tree(ObjectTree& object, const bvh::TriangleSource& source, const bvh::BuildConfig& config,
                CostMemory& memory) {
    const Stopwatch clock;
    object.tree = bvh::build_triangle_bvh(source, config, std::move(object.tree));
    const double ms = clock.elapsed_ms();
    object.measured = false;
    object.built = true;
    object.built_with = config.method;
    memory.note_build(config.method, source.size(), ms, object.costs);
}

std::span<const glm::vec3> LeafGeometry::hold(const Mesh& mesh, std::span<const glm::vec3> world,
                                               std::vector<glm::vec3>& made_here) {
    scene_corners.push_back(mesh.triangles);
    if (world.data() == mesh.positions.data() && world.size() == mesh.positions.size()) {
        scene_positions.push_back(mesh.positions);
        return world;
    }
    if (world.data() != made_here.data()) made_here.assign(world.begin(), world.end());
    return made.emplace_back(std::move(made_here));
}

std::size_t LeafGeometry::bytes() const {
    std::size_t total = held_bytes(meshes) + held_bytes(scene_positions) + held_bytes(scene_corners) +
                        held_bytes(made);
    for (const std::vector<glm::vec3>& m : made) total += held_bytes(m);
    return total;
}

void ObjectTree::read_triangles_from_blocks(const bvh::TriangleSource& source) {
    std::vector<bvh::Triangle>().swap(triangles);
    in_blocks = {};
    if (tree.wide.compact) return;
    in_blocks = bvh::BlockTriangles::index(tree, source);
    if (!in_blocks.indexed()) {
        triangles.resize(source.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t t = range.begin(); t < range.end(); ++t) triangles[t] = source[t];
                          });
    }
    // Full blocks, or none (compact leaves were asked for a tree without the wide one): what
    // compact leaves would have read is no longer needed, once `source` (which may view it)
    // has been read.
    leaf_geometry = {};
}

bvh::TriangleSource ObjectTree::moving_source(const Mesh& mesh, std::span<const glm::vec3> positions) {
    if (reads_as_soup(mesh, positions)) return bvh::TriangleSource::soup(positions.first(3 * mesh.triangles.size()));
    leaf_geometry.scene_corners.assign(1, mesh.triangles);
    leaf_geometry.meshes.assign(1, bvh::TriangleSource::IndexedMesh{positions, mesh.triangles});
    return bvh::TriangleSource(std::span<const bvh::TriangleSource::IndexedMesh>(leaf_geometry.meshes));
}

void ObjectTree::view_moving_positions(const Mesh& mesh, std::span<const glm::vec3> positions) {
    tree.wide.source = moving_source(mesh, positions);
}

bool ObjectTree::reads_as_soup(const Mesh& mesh, std::span<const glm::vec3> positions) {
    if (!soup_checked.shares_storage_with(mesh.triangles)) {
        soup_checked = mesh.triangles;
        soup_checked_is_soup = bvh::TriangleSource::is_soup(mesh.triangles);
    }
    return soup_checked_is_soup && positions.size() >= 3 * mesh.triangles.size();
}

void ObjectTree::prefetch_triangle(std::uint32_t prim) const {
    if (tree.wide.compact) {
        tree.wide.source.prefetch(prim);
        return;
    }
    if (in_blocks.indexed()) {
        in_blocks.prefetch(tree, prim);
        return;
    }
    const char* t = reinterpret_cast<const char*>(&triangles[prim]);
    bvh::prefetch_line(t);
    bvh::prefetch_line(t + sizeof(bvh::Triangle) - 1);
}

std::size_t ObjectTree::triangle_bytes() const {
    return triangles.capacity() * sizeof(bvh::Triangle) + in_blocks.bytes() + leaf_geometry.bytes();
}

void measure_tree(ObjectTree& object, const bvh::SahCosts& costs) {
    if (object.measured) return;
    object.built_sah = object.sah = bvh::sah_cost(object.tree, costs);
    object.shape = bvh::compute_stats(object.tree);
    object.measured = true;
    // How much poorer the Morton tree is than the binned-SAH tree, for the cost model:
    // measured against this object's last binned-SAH tree.
    if (object.built_with == bvh::BuildMethod::binned_sah) {
        object.costs.sah_tree_sah = object.built_sah;
    } else if (object.costs.sah_tree_sah > 0.0) {
        object.costs.fast_quality = object.built_sah / object.costs.sah_tree_sah;
    }
}

void update_tree(ObjectTree& object, const ObjectUpdate& update, const UpdatePolicy& policy,
                 CostMemory& memory, UpdateStats& stats) {
    switch (update.planned.action) {
        case TreeAction::build_in_static_group:  // built with the group, once for all
            break;
        case TreeAction::keep:
        case TreeAction::move_instance:
            ++stats.objects_skipped;
            break;
        case TreeAction::rebuild:
            TreeUpdate(object, update, policy, memory, stats).rebuild();
            break;
        case TreeAction::refit:
            TreeUpdate(object, update, policy, memory, stats).refit();
            break;
    }
}

}  // namespace dynrt
