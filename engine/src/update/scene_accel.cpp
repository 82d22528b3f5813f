#include "scene_accel.h"

#include "dynrt/bvh/refit.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/scene/vertex_normals.h"
#include "update/held_bytes.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <atomic>
#include <optional>
#include <span>

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

/// out[t] = the mesh's triangle t over `positions`, in parallel; returns their bounding box.
/// Precondition: out.size() == mesh.triangles.size().
bvh::Aabb gather(const Mesh& mesh, std::span<const glm::vec3> positions, std::span<bvh::Triangle> out) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, out.size(), 4096), bvh::Aabb{},
        [&](const tbb::blocked_range<std::size_t>& range, bvh::Aabb box) {
            for (std::size_t t = range.begin(); t < range.end(); ++t) {
                const glm::uvec3& i = mesh.triangles[t];
                out[t] = bvh::Triangle{positions[i.x], positions[i.y], positions[i.z]};
                box.extend(out[t].v0);
                box.extend(out[t].v1);
                box.extend(out[t].v2);
            }
            return box;
        },
        [](bvh::Aabb a, const bvh::Aabb& b) {
            a.extend(b);
            return a;
        });
}

void count_class(anim::MotionClass motion_class, std::size_t triangles, UpdateStats& stats) {
    switch (motion_class) {
        case anim::MotionClass::static_:
            ++stats.static_objects;
            stats.static_triangles += triangles;
            break;
        case anim::MotionClass::rigid:
            ++stats.rigid_objects;
            stats.rigid_triangles += triangles;
            break;
        case anim::MotionClass::deformable:
            ++stats.deformable_objects;
            stats.deformable_triangles += triangles;
            break;
        case anim::MotionClass::exploding:
            ++stats.exploding_objects;
            stats.exploding_triangles += triangles;
            break;
    }
}

glm::vec3 transform_point(const glm::mat4& m, const glm::vec3& p) {
    return glm::vec3(m * glm::vec4(p, 1.0f));
}

}  // namespace

void SceneAccel::clear() {
    objects_.clear();
    static_group_ = ObjectTree{};
    static_group_known_ = false;
    static_first_.clear();
    static_objects_.clear();
    static_slot_of_.clear();
    top_ = bvh::TwoLevelBvh{};
    object_boxes_.clear();
}

void SceneAccel::build(ObjectTree& object, const bvh::BuildConfig& config) {
    const Stopwatch clock;
    object.tree = bvh::build_triangle_bvh(object.triangles, config, std::move(object.tree));
    const double ms = clock.elapsed_ms();
    // Its SAH cost and shape are measured after the timed work (see update).
    object.measured = false;
    object.built = true;
    object.built_with = config.method;
    object.costs.penalty_ms = 0.0;
    object.costs.last_extra_ms = -1.0;
    // Small trees say little about the rate: their time is mostly fixed costs.
    const double per_triangle_ns =
        object.triangles.size() >= 10000 ? ms * 1e6 / double(object.triangles.size()) : -1.0;
    if (config.method == bvh::BuildMethod::morton) {
        object.costs.fast_ms = ms;
        if (per_triangle_ns > 0.0) rates_.fast_ns = per_triangle_ns;
    } else {
        object.costs.sah_ms = ms;
        if (per_triangle_ns > 0.0) rates_.sah_ns = per_triangle_ns;
    }
}

TraceCost SceneAccel::trace_cost_of(std::size_t i) const {
    TraceCost cost;
    cost.trace_ms = last_trace_ms_;
    if (i >= objects_.size() || i >= object_boxes_.size()) return cost;
    const ObjectTree& object = objects_[i];
    const bvh::Aabb& box = object_boxes_[i];
    if (!object.measured || last_scene_sah_ <= 0.0 || last_root_area_ <= 0.0 || box.is_empty()) {
        return cost;
    }
    cost.share = std::min(1.0, double(box.half_area()) / last_root_area_ * object.sah /
                                   last_scene_sah_);
    if (object.built_sah > 0.0) cost.degradation = std::max(1.0, object.sah / object.built_sah);
    return cost;
}

