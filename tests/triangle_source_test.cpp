// Building from indexed meshes (bvh/include/dynrt/bvh/triangle_source.h), as the engine's
// static group does to skip a gathered copy of its triangles: the tree must be the one built
// from the gathered triangles byte for byte, for both builders, wide and binary, over several
// meshes numbered one after another (an empty one among them, shared and unshared vertices).

#include "dynrt/bvh/block_triangles.h"
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

INSTANTIATE_TEST_SUITE_P(Builders, IndexedBuild,
                         ::testing::Values(Case{BuildMethod::binned_sah, true}, Case{BuildMethod::binned_sah, false},
                                           Case{BuildMethod::morton, true}, Case{BuildMethod::morton, false}));

}  // namespace
}  // namespace dynrt::bvh
