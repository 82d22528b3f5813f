#include "update/scene_accel.h"

#include "dynrt/engine/stopwatch.h"
#include "dynrt/engine/resident_memory.h"
#include "dynrt/scene/scene_bytes.h"
#include "update/held_bytes.h"
#include "update/static_group_layout.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <span>

namespace dynrt {

namespace {

/// The bounding box of the mesh's triangles over `positions`, in parallel (the vertices no
/// triangle uses are left out).
bvh::Aabb triangles_box(const Mesh& mesh, std::span<const glm::vec3> positions) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096), bvh::Aabb{},
        [&](const tbb::blocked_range<std::size_t>& range, bvh::Aabb box) {
            for (std::size_t t = range.begin(); t < range.end(); ++t) {
                const glm::uvec3& i = mesh.triangles[t];
                box.extend(positions[i.x]);
                box.extend(positions[i.y]);
                box.extend(positions[i.z]);
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
    static_bucket_slot_.clear();
    top_ = bvh::TwoLevelBvh{};
    object_boxes_.clear();
    shading_.clear();
    rigid_trees_.clear();
    top_current_ = false;
}

void SceneAccel::forget_sharers_of(std::size_t owner) {
    for (ObjectTree& object : objects_) {
        if (object.shares_tree_of != std::int64_t(owner)) continue;
        object.shares_tree_of = -1;
        object.built = false;
    }
}

void SceneAccel::invalidate(std::size_t object) {
    if (object >= objects_.size()) return;  // not built yet: the next update builds it anyway
    ObjectTree& tree = objects_[object];
    tree.built = false;
    top_current_ = false;
    forget_sharers_of(object);
    if (tree.known && tree.motion_class == anim::MotionClass::static_) static_group_.built = false;
}

void SceneAccel::release(std::size_t object) {
    if (object >= objects_.size()) return;
    forget_sharers_of(object);
    top_current_ = false;
    const ObjectTree& old = objects_[object];
    ObjectTree emptied;
    emptied.known = old.known;
    emptied.motion_class = old.motion_class;
    emptied.built = old.built;
    emptied.measured = old.measured;
    objects_[object] = std::move(emptied);
    // Its corners and normals were borrowed from the removed mesh, which goes away now.
    shading_.forget(object);
}

void SceneAccel::renew(std::size_t object) {
    if (object >= objects_.size()) return;  // new to the planner anyway
    // A static one leaves the group's list at the group's next build; until then it holds no
    // triangles there (it was released), so no hit resolves to it.
    forget_sharers_of(object);
    top_current_ = false;
    objects_[object] = ObjectTree{};
    shading_.forget(object);
}

namespace {

std::size_t tree_bytes(const bvh::TriangleBvh& tree) {
    // The Morton builder's scratch (TriangleBvh::morton_scratch) is private to bvh/ and left
    // out: the library API's updates build with binned SAH only.
    return held_bytes(tree.bvh.nodes) + held_bytes(tree.bvh.prim_ids) + held_bytes(tree.wide.nodes) +
           held_bytes(tree.wide.quantized_nodes) + held_bytes(tree.wide.blocks) +
           held_bytes(tree.wide.prim_blocks) + tree.wide.source.bytes() + held_bytes(tree.tris) +
           held_bytes(tree.skipped_ids);
}

}  // namespace

void SceneAccel::memory_figures(MemoryStats& out) const {
    out.tree_bytes = tree_bytes(static_group_.tree) + held_bytes(top_.instances) + held_bytes(top_.world_boxes) +
                     held_bytes(top_.top.nodes) + held_bytes(top_.top.prim_ids);
    out.build_triangle_bytes = static_group_.triangle_bytes();
    for (const ObjectTree& o : objects_) {
        out.tree_bytes += tree_bytes(o.tree);
        out.build_triangle_bytes += o.triangle_bytes();
    }
}

std::vector<ObjectMemory> SceneAccel::memory_by_object() const {
    std::vector<ObjectMemory> out;
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        const ObjectTree& o = objects_[i];
        if (o.motion_class == anim::MotionClass::static_ || o.tree.empty()) continue;
        ObjectMemory m;
        m.object = std::int64_t(i);
        m.triangles = o.triangle_count();
        m.tree_bytes = tree_bytes(o.tree);
        m.build_triangle_bytes = o.triangle_bytes();
        out.push_back(std::move(m));
    }
    if (!static_group_.tree.empty()) {
        ObjectMemory m;
        m.triangles = static_group_.triangle_count();
        m.tree_bytes = tree_bytes(static_group_.tree);
        m.build_triangle_bytes = static_group_.triangle_bytes();
        out.push_back(std::move(m));
    }
    return out;
}

std::size_t SceneAccel::memory_bytes() const {
    MemoryStats parts;
    memory_figures(parts);
    std::size_t bytes = held_bytes(objects_) + parts.tree_bytes + parts.build_triangle_bytes;
    bytes += held_bytes(static_first_) + held_bytes(static_objects_) + held_bytes(static_bucket_slot_);
    bytes += held_bytes(instance_trees_) + held_bytes(instancing_states_);
    bytes += rigid_trees_.size() * (sizeof(SourceKey) + sizeof(std::size_t) + 2 * sizeof(void*));
    bytes += held_bytes(object_boxes_) + held_bytes(history_) +
             held_bytes(plan_.objects) + shading_.memory_bytes();
    return bytes;
}

/// One update's inputs, as every object's step reads them.
struct SceneAccel::Update {
    const Scene& scene;
    /// The states the trees follow (instancing_states), and the classes the objects have.
    std::span<const ObjectState> states;
    std::span<const ObjectState> declared;
    const FixedPositions& fixed;
    const UpdatePolicy& policy;
    /// The build settings of exploding objects (their own cost ratio).
    bvh::BuildConfig exploding_build;
};

void SceneAccel::update(const Scene& scene, std::span<const ObjectState> states,
                        const FixedPositions& fixed, const UpdatePolicy& policy,
                        UpdateStats& stats, TreeShape& shape) {
    const std::size_t count = scene.objects.size();
    // Objects removed: start afresh. Objects added at the end: new to the planner.
    if (objects_.size() > count) clear();
    const std::span<const ObjectState> declared = states;
    states = instancing_states(scene, declared, policy);
    history_.resize(objects_.size());
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        ObjectTree& object = objects_[i];
        // A copy carries another object's tree only while both stay rigid and that tree is
        // still the one built from their shared arrays.
        if (object.shares_tree_of >= 0) {
            const auto owner = std::size_t(object.shares_tree_of);
            const bool carried = owner < objects_.size() && objects_[owner].built &&
                                 objects_[owner].shares_tree_of < 0 &&
                                 states[owner].motion_class == anim::MotionClass::rigid &&
                                 states[i].motion_class == anim::MotionClass::rigid;
            if (!carried) {
                object.shares_tree_of = -1;
                object.built = false;
            }
        }
        history_[i] = TreeHistory{object.known, object.motion_class, object.built};
    }
    plan_update(history_, StaticGroupHistory{static_group_known_, static_group_.built}, states,
                policy.method, plan_);
    objects_.resize(count);
    object_boxes_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        objects_[i].motion_class = states[i].motion_class;
        objects_[i].known = true;
    }

    Update run{scene, states, declared, fixed, policy, policy.build};
    run.exploding_build.cost_ratio = policy.exploding_cost_ratio;
    if (plan_.rebuild_static_group) {
        bvh::BuildConfig config = policy.build;
        config.compact_leaves = policy.compact_static_group;
        config.quantized_nodes = policy.quantized_static_group;
        if (policy.memory_budget != 0) choose_static_layout(scene, states, policy.memory_budget, config, stats);
        build_static_group(scene, states, fixed, config, plan_.static_group_reason, stats);
    }
    for (std::size_t i = 0; i < count; ++i) update_object(i, run, stats);
    shading_.refresh(scene, states, fixed);
    // A frame in which no tree was touched and nothing moved keeps the top level it has (a
    // still frame of a forest of copies would otherwise rebuild it over every instance).
    const bool still = top_current_ && !plan_.rebuild_static_group &&
                       std::all_of(plan_.objects.begin(), plan_.objects.end(),
                                   [](const ObjectPlan& p) { return p.action == TreeAction::keep; });
    if (!still) build_top(stats);
    stats.build_ms = stats.refit_ms + stats.rebuild_ms + stats.top_level_ms;
    measure(policy.build.sah_costs(), shape);
}