void SceneAccel::invalidate(std::size_t object) {
    if (object >= objects_.size()) return;  // not built yet: the next update builds it anyway
    ObjectTree& tree = objects_[object];
    tree.built = false;
    if (tree.known && tree.motion_class == anim::MotionClass::static_) static_group_.built = false;
}

void SceneAccel::release(std::size_t object) {
    if (object >= objects_.size()) return;
    const ObjectTree& old = objects_[object];
    ObjectTree emptied;
    emptied.known = old.known;
    emptied.motion_class = old.motion_class;
    emptied.built = old.built;
    emptied.measured = old.measured;
    // Its corners and normals were borrowed from the removed mesh, which goes away now.
    objects_[object] = std::move(emptied);
}

void SceneAccel::renew(std::size_t object) {
    if (object >= objects_.size()) return;  // new to the planner anyway
    // A static one leaves the group's list at the group's next build; until then it holds no
    // triangles there (it was released), so no hit resolves to it.
    objects_[object] = ObjectTree{};
}

namespace {

std::size_t tree_bytes(const bvh::TriangleBvh& tree) {
    // The Morton builder's scratch (TriangleBvh::morton_scratch) is private to bvh/ and left
    // out: the library API's updates build with binned SAH only.
    return held_bytes(tree.bvh.nodes) + held_bytes(tree.bvh.prim_ids) + held_bytes(tree.wide.nodes) +
           held_bytes(tree.wide.blocks) + held_bytes(tree.tris) + held_bytes(tree.skipped_ids);
}

}  // namespace

std::size_t SceneAccel::memory_bytes() const {
    const auto object_bytes = [](const ObjectTree& o) {
        return held_bytes(o.triangles) + tree_bytes(o.tree) + held_bytes(o.own_normals);
    };
    std::size_t bytes = held_bytes(objects_) + object_bytes(static_group_);
    for (const ObjectTree& o : objects_) bytes += object_bytes(o);
    bytes += held_bytes(static_first_) + held_bytes(static_objects_) + held_bytes(static_slot_of_);
    bytes += held_bytes(instance_trees_) + held_bytes(top_.instances) + held_bytes(top_.world_boxes) +
             held_bytes(top_.top.nodes) + held_bytes(top_.top.prim_ids);
    bytes += held_bytes(object_boxes_) + held_bytes(positions_) + held_bytes(history_) +
             held_bytes(plan_.objects);
    return bytes;
}

