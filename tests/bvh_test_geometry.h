#pragma once
// Test geometry for the bvh unit tests, made in code from fixed seeds: random triangle soups,
// closed meshes, random rays, and the brute-force loops the BVH is compared against (the same
// watertight test over every triangle, so answers must agree bit for bit).

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/watertight_intersector.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <span>
#include <utility>
#include <vector>

namespace dynrt::bvh::testing {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

/// A build configuration with this leaf size, cost ratio and bin count, the rest default.
inline BuildConfig config_with(std::uint32_t leaf_size_max, float cost_ratio = 1.0f,
                               std::uint32_t bin_count = 16) {
    BuildConfig c;
    c.leaf_size_max = leaf_size_max;
    c.cost_ratio = cost_ratio;
    c.bin_count = bin_count;
    return c;
}

/// config_with for the binary tree alone (a default build keeps only the wide tree, which
/// wide_bvh_test.cpp checks): for the tests of the binary tree itself.
inline BuildConfig binary_config_with(std::uint32_t leaf_size_max, float cost_ratio = 1.0f,
                                      std::uint32_t bin_count = 16) {
    BuildConfig c = config_with(leaf_size_max, cost_ratio, bin_count);
    c.wide = false;
    return c;
}

inline Ray make_ray(glm::vec3 org, glm::vec3 dir, float tmin = 0.0f, float tmax = kInf) {
    Ray r;
    r.org = org;
    r.dir = dir;
    r.tmin = tmin;
    r.tmax = tmax;
    return r;
}

inline glm::vec3 random_point(std::mt19937& rng, const glm::vec3& lo, const glm::vec3& hi) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
}

inline glm::vec3 random_direction(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    while (true) {
        const glm::vec3 d(n(rng), n(rng), n(rng));
        const float len = glm::length(d);
        if (len > 1e-3f) return d / len;
    }
}

/// `count` triangles with centres uniform in [offset, offset + extent]^3 and vertices within
/// `size` of their centre.
inline std::vector<Triangle> random_soup(std::uint32_t seed, std::size_t count, float extent = 1.0f,
                                         float size = 0.05f, glm::vec3 offset = glm::vec3(0.0f)) {
    std::mt19937 rng(seed);
    std::vector<Triangle> tris(count);
    for (Triangle& t : tris) {
        const glm::vec3 c = offset + random_point(rng, glm::vec3(0.0f), glm::vec3(extent));
        t.v0 = c + random_point(rng, glm::vec3(-size), glm::vec3(size));
        t.v1 = c + random_point(rng, glm::vec3(-size), glm::vec3(size));
        t.v2 = c + random_point(rng, glm::vec3(-size), glm::vec3(size));
    }
    return tris;
}

inline std::vector<Aabb> boxes_of(std::span<const Triangle> tris) {
    std::vector<Aabb> boxes;
    boxes.reserve(tris.size());
    for (const Triangle& t : tris) boxes.push_back(t.bounds());
    return boxes;
}

inline Aabb bounds_of(std::span<const Triangle> tris) {
    Aabb b;
    for (const Triangle& t : tris) b.extend(t.bounds());
    return b;
}

/// An indexed closed mesh, so shared vertices are bit-identical.
struct ClosedMesh {
    std::vector<glm::vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> faces;

    std::vector<Triangle> triangles() const {
        std::vector<Triangle> tris;
        for (const auto& f : faces) tris.push_back({vertices[f[0]], vertices[f[1]], vertices[f[2]]});
        return tris;
    }
    /// Each undirected edge once.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges() const {
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> seen;
        for (const auto& f : faces) {
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = f[k], b = f[(k + 1) % 3];
                seen[{std::min(a, b), std::max(a, b)}] = 1;
            }
        }
        std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
        for (const auto& [e, unused] : seen) out.push_back(e);
        return out;
    }
};

/// The cube [lo, hi]^3 as 12 triangles.
inline ClosedMesh cube_mesh(float lo = 0.0f, float hi = 1.0f) {
    ClosedMesh m;
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back(i & 1 ? hi : lo, i & 2 ? hi : lo, i & 4 ? hi : lo);
    }
    const std::uint32_t quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
        m.faces.push_back({q[0], q[1], q[2]});
        m.faces.push_back({q[0], q[2], q[3]});
    }
    return m;
}

/// A tetrahedron with irregular float coordinates.
inline ClosedMesh tetrahedron_mesh() {
    ClosedMesh m;
    m.vertices = {{0.1f, 0.2f, 0.3f}, {1.7f, 0.4f, 0.1f}, {0.6f, 1.9f, 0.2f}, {0.7f, 0.8f, 1.6f}};
    m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    return m;
}

/// Icosahedron subdivided `levels` times, vertices on the sphere of `radius` around `center`.
inline ClosedMesh icosphere_mesh(int levels, float radius = 1.0f, glm::vec3 center = glm::vec3(0.0f)) {
    ClosedMesh m;
    const float p = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<glm::vec3> unit = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                                   {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                                   {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
    for (auto& v : unit) v = glm::normalize(v);
    std::vector<std::array<std::uint32_t, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = midpoints.find(key);
            if (it != midpoints.end()) return it->second;
            unit.push_back(glm::normalize(unit[a] + unit[b]));
            const auto index = static_cast<std::uint32_t>(unit.size() - 1);
            midpoints[key] = index;
            return index;
        };
        std::vector<std::array<std::uint32_t, 3>> finer;
        for (const auto& f : faces) {
            const std::uint32_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]),
                                c = midpoint(f[2], f[0]);
            finer.push_back({f[0], a, c});
            finer.push_back({f[1], b, a});
            finer.push_back({f[2], c, b});
            finer.push_back({a, b, c});
        }
        faces = std::move(finer);
    }
    for (const auto& v : unit) m.vertices.push_back(center + radius * v);
    m.faces = std::move(faces);
    return m;
}

/// Closest hit by testing every non-degenerate triangle with the watertight test, shrinking
/// tmax as hits are found: the answer the BVH must reproduce bit for bit (up to ties in t).
inline Hit brute_force_closest(std::span<const Triangle> tris, const Ray& ray) {
    const WatertightRay wray(ray);
    Hit best;
    float tmax = ray.tmax;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        if (is_degenerate(tris[i])) continue;
        Hit h;
        if (intersect_watertight(wray, tris[i], ray.tmin, tmax, h)) {
            best = h;
            best.prim = static_cast<std::uint32_t>(i);
            tmax = h.t;
        }
    }
    return best;
}

inline bool brute_force_any(std::span<const Triangle> tris, const Ray& ray) {
    const WatertightRay wray(ray);
    for (const Triangle& t : tris) {
        Hit h;
        if (!is_degenerate(t) && intersect_watertight(wray, t, ray.tmin, ray.tmax, h)) return true;
    }
    return false;
}

/// Number of triangles the watertight test hits along the whole ray.
inline int count_hits(std::span<const Triangle> tris, const Ray& ray) {
    const WatertightRay wray(ray);
    int hits = 0;
    for (const Triangle& t : tris) {
        Hit h;
        hits += intersect_watertight(wray, t, ray.tmin, ray.tmax, h) ? 1 : 0;
    }
    return hits;
}

}  // namespace dynrt::bvh::testing