void SceneAccel::update_object(std::size_t i, const Update& run, UpdateStats& stats) {
    ObjectTree& object = objects_[i];
    const ObjectState& pose = run.states[i];
    const ObjectPlan& planned = plan_.objects[i];
    const Mesh& mesh = run.scene.objects[i].mesh;
    count_class(run.declared[i].motion_class, mesh.triangles.size(), stats);
    const bool rigid = pose.motion_class == anim::MotionClass::rigid;
    if (rigid) {
        // Written whatever the action: the transform is composed in double, its inverse
        // too, so the ray transform is as exact as float storage allows.
        object.object_to_world = glm::mat4(pose.transform);
        object.world_to_object = glm::mat4(glm::inverse(pose.transform));
    }
    ObjectUpdate update{i, run.scene.objects[i].name, mesh, {}, planned,
                        pose.motion_class == anim::MotionClass::exploding ? run.exploding_build
                                                                          : run.policy.build,
                        TraceCost{}};
    // Builds are binned SAH unless the method says otherwise: the fast method always uses the
    // Morton builder, the automatic one where it predicts a lower cost (object_tree.cpp).
    if (run.policy.method == UpdateMethod::fast) update.config.method = bvh::BuildMethod::morton;
    // An object's tree may be refitted, which quantised nodes cannot be. Compact leaves read
    // the posed vertices of a deformable or exploding object (a rigid one's keep full blocks).
    const bool moving = pose.motion_class == anim::MotionClass::deformable ||
                        pose.motion_class == anim::MotionClass::exploding;
    update.config.compact_leaves = moving && run.policy.compact_moving_objects;
    update.config.quantized_nodes = false;
    // Built for memory too, as the static group is (lean_leaf_size_min).
    if (update.config.compact_leaves) {
        update.config.leaf_size_min = std::max(update.config.leaf_size_min, lean_leaf_size_min(mesh.triangles.size()));
    }
    // A kept compact tree views this update's vertices (the same values: nothing moved), so
    // that it never outlives the storage it reads.
    if (moving && object.tree.wide.compact && planned.action == TreeAction::keep) {
        object.view_moving_positions(mesh, pose.world_positions);
    }
    if (planned.action == TreeAction::rebuild || planned.action == TreeAction::refit) {
        // Read only when the triangles are (the library API checks a borrowed buffer as it
        // reads it). A rigid object's are in object space; the planner never refits one.
        update.positions = rigid ? run.fixed.object_space(i) : pose.world_positions;
        if (run.policy.method == UpdateMethod::automatic) {
            update.trace = costs_.trace_cost(object_boxes_[i], object.sah, object.built_sah, object.measured);
        }
    }
    const bool rigid_build = rigid && planned.action == TreeAction::rebuild;
    if (rigid_build) {
        // A copy of a mesh whose tree is built already carries that tree: the same arrays
        // give the same tree, bit for bit.
        if (const std::optional<std::size_t> owner = tree_to_share(i, update.positions, mesh)) {
            object.triangles = {};
            object.tree = bvh::TriangleBvh{};
            object.in_blocks = {};
            object.shares_tree_of = std::int64_t(*owner);
            object.built = true;
            object.measured = true;
            ++stats.objects_skipped;
            return;
        }
        object.shares_tree_of = -1;
    }
    update_tree(object, update, run.policy, costs_, stats);
    if (rigid_build && object.built && !update.positions.empty()) {
        object.built_from_positions = update.positions.data();
        object.built_from_corners = mesh.triangles.data();
        rigid_trees_[SourceKey{object.built_from_positions, object.built_from_corners, update.positions.size()}] = i;
    }
}