void SceneAccel::update(const Scene& scene, std::span<const ObjectState> states,
                        const FixedPositions& fixed, const UpdatePolicy& policy,
                        UpdateStats& stats, TreeShape& shape) {
    const std::size_t count = scene.objects.size();
    // Objects removed: start afresh. Objects added at the end: new to the planner.
    if (objects_.size() > count) clear();
    history_.resize(objects_.size());
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        const ObjectTree& object = objects_[i];
        history_[i] = TreeHistory{object.known, object.motion_class, object.built};
    }
    plan_update(history_, StaticGroupHistory{static_group_known_, static_group_.built}, states,
                policy.method, plan_);
    const UpdatePlan& plan = plan_;
    objects_.resize(count);
    object_boxes_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        objects_[i].motion_class = states[i].motion_class;
        objects_[i].known = true;
    }

    bvh::BuildConfig exploding_build = policy.build;
    exploding_build.cost_ratio = policy.exploding_cost_ratio;
    const bvh::SahCosts costs = policy.build.sah_costs();

    Stopwatch clock;
    if (plan.rebuild_static_group) {
        build_static_group(scene, states, fixed, policy.build, plan.static_group_reason, stats);
    }
    for (std::size_t i = 0; i < count; ++i) {
        ObjectTree& object = objects_[i];
        const ObjectState& pose = states[i];
        const ObjectPlan& planned = plan.objects[i];
        const Mesh& mesh = scene.objects[i].mesh;
        count_class(pose.motion_class, mesh.triangles.size(), stats);
        const bool exploding = pose.motion_class == anim::MotionClass::exploding;
        bvh::BuildConfig config = exploding ? exploding_build : policy.build;
        // Builds are binned SAH unless the method says otherwise: the fast method always uses
        // the Morton builder, the automatic one where it predicts a lower cost (below).
        if (policy.method == UpdateMethod::fast) config.method = bvh::BuildMethod::morton;
        const auto choose = [&](const RebuildChoice& choice, const std::string& why) {
            config.method = choice.method;
            stats.choices.push_back(TreeChoice{
                i, scene.objects[i].name,
                choice.method == bvh::BuildMethod::morton ? "rebuild (fast)" : "rebuild (sah)",
                why});
        };
        // After any choice: the builder is part of the record.
        const auto record = [&](RebuildReason reason, double refitted_sah = 0.0) {
            stats.rebuilds.push_back(TreeRebuild{i, scene.objects[i].name, reason, refitted_sah,
                                                 object.built_sah,
                                                 bvh::build_method_name(config.method)});
            ++stats.objects_rebuilt;
            stats.triangles_rebuilt += mesh.triangles.size();
        };
        if (pose.motion_class == anim::MotionClass::rigid) {
            // Written whatever the action: the transform is composed in double, its inverse
            // too, so the ray transform is as exact as float storage allows.
            object.object_to_world = glm::mat4(pose.transform);
            object.world_to_object = glm::mat4(glm::inverse(pose.transform));
        }

        switch (planned.action) {
            case TreeAction::build_in_static_group:  // built above, once for all
                break;
            case TreeAction::keep:
            case TreeAction::move_instance:
                ++stats.objects_skipped;
                break;
            case TreeAction::rebuild: {
                // Only an exploding object's rebuild replaces a tree that matches its class;
                // every other rebuild has none to keep.
                const bool had_tree = planned.reason == RebuildReason::exploding;
                clock.lap_ms();
                const bool moved =
                    assemble(mesh, pose.motion_class == anim::MotionClass::rigid
                                       ? fixed.object_space(i)
                                       : pose.world_positions,
                             object.triangles);
                stats.update_ms += clock.lap_ms();
                if (had_tree && !moved) {
                    // The animation said it changed; its vertices say otherwise.
                    ++stats.objects_skipped;
                    break;
                }
                if (policy.method == UpdateMethod::automatic && had_tree) {
                    const RebuildChoice choice = choose_rebuild(
                        object.costs, mesh.triangles.size(), rates_, trace_cost_of(i));
                    choose(choice, explain_rebuild(choice));
                }
                record(planned.reason);
                // The tree does not match the triangles just stored until the build
                // completes: should it throw, the next update must rebuild, not refit.
                object.built = false;
                build(object, config);
                stats.rebuild_ms += clock.lap_ms();
                break;
            }
            case TreeAction::refit: {
                clock.lap_ms();
                const bool moved = assemble(mesh, pose.world_positions, object.triangles);
                stats.update_ms += clock.lap_ms();
                if (!moved) {
                    ++stats.objects_skipped;
                    break;
                }
                if (policy.method == UpdateMethod::automatic) {
                    if (const std::optional<RebuildChoice> skip = rebuild_instead_of_refit(
                            object.costs, mesh.triangles.size(), rates_, trace_cost_of(i))) {
                        choose(*skip, explain_skipped_refit(object.costs, *skip));
                        record(RebuildReason::refits_cost_more, object.sah);
                        object.built = false;
                        build(object, config);
                        stats.rebuild_ms += clock.lap_ms();
                        break;
                    }
                }
                object.built = false;  // until the refit completes (see above)
                const bvh::RefitResult refit = bvh::refit(object.tree, object.triangles, costs);
                object.built = !refit.needs_rebuild();
                const double refit_ms = clock.lap_ms();
                stats.refit_ms += refit_ms;
                object.costs.refit_ms = refit_ms;
                ++stats.objects_refitted;
                stats.triangles_refitted += mesh.triangles.size();
                std::optional<RebuildReason> rebuild;
                if (refit.needs_rebuild()) {
                    rebuild = RebuildReason::degenerate_gained_area;
                } else if (policy.method == UpdateMethod::threshold) {
                    rebuild = judge_refit(refit, object.built_sah, policy);
                } else if (policy.method == UpdateMethod::automatic) {
                    const RefitJudgement judgement =
                        judge_refit_cost(refit.sah_cost, object.built_sah, object.costs,
                                         mesh.triangles.size(), rates_, trace_cost_of(i));
                    if (judgement.rebuild) {
                        rebuild = RebuildReason::refits_cost_more;
                        choose(judgement.choice, explain_refit(judgement));
                    } else {
                        object.costs.penalty_ms = judgement.penalty_ms;
                        object.costs.last_extra_ms = judgement.extra_ms;
                        stats.choices.push_back(
                            TreeChoice{i, scene.objects[i].name, "refit", explain_refit(judgement)});
                    }
                }
                if (rebuild) {
                    const bool degraded = *rebuild == RebuildReason::sah_degraded ||
                                          *rebuild == RebuildReason::refits_cost_more;
                    record(*rebuild, degraded ? refit.sah_cost : 0.0);
                    build(object, config);
                    stats.rebuild_ms += clock.lap_ms();
                } else {
                    object.sah = refit.sah_cost;
                }
                break;
            }
        }
    }

    // ---- Vertex normals, for shading: borrowed spans, refreshed every update ----
    for (std::size_t i = 0; i < count; ++i) {
        ObjectTree& object = objects_[i];
        object.corners = scene.objects[i].mesh.triangles;
        switch (states[i].motion_class) {
            case anim::MotionClass::static_:
                object.normals = object.own_normals;  // taken when the static group was built
                break;
            case anim::MotionClass::rigid:
                object.normals = fixed.object_space_normals(i);
                object.normal_to_world = glm::mat3(normal_matrix(glm::dmat3(states[i].transform)));
                break;
            default:
                object.normals = states[i].world_normals;
                break;
        }
    }

    // ---- Top level: the static group and one instance per other object, every frame ----
    clock.lap_ms();
    std::vector<bvh::Instance> instances;
    instance_trees_.clear();
    if (!static_objects_.empty()) {
        bvh::Instance group;
        group.blas = &static_group_.tree;
        group.object = static_group_id();
        instances.push_back(group);
        instance_trees_.push_back(&static_group_);
    }
    for (std::size_t i = 0; i < count; ++i) {
        ObjectTree& object = objects_[i];
        if (object.motion_class == anim::MotionClass::static_) continue;
        bvh::Instance instance;
        instance.blas = &object.tree;
        instance.identity = object.motion_class != anim::MotionClass::rigid;
        instance.object_to_world = object.object_to_world;
        instance.world_to_object = object.world_to_object;
        instance.object = std::uint32_t(i);
        instances.push_back(instance);
        instance_trees_.push_back(&object);
    }
    bvh::build_top_level(top_, std::move(instances));
    stats.top_level_ms = clock.lap_ms();
    for (std::size_t k = 0; k < top_.instances.size(); ++k) {
        const std::uint32_t id = top_.instances[k].object;
        if (id != static_group_id()) object_boxes_[id] = top_.world_boxes[k];
    }
    stats.build_ms = stats.refit_ms + stats.rebuild_ms + stats.top_level_ms;

    // ---- Shape of the whole structure ----
    // Trees built this frame are measured here, outside the build's timer but inside the
    // frame's (update_ms): their SAH cost is what later refits are compared with and what the
    // automatic update method predicts trace times from; their shape is only reported. The
    // walks are parallel (bvh.cpp), a few ms for a million triangles.
    for (ObjectTree* tree : instance_trees_) {
        ObjectTree& object = *tree;
        if (object.measured) continue;
        object.built_sah = object.sah = bvh::sah_cost(object.tree.bvh, costs);
        object.shape = bvh::compute_stats(object.tree.bvh);
        object.measured = true;
        // How much poorer the Morton tree is than the binned-SAH tree, for the cost model:
        // measured against this object's last binned-SAH tree.
        if (object.built_with == bvh::BuildMethod::binned_sah) {
            object.costs.sah_tree_sah = object.built_sah;
        } else if (object.costs.sah_tree_sah > 0.0) {
            object.costs.fast_quality = object.built_sah / object.costs.sah_tree_sah;
        }
    }
    // SAH cost of the two levels as one tree: the top level's inner nodes, then each object's
    // own cost (relative to its root) weighted by the chance of reaching its world box.
    const bvh::Aabb bounds = world_bounds();
    const double root_area = bounds.is_empty() ? 0.0 : double(bounds.half_area());
    double sah = bvh::sah_cost(top_.top, bvh::SahCosts{1.0f, 0.0f});
    std::size_t triangles = 0, nodes = top_.top.nodes.size(), leaves = 0;
    std::uint32_t leaf_max = 0, depth = 0;
    for (std::size_t k = 0; k < instance_trees_.size(); ++k) {
        const ObjectTree& object = *instance_trees_[k];
        triangles += object.triangles.size();
        shape.degenerate_skipped += object.tree.degenerate_skipped;
        const bvh::Aabb& box = top_.world_boxes[k];
        if (root_area > 0.0 && !box.is_empty()) sah += double(box.half_area()) / root_area * object.sah;
        nodes += object.shape.nodes;
        leaves += object.shape.leaves;
        shape.binary_tree_bytes += object.tree.bvh.nodes.size() * sizeof(bvh::BvhNode) +
                                   object.tree.bvh.prim_ids.size() * sizeof(std::uint32_t) +
                                   object.tree.tris.size() * sizeof(bvh::Triangle);
        shape.wide_tree_bytes += object.tree.wide.bytes();
        leaf_max = std::max(leaf_max, object.shape.leaf_prims_max);
        depth = std::max(depth, object.shape.depth);
    }
    last_scene_sah_ = sah;
    last_root_area_ = root_area;
    const bvh::BvhStats top_shape = bvh::compute_stats(top_.top);
    shape.triangles = triangles;
    shape.sah_cost = sah;
    shape.nodes = nodes;
    shape.leaves = leaves;
    shape.leaf_tris_mean =
        leaves > 0 ? double(triangles - shape.degenerate_skipped) / double(leaves) : 0.0;
    shape.leaf_tris_max = leaf_max;
    // Top-level depth (its leaves are the objects) plus the deepest object tree: an upper bound
    // on the longest path, exact for one object.
    shape.depth = depth + (top_shape.depth > 0 ? top_shape.depth - 1 : 0);
}

