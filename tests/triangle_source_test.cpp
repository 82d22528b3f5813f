// Building from indexed meshes (bvh/include/dynrt/bvh/triangle_source.h), as the engine's
// static group does to skip a gathered copy of its triangles: the tree must be the one built
// from the gathered triangles byte for byte, for both builders, wide and binary, over several
// meshes numbered one after another (an empty one among them, shared and unshared vertices).

#include "dynrt/bvh/block_triangles.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/triangle_source.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace dynrt::bvh {
namespace {

struct Meshes {
    std::vector<std::vector<glm::vec3>> positions;
    std::vector<std::vector<glm::uvec3>> triangles;
    std::vector<TriangleSource::IndexedMesh> views;
    std::vector<Triangle> gathered;
};

/// A grid of shared vertices, an empty mesh, a soup (three vertices of its own per triangle,
/// a degenerate one among them) and a grid again.
Meshes three_meshes() {
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

template <class Vector>
bool same_bytes(const Vector& a, const Vector& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

struct Case {
    BuildMethod method;
    bool wide;
};

class IndexedBuild : public ::testing::TestWithParam<Case> {};

TEST_P(IndexedBuild, IsTheTreeOfTheGatheredTrianglesByteForByte) {
    const Meshes m = three_meshes();
    const TriangleSource indexed(m.views);
    ASSERT_TRUE(indexed.indexed());
    ASSERT_EQ(indexed.size(), m.gathered.size());
    for (std::size_t i = 0; i < m.gathered.size(); ++i) {
        const Triangle t = indexed[i];
        ASSERT_EQ(std::memcmp(&t, &m.gathered[i], sizeof t), 0) << "triangle " << i;
    }
    BuildConfig config;
    config.method = GetParam().method;
    config.wide = GetParam().wide;
    const TriangleBvh from_indexed = build_triangle_bvh(indexed, config);
    const TriangleBvh from_gathered = build_triangle_bvh(m.gathered, config);
    EXPECT_EQ(from_indexed.degenerate_skipped, 1u);
    EXPECT_TRUE(same_bytes(from_indexed.skipped_ids, from_gathered.skipped_ids));
    EXPECT_TRUE(same_bytes(from_indexed.wide.nodes, from_gathered.wide.nodes));
    EXPECT_TRUE(same_bytes(from_indexed.wide.blocks, from_gathered.wide.blocks));
    EXPECT_TRUE(same_bytes(from_indexed.bvh.nodes, from_gathered.bvh.nodes));
    EXPECT_TRUE(same_bytes(from_indexed.bvh.prim_ids, from_gathered.bvh.prim_ids));
    EXPECT_TRUE(same_bytes(from_indexed.tris, from_gathered.tris));
    EXPECT_EQ(validate(from_indexed, m.gathered, config.leaf_size_max), "");
    // The blocks' index reads every triangle back, the left-out one from its copy.
    const BlockTriangles back = BlockTriangles::index(from_indexed, indexed);
    ASSERT_EQ(back.indexed(), GetParam().wide);
    if (back.indexed()) {
        for (std::uint32_t i = 0; i < m.gathered.size(); ++i) {
            const Triangle t = back.at(from_indexed, i);
            ASSERT_EQ(std::memcmp(&t, &m.gathered[i], sizeof t), 0) << "triangle " << i;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Builders, IndexedBuild,
                         ::testing::Values(Case{BuildMethod::binned_sah, true}, Case{BuildMethod::binned_sah, false},
                                           Case{BuildMethod::morton, true}, Case{BuildMethod::morton, false}));

}  // namespace
}  // namespace dynrt::bvh
