// Compact leaves (BuildConfig::compact_leaves, bvh/include/dynrt/bvh/wide_bvh.h): a wide tree
// whose leaves keep only their triangles' indices and read the corners from the build's
// source as the trace reaches them. Against the same build with full blocks: the very same
// nodes byte for byte, the same indices in the same lanes, and the same hits bit for bit
// (t, u, v and primitive) for closest and any hit, from both builders, over indexed meshes
// (indexed_meshes.h: shared vertices, a soup, an empty mesh, a degenerate triangle) and plain triangles,
// as built and refitted to moved triangles. The packets' agreement is in packet_traversal_test.cpp.

#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/triangle_source.h"
#include "dynrt/bvh/wide_bvh.h"

#include "bvh_test_geometry.h"
#include "indexed_meshes.h"
#include "tree_rays.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::Meshes;
using testing::three_meshes;

struct Case {
    BuildMethod method;
    bool indexed;
};

class CompactLeaves : public ::testing::TestWithParam<Case> {};

TEST_P(CompactLeaves, KeepTheFullTreesNodesAndLanesAndGiveItsHitsBitForBit) {
    const Meshes m = three_meshes();
    const TriangleSource source = GetParam().indexed ? TriangleSource(m.views) : TriangleSource(m.gathered);
    BuildConfig config;
    config.method = GetParam().method;
    const TriangleBvh full = build_triangle_bvh(source, config);
    config.compact_leaves = true;
    const TriangleBvh compact = build_triangle_bvh(source, config);

    ASSERT_FALSE(full.wide.compact);
    ASSERT_TRUE(compact.wide.compact);
    EXPECT_TRUE(compact.wide.blocks.empty());
    EXPECT_TRUE(full.wide.prim_blocks.empty());
    EXPECT_EQ(compact.degenerate_skipped, 1u);
    EXPECT_EQ(validate(compact, m.gathered, config.leaf_size_max), "");
    // The same nodes, and every block's lanes the same indices.
    ASSERT_EQ(compact.wide.nodes.size(), full.wide.nodes.size());
    EXPECT_EQ(std::memcmp(compact.wide.nodes.data(), full.wide.nodes.data(),
                          full.wide.nodes.size() * sizeof(full.wide.nodes[0])),
              0);
    ASSERT_EQ(compact.wide.prim_blocks.size(), full.wide.blocks.size());
    for (std::size_t b = 0; b < full.wide.blocks.size(); ++b) {
        for (int lane = 0; lane < kBlockLanes; ++lane) {
            ASSERT_EQ(compact.wide.prim_blocks[b].prim[lane], full.wide.blocks[b].prim[lane]) << b << " " << lane;
        }
    }
    // A tenth of the blocks' bytes.
    EXPECT_LT(compact.wide.bytes() - compact.wide.nodes.size() * sizeof(compact.wide.nodes[0]),
              (full.wide.bytes() - full.wide.nodes.size() * sizeof(full.wide.nodes[0])) / 8);

    testing::expect_same_hits(full.wide, compact.wide, true);
}

INSTANTIATE_TEST_SUITE_P(Builders, CompactLeaves,
                         ::testing::Values(Case{BuildMethod::binned_sah, true}, Case{BuildMethod::binned_sah, false},
                                           Case{BuildMethod::morton, true}, Case{BuildMethod::morton, false}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             return std::string(build_method_name(info.param.method)) +
                                    (info.param.indexed ? "_indexed" : "_triangles");
                         });

/// `m`'s vertices moved: a swell along x and a random jitter, so every box changes.
Meshes moved(const Meshes& m) {
    Meshes out;
    out.triangles = m.triangles;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
    for (const std::vector<glm::vec3>& mesh : m.positions) {
        std::vector<glm::vec3>& p = out.positions.emplace_back();
        for (const glm::vec3& v : mesh) {
            p.push_back(v + glm::vec3(jitter(rng), 0.3f * std::sin(v.x) + jitter(rng), jitter(rng)));
        }
    }
    for (std::size_t k = 0; k < out.positions.size(); ++k) {
        out.views.push_back(TriangleSource::IndexedMesh{out.positions[k], out.triangles[k]});
        for (const glm::uvec3& t : out.triangles[k]) {
            const std::vector<glm::vec3>& p = out.positions[k];
            out.gathered.push_back(Triangle{p[t.x], p[t.y], p[t.z]});
        }
    }
    return out;
}