void SceneAccel::build_static_group(const Scene& scene, std::span<const ObjectState> states,
                                    const FixedPositions& fixed, const bvh::BuildConfig& config,
                                    RebuildReason reason, UpdateStats& stats) {
    // Static objects never move, so one tree over all of them in world space serves them
    // best: it splits across objects (per-object trees overlap, and rays pay for every
    // overlapping one) and costs the top level a single instance. A scene of static objects
    // thus traces exactly the one tree of their concatenated triangles.
    static_objects_.clear();
    static_first_.clear();
    static_slot_of_.clear();
    std::size_t total = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        if (states[i].motion_class == anim::MotionClass::static_) total += scene.objects[i].mesh.triangles.size();
    }
    // Gathered straight into the group's storage (kept from build to build), boxes on the way.
    std::vector<bvh::Triangle>& all = static_group_.triangles;
    all.resize(total);
    static_slot_of_.resize(total);
    Stopwatch clock;
    static_group_known_ = true;
    std::size_t first = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        if (states[i].motion_class != anim::MotionClass::static_) continue;
        const Mesh& mesh = scene.objects[i].mesh;
        const std::span<bvh::Triangle> out(all.data() + first, mesh.triangles.size());
        object_boxes_[i] = gather(mesh, fixed.world(i, positions_), out);
        const std::span<const glm::vec3> normals = fixed.world_normals(i, positions_);
        objects_[i].own_normals.assign(normals.begin(), normals.end());
        static_objects_.push_back(std::uint32_t(i));
        static_first_.push_back(std::uint32_t(first));
        std::fill(static_slot_of_.begin() + std::ptrdiff_t(first),
                  static_slot_of_.begin() + std::ptrdiff_t(first + out.size()),
                  std::uint32_t(static_objects_.size() - 1));
        objects_[i].group_first = std::uint32_t(first);
        first += out.size();
        stats.rebuilds.push_back(TreeRebuild{i, scene.objects[i].name, reason, 0.0, 0.0});
        ++stats.objects_rebuilt;
        stats.triangles_rebuilt += mesh.triangles.size();
    }
    stats.update_ms += clock.lap_ms();
    static_group_.motion_class = anim::MotionClass::static_;
    build(static_group_, config);
    stats.rebuild_ms += clock.lap_ms();
}