std::optional<std::size_t> SceneAccel::tree_to_share(std::size_t object, std::span<const glm::vec3> positions,
                                                     const Mesh& mesh) const {
    if (positions.empty()) return std::nullopt;
    const SourceKey key{positions.data(), mesh.triangles.data(), positions.size()};
    const auto found = rigid_trees_.find(key);
    if (found == rigid_trees_.end() || found->second == object || found->second >= objects_.size()) {
        return std::nullopt;
    }
    // The record may be stale (that object since rebuilt from other arrays, or freed).
    const ObjectTree& owner = objects_[found->second];
    const bool same = owner.built && owner.shares_tree_of < 0 &&
                      owner.motion_class == anim::MotionClass::rigid &&
                      owner.built_from_positions == key.positions && owner.built_from_corners == key.corners &&
                      owner.triangle_count() == mesh.triangles.size();
    if (!same) return std::nullopt;
    return found->second;
}

std::span<const ObjectState> SceneAccel::instancing_states(const Scene& scene, std::span<const ObjectState> states,
                                                           const UpdatePolicy& policy) {
    std::size_t static_triangles = 0;
    for (std::size_t i = 0; i < states.size(); ++i) {
        if (states[i].motion_class == anim::MotionClass::static_) static_triangles += scene.objects[i].mesh.triangles.size();
    }
    if (static_triangles <= policy.static_group_limit) return states;
    // Copies: objects whose mesh's positions another static or rigid object holds too.
    std::unordered_map<const glm::vec3*, std::size_t> holders;
    for (std::size_t i = 0; i < states.size(); ++i) {
        const anim::MotionClass c = states[i].motion_class;
        const glm::vec3* positions = scene.objects[i].mesh.positions.data();
        if (positions && (c == anim::MotionClass::static_ || c == anim::MotionClass::rigid)) ++holders[positions];
    }
    instancing_states_.assign(states.begin(), states.end());
    for (std::size_t i = 0; i < states.size(); ++i) {
        const Object& object = scene.objects[i];
        // A skinned or morphed object's object space is a shape of its own, never shared.
        if (states[i].motion_class != anim::MotionClass::static_ || object.skin || object.morph) continue;
        const auto found = holders.find(object.mesh.positions.data());
        if (found != holders.end() && found->second > 1) instancing_states_[i].motion_class = anim::MotionClass::rigid;
    }
    return instancing_states_;
}

