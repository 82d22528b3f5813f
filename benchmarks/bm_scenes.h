#pragma once
// Benchmark inputs: a procedural scene spec, loaded and posed once per process, flattened to
// the triangle soup dynrt builds over and to the indexed buffers Embree builds over.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/engine/scene_loading.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::bench {

/// One posed scene in both forms. Positions and indices are per object, exactly as posed.
struct SceneInput {
    std::string spec;
    /// Every triangle of every object in world space, in scene order.
    std::vector<bvh::Triangle> triangles;
    bvh::Aabb bounds;
    /// Per object: world positions as x, y, z floats plus one float of padding (Embree reads
    /// vertices as 16 bytes), and triangle indices.
    std::vector<std::vector<float>> positions;
    std::vector<std::vector<std::uint32_t>> indices;
};

/// Loads `spec` (e.g. "sphere:1000000") with dynrt::load_scene, poses frame 0 with
/// anim::pose_scene and keeps the result for the rest of the process.
inline const SceneInput& scene_input(const std::string& spec) {
    static std::map<std::string, std::unique_ptr<SceneInput>> cache;
    auto& slot = cache[spec];
    if (slot) return *slot;
    const Scene scene = load_scene(spec);
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    auto input = std::make_unique<SceneInput>();
    input->spec = spec;
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const std::vector<glm::vec3>& p = posed.objects[o].positions;
        std::vector<float>& flat = input->positions.emplace_back();
        flat.reserve(3 * p.size() + 1);
        for (const glm::vec3& v : p) flat.insert(flat.end(), {v.x, v.y, v.z});
        flat.push_back(0.0f);
        std::vector<std::uint32_t>& idx = input->indices.emplace_back();
        for (const glm::uvec3& t : scene.objects[o].mesh.triangles) {
            idx.insert(idx.end(), {t.x, t.y, t.z});
            const bvh::Triangle tri{p[t.x], p[t.y], p[t.z]};
            input->triangles.push_back(tri);
            input->bounds.extend(tri.bounds());
        }
    }
    slot = std::move(input);
    return *slot;
}

}  // namespace dynrt::bench