const bvh::Triangle* SceneAccel::triangle_address(std::size_t object, std::uint32_t prim) const {
    const ObjectTree& o = objects_[object];
    if (o.motion_class == anim::MotionClass::static_) {
        return &static_group_.triangles[o.group_first + prim];
    }
    return &o.triangles[prim];
}

bvh::Triangle SceneAccel::world_triangle(std::size_t object, std::uint32_t prim) const {
    const ObjectTree& o = objects_[object];
    const bvh::Triangle& t = *triangle_address(object, prim);
    if (o.motion_class != anim::MotionClass::rigid) return t;
    return bvh::Triangle{transform_point(o.object_to_world, t.v0),
                         transform_point(o.object_to_world, t.v1),
                         transform_point(o.object_to_world, t.v2)};
}

bool SceneAccel::world_vertex_normals(std::size_t object, std::uint32_t prim, glm::vec3 (&out)[3]) const {
    const ObjectTree& o = objects_[object];
    if (!vertex_normals_ || o.normals.empty()) return false;
    const glm::uvec3& corner = o.corners[prim];
    out[0] = o.normals[corner.x];
    out[1] = o.normals[corner.y];
    out[2] = o.normals[corner.z];
    if (o.motion_class == anim::MotionClass::rigid) {
        for (glm::vec3& n : out) n = normalize_or_zero(o.normal_to_world * n);
    }
    return true;
}