void SceneAccel::build_top(UpdateStats& stats) {
    // The static group and one instance per other object, every frame.
    const Stopwatch clock;
    std::vector<bvh::Instance> instances;
    instance_trees_.clear();
    if (!static_objects_.empty()) {
        bvh::Instance group;
        group.blas = &static_group_.tree;
        group.object = static_group_id();
        instances.push_back(group);
        instance_trees_.push_back(&static_group_);
    }
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        ObjectTree& object = objects_[i];
        if (object.motion_class == anim::MotionClass::static_) continue;
        ObjectTree& carried = object.shares_tree_of >= 0 ? objects_[std::size_t(object.shares_tree_of)] : object;
        bvh::Instance instance;
        instance.blas = &carried.tree;
        instance.identity = object.motion_class != anim::MotionClass::rigid;
        instance.object_to_world = object.object_to_world;
        instance.world_to_object = object.world_to_object;
        instance.object = std::uint32_t(i);
        instances.push_back(instance);
        instance_trees_.push_back(&carried);
    }
    bvh::build_top_level(top_, std::move(instances));
    top_current_ = true;
    stats.top_level_ms = clock.elapsed_ms();
    for (std::size_t k = 0; k < top_.instances.size(); ++k) {
        const std::uint32_t id = top_.instances[k].object;
        if (id != static_group_id()) object_boxes_[id] = top_.world_boxes[k];
    }
}

