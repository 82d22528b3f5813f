#pragma once
// Test scenes for the two-level BVH: objects given in object space with a placement, turned at
// once into (a) bottom-level trees and instances and (b) an engine Scene posed in world space,
// from which the exact double-precision reference tracer is built. Also the brute force over
// instances (every instance's tree traced without the top level) that the top level must
// reproduce bit for bit.

#include "bvh_test_geometry.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <bit>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::bvh::testing {

/// One object: a mesh (index into TwoLevelWorld's meshes, so two objects may share a tree) and
/// where it sits. Identity objects are posed in world space by `place` before building their
/// tree (their tree is their own); transformed ones share the mesh's object-space tree.
struct ObjectSpec {
    std::size_t mesh = 0;
    bool identity = true;
    glm::dmat4 place{1.0};
};

inline glm::dmat4 placement(glm::dvec3 translate, double angle_deg = 0.0,
                            glm::dvec3 axis = {0.0, 0.0, 1.0}, glm::dvec3 scale = {1.0, 1.0, 1.0}) {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), translate);
    m = glm::rotate(m, glm::radians(angle_deg), glm::normalize(axis));
    return glm::scale(m, scale);
}

inline std::vector<Triangle> translated(std::vector<Triangle> tris, glm::vec3 offset) {
    for (Triangle& t : tris) {
        t.v0 += offset;
        t.v1 += offset;
        t.v2 += offset;
    }
    return tris;
}

/// The float placement an instance uses, and the world positions pose_scene gives: the object
/// transform is stored in float (Object::transform), so both see the same matrix.
struct TwoLevelWorld {
    std::vector<std::vector<Triangle>> meshes;
    std::vector<ObjectSpec> objects;
    /// Object ids in instance order (default: object index, instance i = object i).
    std::vector<std::uint32_t> instance_order;

    std::vector<std::unique_ptr<TriangleBvh>> trees;
    std::vector<std::vector<Triangle>> world_tris;  // per object, as the reference sees them
    TwoLevelBvh tlas;
    Scene scene;
    anim::PosedScene posed;
    std::unique_ptr<reference::ReferenceTracer> reference;

    /// Builds trees, instances, the top level and the reference.
    void build() {
        const BuildConfig config{1.0f, 4, 16};
        std::vector<std::unique_ptr<TriangleBvh>> mesh_trees(meshes.size());
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            mesh_trees[m] = std::make_unique<TriangleBvh>(build_triangle_bvh(meshes[m], config));
        }
        scene = Scene{};
        scene.source = "two-level test";
        scene.materials.push_back(Material{});
        std::vector<Instance> by_object(objects.size());
        for (std::size_t o = 0; o < objects.size(); ++o) {
            const ObjectSpec& spec = objects[o];
            const glm::mat4 place_f(spec.place);
            Object object;
            object.name = "object " + std::to_string(o);
            for (const Triangle& t : meshes[spec.mesh]) {
                const auto base = static_cast<std::uint32_t>(object.mesh.positions.size());
                object.mesh.positions.insert(object.mesh.positions.end(), {t.v0, t.v1, t.v2});
                object.mesh.triangles.emplace_back(base, base + 1, base + 2);
            }
            object.transform = place_f;
            scene.objects.push_back(std::move(object));
        }
        anim::pose_scene(scene, 0, posed);
        reference = std::make_unique<reference::ReferenceTracer>(scene, posed);
        world_tris.assign(objects.size(), {});
        for (std::size_t o = 0; o < objects.size(); ++o) {
            const std::vector<glm::vec3>& p = posed.objects[o].positions;
            for (std::size_t k = 0; k + 2 < p.size(); k += 3) world_tris[o].push_back({p[k], p[k + 1], p[k + 2]});
            Instance& instance = by_object[o];
            instance.object = static_cast<std::uint32_t>(o);
            instance.identity = objects[o].identity;
            if (instance.identity) {
                // Its own tree over the posed (world-space) triangles, exactly the reference's.
                trees.push_back(std::make_unique<TriangleBvh>(build_triangle_bvh(world_tris[o], config)));
                instance.blas = trees.back().get();
            } else {
                instance.blas = mesh_trees[objects[o].mesh].get();
                instance.object_to_world = glm::mat4(objects[o].place);
                instance.world_to_object =
                    glm::mat4(glm::inverse(glm::dmat4(instance.object_to_world)));
            }
        }
        for (auto& t : mesh_trees) trees.push_back(std::move(t));
        if (instance_order.empty()) {
            for (std::size_t o = 0; o < objects.size(); ++o) instance_order.push_back(static_cast<std::uint32_t>(o));
        }
        std::vector<Instance> instances;
        for (std::uint32_t o : instance_order) instances.push_back(by_object[o]);
        build_top_level(tlas, std::move(instances));
    }

    Aabb world_bounds() const {
        Aabb b;
        for (const auto& tris : world_tris) b.extend(bounds_of(tris));
        return b;
    }
};