// A compact tree refitted to moved triangles (a deformable object's, UpdatePolicy::
// compact_moving_objects) is the full tree refitted to them: the same boxes byte for byte, the
// same SAH cost, and the same hits, read from the new triangles it views from then on.
TEST_P(CompactLeaves, RefitLikeTheFullTreeAndViewTheNewTriangles) {
    const Meshes m = three_meshes();
    const Meshes after = moved(m);
    const auto source_of = [&](const Meshes& meshes) {
        return GetParam().indexed ? TriangleSource(meshes.views) : TriangleSource(meshes.gathered);
    };
    BuildConfig config;
    config.method = GetParam().method;
    TriangleBvh full = build_triangle_bvh(source_of(m), config);
    config.compact_leaves = true;
    TriangleBvh compact = build_triangle_bvh(source_of(m), config);

    const RefitResult full_refit = refit(full, source_of(after), config.sah_costs());
    const RefitResult compact_refit = refit(compact, source_of(after), config.sah_costs());
    ASSERT_FALSE(compact_refit.needs_rebuild());
    EXPECT_EQ(compact_refit.sah_cost, full_refit.sah_cost);
    EXPECT_TRUE(full_refit.moved);
    EXPECT_TRUE(compact_refit.moved);
    ASSERT_EQ(compact.wide.nodes.size(), full.wide.nodes.size());
    EXPECT_EQ(std::memcmp(compact.wide.nodes.data(), full.wide.nodes.data(),
                          full.wide.nodes.size() * sizeof(full.wide.nodes[0])),
              0);
    EXPECT_EQ(validate(compact, after.gathered, config.leaf_size_max), "");
    EXPECT_NE(validate(compact, m.gathered, config.leaf_size_max), "");
    testing::expect_same_hits(full.wide, compact.wide, true);

    // Refitted to the very same triangles, it cannot tell: a compact leaf keeps no corners to
    // compare with, so it says moved (a full tree's refit says it did not).
    EXPECT_FALSE(refit(full, source_of(after), config.sah_costs()).moved);
    EXPECT_TRUE(refit(compact, source_of(after), config.sah_costs()).moved);
}

TEST(CompactLeavesChecks, AMovedSourceIsCaughtAndQuantisedNodesAreNotRefitted) {
    Meshes m = three_meshes();
    BuildConfig config;
    config.compact_leaves = true;
    const TriangleSource source(m.views);
    TriangleBvh tree = build_triangle_bvh(source, config);
    ASSERT_EQ(validate(tree, m.gathered, config.leaf_size_max), "");
    // The leaves read the source as it is now: a vertex moved under the tree is what the
    // check sees (the engine holds the static group's vertices unchanged for this reason).
    m.positions[0][7] += glm::vec3(0.0f, 0.25f, 0.0f);
    EXPECT_NE(validate(tree, m.gathered, config.leaf_size_max), "");
    // Quantised boxes were rounded against exact ones a refit no longer has.
    config.quantized_nodes = true;
    TriangleBvh quantized = build_triangle_bvh(source, config);
    ASSERT_TRUE(quantized.wide.quantized);
    try {
        refit_wide(quantized.wide, source, config.sah_costs());
        ADD_FAILURE() << "a quantised tree was refitted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("quantised"), std::string::npos) << e.what();
    }
    // Without the wide tree there is nothing compact: the binary tree keeps its copy.
    config.quantized_nodes = false;
    config.wide = false;
    const TriangleBvh binary = build_triangle_bvh(source, config);
    EXPECT_FALSE(binary.wide.compact);
    EXPECT_EQ(binary.tris.size(), binary.bvh.prim_ids.size());
}

}  // namespace
}  // namespace dynrt::bvh
