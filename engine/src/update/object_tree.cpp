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

/// One object's update in progress: its tree, what it was asked, and where its figures go.
class TreeUpdate {
public:
    TreeUpdate(ObjectTree& object, const ObjectUpdate& update, const UpdatePolicy& policy,
               CostMemory& memory, UpdateStats& stats)
        : object_(object), update_(update), policy_(policy), memory_(memory), stats_(stats),
          config_(update.config) {}

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
    /// Rebuilds the tree for `reason` (after any choice: the builder is part of the record).
    void build(RebuildReason reason, double refitted_sah = 0.0) {
        stats_.rebuilds.push_back(TreeRebuild{update_.index, update_.name, reason, refitted_sah,
                                              object_.built_sah, bvh::build_method_name(config_.method)});
        ++stats_.objects_rebuilt;
        stats_.triangles_rebuilt += update_.mesh.triangles.size();
        // The tree does not match the triangles just stored until the build completes: should
        // it throw, the next update must rebuild, not refit.
        object_.built = false;
        build_tree(object_, object_.triangles, config_, memory_);
        stats_.rebuild_ms += clock_.lap_ms();
    }
    /// Gathers the triangles from the positions (timed as update_ms, evaluating the scene);
    /// returns whether any changed.
    bool gather() {
        clock_.lap_ms();
        const bool moved = assemble(update_.mesh, update_.positions, object_.triangles);
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
    Stopwatch clock_;
};

void TreeUpdate::rebuild() {
    // Only an exploding object's rebuild replaces a tree that matches its class; every other
    // rebuild has none to keep.
    const bool had_tree = update_.planned.reason == RebuildReason::exploding;
    const bool moved = gather();
    if (had_tree && !moved) {
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
    if (!gather()) {
        ++stats_.objects_skipped;
        return;
    }
    const std::size_t triangles = update_.mesh.triangles.size();
    if (policy_.method == UpdateMethod::automatic) {
        if (const std::optional<RebuildChoice> skip =
                rebuild_instead_of_refit(object_.costs, triangles, memory_.rates(), update_.trace)) {
            choose(*skip, explain_skipped_refit(object_.costs, *skip));
            build(RebuildReason::refits_cost_more, object_.sah);
            return;
        }
    }
    object_.built = false;  // until the refit completes (see build)
    const bvh::RefitResult refit = bvh::refit(object_.tree, object_.triangles, policy_.build.sah_costs());
    object_.built = !refit.needs_rebuild();
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
