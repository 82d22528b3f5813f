// Building and refitting from indexed meshes and soups (bvh/include/dynrt/bvh/triangle_source.h),
// as the engine does to skip a gathered copy of its triangles: the tree must be the one built
// (or refitted) from the gathered triangles byte for byte, for both builders, wide and binary,
// over several meshes numbered one after another (an empty one among them, shared and
// unshared vertices); a refit says whether anything moved.

#include "dynrt/bvh/block_triangles.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/triangle_source.h"

#include "bvh_test_geometry.h"
#include "indexed_meshes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::Meshes;
using testing::three_meshes;

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

/// A soup's corners, three a triangle in order, and its index triples (3t, 3t + 1, 3t + 2).
struct Soup {
    std::vector<glm::vec3> corners;
    std::vector<glm::uvec3> triples;
};

Soup soup_of(const std::vector<Triangle>& tris) {
    Soup s;
    for (const Triangle& t : tris) {
        const unsigned v = unsigned(s.corners.size());
        s.corners.insert(s.corners.end(), {t.v0, t.v1, t.v2});
        s.triples.emplace_back(v, v + 1, v + 2);
    }
    return s;
}

TEST(SoupSource, IsFoundByItsTriplesAndReadInPlace) {
    // More triangles than is_soup checks on one thread, so a triple out of order near the end
    // is found by the parallel part.
    const std::vector<Triangle> tris = testing::random_soup(21, 70000, 10.0f, 0.2f);
    Soup s = soup_of(tris);
    EXPECT_TRUE(TriangleSource::is_soup(s.triples));
    EXPECT_TRUE(TriangleSource::is_soup({}));
    const TriangleSource soup = TriangleSource::soup(s.corners);
    EXPECT_FALSE(soup.indexed());
    ASSERT_EQ(soup.size(), tris.size());
    for (std::size_t i = 0; i < tris.size(); i += 97) {
        const Triangle t = soup[i];
        ASSERT_EQ(std::memcmp(&t, &tris[i], sizeof t), 0) << "triangle " << i;
    }
    std::swap(s.triples[69990].y, s.triples[69990].z);
    EXPECT_FALSE(TriangleSource::is_soup(s.triples));
    // Shared vertices are not a soup.
    EXPECT_FALSE(TriangleSource::is_soup(three_meshes().triangles[0]));
    // Built in place, the tree is the gathered triangles' byte for byte.
    for (const BuildMethod method : {BuildMethod::binned_sah, BuildMethod::morton}) {
        BuildConfig config;
        config.method = method;
        const TriangleBvh from_soup = build_triangle_bvh(soup, config);
        const TriangleBvh from_copy = build_triangle_bvh(tris, config);
        EXPECT_TRUE(same_bytes(from_soup.wide.nodes, from_copy.wide.nodes));
        EXPECT_TRUE(same_bytes(from_soup.wide.blocks, from_copy.wide.blocks));
    }
}

class SourceRefit : public ::testing::TestWithParam<bool> {};

TEST_P(SourceRefit, IsTheRefitOfTheGatheredTrianglesAndSaysWhetherAnythingMoved) {
    BuildConfig config;
    config.wide = GetParam();
    const Meshes m = three_meshes();
    const TriangleBvh built = build_triangle_bvh(m.gathered, config);
    // Every vertex moved (the left-out degenerate triangle stays degenerate: its corners move
    // together), read three ways.
    Meshes after = m;
    for (std::vector<glm::vec3>& p : after.positions) {
        for (glm::vec3& v : p) v = v * 1.25f + glm::vec3(0.5f, -0.25f, 0.125f * v.x);
    }
    after.views.clear();
    after.gathered.clear();
    for (std::size_t k = 0; k < after.positions.size(); ++k) {
        after.views.push_back(TriangleSource::IndexedMesh{after.positions[k], after.triangles[k]});
        for (const glm::uvec3& t : after.triangles[k]) {
            after.gathered.push_back(Triangle{after.positions[k][t.x], after.positions[k][t.y], after.positions[k][t.z]});
        }
    }
    TriangleBvh from_copy = built;
    const RefitResult copy_result = refit(from_copy, after.gathered, config.sah_costs());
    ASSERT_FALSE(copy_result.needs_rebuild());
    EXPECT_TRUE(copy_result.moved);
    TriangleBvh from_indexed = built;
    const RefitResult indexed_result = refit(from_indexed, TriangleSource(after.views), config.sah_costs());
    EXPECT_TRUE(indexed_result.moved);
    EXPECT_EQ(indexed_result.sah_cost, copy_result.sah_cost);
    EXPECT_TRUE(same_bytes(from_indexed.wide.nodes, from_copy.wide.nodes));
    EXPECT_TRUE(same_bytes(from_indexed.wide.blocks, from_copy.wide.blocks));
    EXPECT_TRUE(same_bytes(from_indexed.bvh.nodes, from_copy.bvh.nodes));
    EXPECT_TRUE(same_bytes(from_indexed.tris, from_copy.tris));

    // The soup among the meshes, alone, read in place.
    const Soup soup = soup_of(std::vector<Triangle>(after.gathered.begin() + 900, after.gathered.begin() + 1800));
    ASSERT_EQ(after.triangles[1].size(), 0u);
    ASSERT_EQ(after.triangles[2].size(), 900u);
    const std::vector<Triangle> soup_before(m.gathered.begin() + 900, m.gathered.begin() + 1800);
    const TriangleBvh soup_built = build_triangle_bvh(soup_before, config);
    TriangleBvh soup_copy = soup_built, soup_in_place = soup_built;
    const std::vector<Triangle> soup_after(after.gathered.begin() + 900, after.gathered.begin() + 1800);
    refit(soup_copy, soup_after, config.sah_costs());
    EXPECT_TRUE(refit(soup_in_place, TriangleSource::soup(soup.corners), config.sah_costs()).moved);
    EXPECT_TRUE(same_bytes(soup_in_place.wide.blocks, soup_copy.wide.blocks));
    EXPECT_TRUE(same_bytes(soup_in_place.bvh.nodes, soup_copy.bvh.nodes));

    // Refitted again to the same triangles, nothing moved and no byte changes.
    const TriangleBvh kept = from_indexed;
    const RefitResult again = refit(from_indexed, TriangleSource(after.views), config.sah_costs());
    EXPECT_FALSE(again.moved);
    EXPECT_TRUE(same_bytes(from_indexed.wide.blocks, kept.wide.blocks));
    EXPECT_TRUE(same_bytes(from_indexed.tris, kept.tris));
    // One corner of one triangle moves: that is seen.
    after.positions[3][5].z += 0.01f;
    EXPECT_TRUE(refit(from_indexed, TriangleSource(after.views), config.sah_costs()).moved);
}

INSTANTIATE_TEST_SUITE_P(WideAndBinary, SourceRefit, ::testing::Values(true, false));

INSTANTIATE_TEST_SUITE_P(Builders, IndexedBuild,
                         ::testing::Values(Case{BuildMethod::binned_sah, true}, Case{BuildMethod::binned_sah, false},
                                           Case{BuildMethod::morton, true}, Case{BuildMethod::morton, false}));

}  // namespace
}  // namespace dynrt::bvh