void SceneAccel::object_world_parts(std::size_t i, std::size_t max_parts,
                                    std::vector<bvh::Aabb>& out) const {
    if (i >= object_boxes_.size() || object_boxes_[i].is_empty()) return;
    const bool own_tree = i < objects_.size() && objects_[i].built &&
                          objects_[i].motion_class != anim::MotionClass::static_ &&
                          !objects_[i].tree.bvh.empty();
    if (!own_tree || max_parts <= 1) {
        out.push_back(object_boxes_[i]);
        return;
    }
    const ObjectTree& o = objects_[i];
    const std::vector<bvh::BvhNode>& nodes = o.tree.bvh.nodes;
    // Best first: split the inner node of largest surface area until the cut has max_parts
    // nodes or only leaves. The cut is small (max_parts), so a linear search picks the node.
    std::vector<std::uint32_t> cut{0};
    while (cut.size() < max_parts) {
        std::size_t best = cut.size();
        float best_area = -1.0f;
        for (std::size_t k = 0; k < cut.size(); ++k) {
            const bvh::BvhNode& node = nodes[cut[k]];
            if (node.is_leaf()) continue;
            const float area = node.box.half_area();
            if (area > best_area) {
                best_area = area;
                best = k;
            }
        }
        if (best == cut.size()) break;
        const std::uint32_t left = nodes[cut[best]].first;
        cut[best] = left;
        cut.push_back(left + 1);
    }
    const bool rigid = o.motion_class == anim::MotionClass::rigid;
    for (const std::uint32_t n : cut) {
        const bvh::Aabb& box = nodes[n].box;
        if (box.is_empty()) continue;
        if (!rigid) {
            out.push_back(box);
            continue;
        }
        bvh::Aabb world;
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 corner((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                                   (c & 4) ? box.hi.z : box.lo.z);
            world.extend(transform_point(o.object_to_world, corner));
        }
        out.push_back(world);
    }
}

bvh::Aabb SceneAccel::world_bounds() const {
    bvh::Aabb bounds;
    for (const bvh::Aabb& box : top_.world_boxes) {
        if (!box.is_empty()) bounds.extend(box);
    }
    return bounds;
}

}  // namespace dynrt