/// Every instance traced without the top level, the smallest (t, object, prim) kept: what
/// intersect_closest(tlas, ray) must return bit for bit.
inline InstanceHit brute_force_instances(const TwoLevelBvh& tlas, const Ray& ray) {
    InstanceHit best;
    for (const Instance& instance : tlas.instances) {
        const Hit h = intersect_closest(*instance.blas, to_object_space(instance, ray));
        if (!h.is_hit()) continue;
        const bool wins = !best.is_hit() || h.t < best.hit.t ||
                          (h.t == best.hit.t && (instance.object < best.object ||
                                                 (instance.object == best.object && h.prim < best.hit.prim)));
        if (wins) {
            best.hit = h;
            best.object = instance.object;
        }
    }
    return best;
}

/// Bit-for-bit equality of two instance hits (t, u, v, prim, object).
inline bool same_bits(const InstanceHit& a, const InstanceHit& b) {
    return std::bit_cast<std::uint32_t>(a.hit.t) == std::bit_cast<std::uint32_t>(b.hit.t) &&
           std::bit_cast<std::uint32_t>(a.hit.u) == std::bit_cast<std::uint32_t>(b.hit.u) &&
           std::bit_cast<std::uint32_t>(a.hit.v) == std::bit_cast<std::uint32_t>(b.hit.v) &&
           a.hit.prim == b.hit.prim && a.object == b.object;
}

inline std::string describe(const InstanceHit& h) {
    return "{t " + std::to_string(h.hit.t) + " u " + std::to_string(h.hit.u) + " v " +
           std::to_string(h.hit.v) + " prim " + std::to_string(h.hit.prim) + " object " +
           std::to_string(h.object) + "}";
}

inline std::string describe(const Ray& r) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "ray org (%a %a %a) dir (%a %a %a) [%a %a]", r.org.x, r.org.y,
                  r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
    return buf;
}

/// The mixed scene: identity and transformed instances (rotations, non-uniform and mirrored
/// scale, translation), overlapping, one mesh placed twice, an empty mesh and an all-degenerate
/// one. Extent about [-4, 4]^3 around `center`.
inline TwoLevelWorld mixed_world(glm::dvec3 center = glm::dvec3(0.0)) {
    TwoLevelWorld w;
    const glm::vec3 c(center);
    w.meshes.push_back(translated(icosphere_mesh(2, 1.0f).triangles(), c));          // 0 world sphere
    w.meshes.push_back(cube_mesh(-0.5f, 0.5f).triangles());                          // 1 unit cube
    w.meshes.push_back(icosphere_mesh(1, 1.0f).triangles());                         // 2 coarse sphere
    w.meshes.push_back(tetrahedron_mesh().triangles());                              // 3 tetrahedron
    w.meshes.push_back(random_soup(11, 300, 6.0f, 0.2f, c - glm::vec3(3.0f)));       // 4 world soup
    w.meshes.push_back({});                                                          // 5 empty
    w.meshes.push_back({{glm::vec3(0.0f), glm::vec3(1.0f), glm::vec3(2.0f)}});       // 6 degenerate
    w.objects = {
        {0, true, glm::dmat4(1.0)},
        {1, false, placement(center + glm::dvec3(2.5, 0.0, 0.0), 30.0, {1.0, 1.0, 0.0})},
        {2, false, placement(center + glm::dvec3(0.5, 1.0, 0.0), 50.0, {0.3, 1.0, 0.2}, {3.0, 0.5, 1.0})},
        {3, false, placement(center + glm::dvec3(-2.0, 0.0, 0.5), 20.0, {1.0, 0.0, 0.0}, {-1.0, 1.0, 1.0})},
        {4, true, glm::dmat4(1.0)},
        {1, false, placement(center + glm::dvec3(0.0, -2.5, 0.0), 45.0, {0.0, 0.0, 1.0}, {1.5, 1.5, 1.5})},
        {5, false, placement(center + glm::dvec3(1.0, 1.0, 1.0), 10.0)},
        {6, false, placement(center + glm::dvec3(1.0, -1.0, 1.0), 10.0)},
        {5, true, glm::dmat4(1.0)},
        {2, false, placement(center + glm::dvec3(-0.5, -0.5, 2.0), 70.0, {0.0, 1.0, 0.0}, {0.25, 2.0, 0.7})},
    };
    // Objects whose placement is the identity keep their world-space meshes as posed.
    return w;
}

}  // namespace dynrt::bvh::testing