void SceneAccel::measure(const bvh::SahCosts& costs, TreeShape& shape) {
    // Trees built this frame are measured here, outside the build's timer but inside the
    // frame's (update_ms): their SAH cost is what later refits are compared with and what the
    // automatic update method predicts trace times from; their shape is only reported. The
    // walks are parallel (bvh.cpp), a few ms for a million triangles.
    for (ObjectTree* tree : instance_trees_) measure_tree(*tree, costs);
    // SAH cost of the two levels as one tree: the top level's inner nodes, then each object's
    // own cost (relative to its root) weighted by the chance of reaching its world box.
    const bvh::Aabb bounds = world_bounds();
    const double root_area = bounds.is_empty() ? 0.0 : double(bounds.half_area());
    double sah = bvh::sah_cost(top_.top, bvh::SahCosts{1.0f, 0.0f});
    std::size_t triangles = 0, nodes = top_.top.nodes.size(), leaves = 0;
    std::uint32_t leaf_max = 0, depth = 0;
    for (std::size_t k = 0; k < instance_trees_.size(); ++k) {
        const ObjectTree& object = *instance_trees_[k];
        triangles += object.triangle_count();
        shape.degenerate_skipped += object.tree.degenerate_skipped;
        const bvh::Aabb& box = top_.world_boxes[k];
        if (root_area > 0.0 && !box.is_empty()) sah += double(box.half_area()) / root_area * object.sah;
        nodes += object.shape.nodes;
        leaves += object.shape.leaves;
        leaf_max = std::max(leaf_max, object.shape.leaf_prims_max);
        depth = std::max(depth, object.shape.depth);
        // A tree that several instances carry is held once.
        const std::uint32_t id = top_.instances[k].object;
        if (id != static_group_id() && objects_[id].shares_tree_of >= 0) continue;
        shape.binary_tree_bytes += object.tree.bvh.nodes.size() * sizeof(bvh::BvhNode) +
                                   object.tree.bvh.prim_ids.size() * sizeof(std::uint32_t) +
                                   object.tree.tris.size() * sizeof(bvh::Triangle);
        shape.wide_tree_bytes += object.tree.wide.bytes();
    }
    costs_.note_scene(sah, root_area);
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

void SceneAccel::index_static_buckets(std::size_t total) {
    static_bucket_slot_.clear();
    if (static_objects_.empty()) return;
    // Entry b: the object holding the bucket's first triangle (the last one starting at or
    // before it, which skips objects without triangles); the entry past the last bucket
    // bounds resolve()'s search there.
    const std::size_t buckets = (total >> kStaticBucketShift) + 1;
    static_bucket_slot_.resize(buckets + 1);
    std::size_t k = 0;
    for (std::size_t b = 0; b <= buckets; ++b) {
        const std::size_t prim = std::min(b << kStaticBucketShift, total == 0 ? 0 : total - 1);
        while (k + 1 < static_first_.size() && static_first_[k + 1] <= prim) ++k;
        static_bucket_slot_[b] = std::uint32_t(k);
    }
}

void SceneAccel::choose_static_layout(const Scene& scene, std::span<const ObjectState> states,
                                      std::size_t budget, bvh::BuildConfig& config, UpdateStats& stats) {
    std::size_t triangles = 0;
    for (std::size_t i = 0; i < states.size(); ++i) {
        if (states[i].motion_class == anim::MotionClass::static_) triangles += scene.objects[i].mesh.triangles.size();
    }
    // What is resident now (the scene model, the libraries, trees kept from earlier frames);
    // where it cannot be read, the scene model at least.
    std::size_t resident = resident_memory().current;
    if (resident == 0) resident = scene_bytes(scene);
    const StaticLayoutChoice choice = choose_static_group_layout(triangles, resident, budget);
    config.compact_leaves = choice.layout.compact_leaves;
    config.quantized_nodes = choice.layout.quantized_nodes;
    stats.static_layout = choice.layout.name();
    stats.static_layout_why = choice.why;
    stats.static_layout_predicted_peak = choice.predicted_peak;
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
    static_bucket_slot_.clear();
    // The tree is built from the objects' vertices through their index triples, with no
    // gathered copy of the triangles (36 bytes each at the build's peak). Vertices at the
    // identity are the scene's own; those under a transform are made here and held until the
    // build is done (12 bytes a vertex).
    // With compact leaves the group keeps the views, and what they view, for the tree to read.
    static_group_.leaf_geometry = {};
    std::vector<bvh::TriangleSource::IndexedMesh> own_meshes;
    std::vector<bvh::TriangleSource::IndexedMesh>& meshes =
        config.compact_leaves ? static_group_.leaf_geometry.meshes : own_meshes;
    std::vector<std::vector<glm::vec3>> transformed;
    transformed.reserve(scene.objects.size());
    // World normals made under a transform, one object at a time (shading copies them).
    std::vector<glm::vec3> normals_made;
    Stopwatch clock;
    static_group_known_ = true;
    // No index into the old tree survives, should the build below throw.
    static_group_.triangles.clear();
    static_group_.in_blocks = {};
    std::size_t first = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        if (states[i].motion_class != anim::MotionClass::static_) continue;
        const Mesh& mesh = scene.objects[i].mesh;
        std::vector<glm::vec3>& made = transformed.emplace_back();
        std::span<const glm::vec3> world = fixed.world(i, made);
        if (world.data() != made.data()) std::vector<glm::vec3>().swap(made);
        if (config.compact_leaves) world = static_group_.leaf_geometry.hold(mesh, world, made);
        meshes.push_back(bvh::TriangleSource::IndexedMesh{world, mesh.triangles});
        object_boxes_[i] = triangles_box(mesh, world);
        // Borrowed where FixedPositions holds them; copied where it made them in the scratch.
        const std::span<const glm::vec3> normals = fixed.world_normals(i, normals_made);
        shading_.keep_static_normals(i, normals, normals.empty() || normals.data() != normals_made.data());
        static_objects_.push_back(std::uint32_t(i));
        static_first_.push_back(std::uint32_t(first));
        objects_[i].group_first = std::uint32_t(first);
        first += mesh.triangles.size();
        stats.rebuilds.push_back(TreeRebuild{i, scene.objects[i].name, reason, 0.0, 0.0});
        ++stats.objects_rebuilt;
        stats.triangles_rebuilt += mesh.triangles.size();
    }
    index_static_buckets(first);
    stats.update_ms += clock.lap_ms();
    static_group_.motion_class = anim::MotionClass::static_;
    const bvh::TriangleSource source(meshes);
    bvh::BuildConfig build = config;
    // Built for memory too: coarser binary leaves for big groups (lean_leaf_size_min).
    if (build.compact_leaves) build.leaf_size_min = std::max(build.leaf_size_min, lean_leaf_size_min(first));
    build_tree(static_group_, source, build, costs_);
    // The group is never refitted: shading reads a hit's corners back from the tree's own
    // blocks, or with compact leaves from what they read (timed with the build, whose last
    // step it is).
    static_group_.read_triangles_from_blocks(source);
    stats.rebuild_ms += clock.lap_ms();
}

