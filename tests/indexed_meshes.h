#pragma once
// Indexed meshes for the tests of builds from a TriangleSource (triangle_source_test.cpp,
// compact_leaves_test.cpp): several meshes numbered one after another, with shared and
// unshared vertices, an empty mesh and one zero-area triangle.

#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_source.h"

#include "bvh_test_geometry.h"

#include <glm/vec3.hpp>

#include <random>
#include <vector>

namespace dynrt::bvh::testing {

struct Meshes {
    std::vector<std::vector<glm::vec3>> positions;
    std::vector<std::vector<glm::uvec3>> triangles;
    std::vector<TriangleSource::IndexedMesh> views;
    std::vector<Triangle> gathered;
};

/// A grid of shared vertices, an empty mesh, a soup (three vertices of its own per triangle,
/// a degenerate one among them) and a grid again.
inline Meshes three_meshes() {
    Meshes m;
    std::mt19937 rng(11);
    const auto grid = [&](int n, glm::vec3 at) {
        std::vector<glm::vec3>& p = m.positions.emplace_back();
        std::vector<glm::uvec3>& t = m.triangles.emplace_back();
        std::uniform_real_distribution<float> bump(-0.05f, 0.05f);
        for (int y = 0; y <= n; ++y) {
            for (int x = 0; x <= n; ++x) p.push_back(at + glm::vec3(float(x), float(y), bump(rng)));
        }
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
                const unsigned v = unsigned(y * (n + 1) + x), w = unsigned(n + 1);
                t.emplace_back(v, v + 1, v + w);
                t.emplace_back(v + 1, v + w + 1, v + w);
            }
        }
    };
    grid(30, glm::vec3(0.0f));
    m.positions.emplace_back();
    m.triangles.emplace_back();
    {
        const std::vector<Triangle> soup = testing::random_soup(5, 900, 20.0f, 0.5f, glm::vec3(-5.0f));
        std::vector<glm::vec3>& p = m.positions.emplace_back();
        std::vector<glm::uvec3>& t = m.triangles.emplace_back();
        for (const Triangle& s : soup) {
            const unsigned v = unsigned(p.size());
            p.insert(p.end(), {s.v0, s.v1, s.v2});
            t.emplace_back(v, v + 1, v + 2);
        }
        t[17] = glm::uvec3(t[17].x, t[17].x, t[17].y);  // zero area: left out of the tree
    }
    grid(12, glm::vec3(3.0f, -8.0f, 2.0f));
    for (std::size_t k = 0; k < m.positions.size(); ++k) {
        m.views.push_back(TriangleSource::IndexedMesh{m.positions[k], m.triangles[k]});
        for (const glm::uvec3& t : m.triangles[k]) {
            m.gathered.push_back(Triangle{m.positions[k][t.x], m.positions[k][t.y], m.positions[k][t.z]});
        }
    }
    return m;
}

}  // namespace dynrt::bvh::testing