/// The tree that holds `object`'s triangles, and where its triangle 0 is in it.
std::pair<const ObjectTree*, std::uint32_t> SceneAccel::holder_of(std::size_t object) const {
    const ObjectTree& o = objects_[object];
    if (o.motion_class == anim::MotionClass::static_) return {&static_group_, o.group_first};
    if (o.shares_tree_of >= 0) return {&objects_[std::size_t(o.shares_tree_of)], 0};
    return {&o, 0};
}

void SceneAccel::prefetch_triangle(std::size_t object, std::uint32_t prim) const {
    const auto [tree, first] = holder_of(object);
    tree->prefetch_triangle(first + prim);
}

std::optional<bvh::Triangle> SceneAccel::tree_triangle(std::uint32_t object, std::uint32_t prim) const {
    if (object == static_group_id()) {
        if (prim >= static_group_.triangle_count()) return std::nullopt;
        return static_group_.triangle(prim);
    }
    if (object >= objects_.size()) return std::nullopt;
    if (objects_[object].motion_class == anim::MotionClass::static_) return std::nullopt;
    const ObjectTree& o = *holder_of(object).first;
    if (prim >= o.triangle_count()) return std::nullopt;
    return o.triangle(prim);
}

bvh::Triangle SceneAccel::world_triangle(std::size_t object, std::uint32_t prim) const {
    const auto [tree, first] = holder_of(object);
    const bvh::Triangle t = tree->triangle(first + prim);
    if (tree->motion_class != anim::MotionClass::rigid) return t;
    // The object's own transform: the tree may be another copy's.
    const glm::mat4& to_world = objects_[object].object_to_world;
    return bvh::Triangle{transform_point(to_world, t.v0), transform_point(to_world, t.v1),
                         transform_point(to_world, t.v2)};
}

void SceneAccel::object_world_parts(std::size_t i, std::size_t max_parts,
                                    std::vector<bvh::Aabb>& out) const {
    if (i >= object_boxes_.size() || object_boxes_[i].is_empty()) return;
    const bool own_tree = i < objects_.size() && objects_[i].built &&
                          objects_[i].motion_class != anim::MotionClass::static_ &&
                          !holder_of(i).first->tree.empty();
    if (!own_tree || max_parts <= 1) {
        out.push_back(object_boxes_[i]);
        return;
    }
    const ObjectTree& o = objects_[i];
    std::vector<bvh::Aabb> parts;
    bvh::cover_boxes(holder_of(i).first->tree, max_parts, parts);
    const bool rigid = o.motion_class == anim::MotionClass::rigid;
    for (const bvh::Aabb& box : parts) {
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
