// Quantised wide nodes (BuildConfig::quantized_nodes, bvh/include/dynrt/bvh/quantized_node.h):
//   - one node: every decoded child box holds the exact box, near the origin and far from it
//     (up to 1e30), for boxes of every size down to a point, and stays within a step of it (an
//     encoder that gave every child the whole node box would fail); the SIMD decode the
//     traversal runs gives the same floats as the scalar one; a box no 8-bit grid covers is
//     refused and the tree keeps float nodes;
//   - whole trees from both builders, full and compact leaves, near and far from the origin:
//     half the node bytes, validate's checks (which catch a plane moved inwards), and the float
//     tree's hits bit for bit (t, u, v and primitive) for closest and any hit; refit refuses.
// The packets' agreement is in packet_traversal_test.cpp.

#include "dynrt/bvh/quantized_node.h"
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
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::make_ray;

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }


/// A node of `used` children with random boxes inside [at, at + extent]^3, some of them flat
/// or a single point.
WideNode<8> random_node(std::mt19937& rng, glm::vec3 at, float extent, int used) {
    WideNode<8> node = WideNode<8>::empty();
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < used; ++i) {
        glm::vec3 a = at + extent * glm::vec3(unit(rng), unit(rng), unit(rng));
        glm::vec3 b = at + extent * glm::vec3(unit(rng), unit(rng), unit(rng));
        if (i == 1) b = a;                 // a point
        if (i == 2) b.y = a.y;             // flat on y
        if (i == 3) b = a + glm::vec3(extent * 1e-7f);  // tiny (a point far from the origin)
        node.set_box(i, Aabb{glm::min(a, b), glm::max(a, b)});
        node.child[i] = static_cast<std::uint32_t>(10 + i);
        node.blocks[i] = static_cast<std::uint16_t>(i % 2);
    }
    return node;
}

TEST(QuantizedNode, DecodedBoxesHoldTheExactOnesNearAndFarFromTheOrigin) {
    std::mt19937 rng(5);
    typedef float F __attribute__((vector_size(32)));  // eight lanes, as the kernels use
    int checked = 0;
    for (const float at : {0.0f, -1.5f, 1000.0f, -3.0e6f, 7.0e9f, 1.0e20f, -1.0e30f}) {
        for (const float extent : {1e-6f, 1e-2f, 1.0f, 300.0f, 1e7f, 1e12f}) {
            for (int used = 1; used <= 8; ++used) {
                const WideNode<8> node = random_node(rng, glm::vec3(at, -at, at * 0.5f), extent, used);
                QuantizedWideNode<8> q;
                ASSERT_TRUE(quantize_node(node, q)) << at << " " << extent;
                F lo[3], hi[3];
                child_box_lanes<F>(q, lo, hi);
                for (int i = 0; i < 8; ++i) {
                    ASSERT_EQ(q.child[i], node.child[i]);
                    ASSERT_EQ(q.blocks[i], node.blocks[i]);
                    ASSERT_EQ(((q.used >> i) & 1u) != 0, i < used);
                    const Aabb box = q.box(i);
                    if (i >= used) {
                        EXPECT_TRUE(box.is_empty());
                        continue;
                    }
                    const Aabb exact = node.box(i);
                    ASSERT_TRUE(box.contains(exact)) << "at " << at << " extent " << extent << " slot " << i;
                    for (int a = 0; a < 3; ++a) {
                        // The SIMD decode is the scalar one.
                        ASSERT_TRUE(same_bits(lo[a][i], box.lo[a]) && same_bits(hi[a][i], box.hi[a]));
                        // Within one step (and the float spacing there) of the exact plane.
                        const float step = q.scale(a);
                        const float slack_lo = step + 2.0f * std::abs(std::nextafter(exact.lo[a], 0.0f) - exact.lo[a]);
                        const float slack_hi = step + 2.0f * std::abs(std::nextafter(exact.hi[a], 0.0f) - exact.hi[a]);
                        EXPECT_LE(exact.lo[a] - box.lo[a], slack_lo) << "slot " << i << " axis " << a;
                        EXPECT_LE(box.hi[a] - exact.hi[a], slack_hi) << "slot " << i << " axis " << a;
                    }
                    ++checked;
                }
            }
        }
    }
    EXPECT_EQ(checked, 7 * 6 * 36);
}

TEST(QuantizedNode, ABoxNoGridCoversIsRefusedAndTheTreeKeepsFloatNodes) {
    WideNode<8> node = WideNode<8>::empty();
    const float big = 3.0e38f;
    node.set_box(0, Aabb{{-big, 0, 0}, {big, 1, 1}});
    node.child[0] = 1;
    node.blocks[0] = 1;
    QuantizedWideNode<8> q;
    EXPECT_FALSE(quantize_node(node, q));
    node.set_box(0, Aabb{{0, 0, 0}, {std::numeric_limits<float>::infinity(), 1, 1}});
    EXPECT_FALSE(quantize_node(node, q));

    // A tree over a huge triangle and a small one: built, it stays float and traces the same.
    std::vector<Triangle> tris = {Triangle{{-big, -1, 0}, {big, -1, 0}, {0, 1, 0}},
                                  Triangle{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}};
    BuildConfig config;
    config.quantized_nodes = true;
    const TriangleBvh tree = build_triangle_bvh(TriangleSource(tris), config);
    EXPECT_FALSE(tree.wide.quantized);
    EXPECT_EQ(validate(tree, tris, config.leaf_size_max), "");
    const Hit hit = intersect_closest(tree.wide, make_ray({0.2f, 0.2f, 5}, {0, 0, -1}));
    EXPECT_EQ(hit.prim, 1u);
}

/// Triangles of indexed meshes (a grid, a soup with a degenerate triangle, another grid)
/// moved by `offset`, and random rays about them.
struct Case {
    BuildMethod method;
    bool compact;
    float offset;
};

class QuantizedTrees : public ::testing::TestWithParam<Case> {};

TEST_P(QuantizedTrees, HalveTheNodesAndGiveTheFloatTreesHitsBitForBit) {
    testing::Meshes m = testing::three_meshes();
    for (std::size_t k = 0; k < m.positions.size(); ++k) {
        for (glm::vec3& p : m.positions[k]) p += glm::vec3(GetParam().offset, -0.5f * GetParam().offset, 0.25f * GetParam().offset);
    }
    m.gathered.clear();
    for (std::size_t k = 0; k < m.positions.size(); ++k) {
        for (const glm::uvec3& t : m.triangles[k]) {
            m.gathered.push_back(Triangle{m.positions[k][t.x], m.positions[k][t.y], m.positions[k][t.z]});
        }
    }
    const TriangleSource source(m.views);
    BuildConfig config;
    config.method = GetParam().method;
    config.compact_leaves = GetParam().compact;
    const TriangleBvh exact = build_triangle_bvh(source, config);
    config.quantized_nodes = true;
    const TriangleBvh quantized = build_triangle_bvh(source, config);

    ASSERT_FALSE(exact.wide.quantized);
    ASSERT_TRUE(quantized.wide.quantized);
    EXPECT_TRUE(quantized.wide.nodes.empty());
    ASSERT_EQ(quantized.wide.quantized_nodes.size(), exact.wide.nodes.size());
    EXPECT_EQ(quantized.wide.bytes() + exact.wide.nodes.size() * sizeof(WideNode<8>) / 2, exact.wide.bytes());
    EXPECT_EQ(validate(quantized, m.gathered, config.leaf_size_max), "");
    EXPECT_EQ(compute_stats(quantized).nodes, compute_stats(exact).nodes);

    testing::expect_same_hits(exact.wide, quantized.wide, false);
}

INSTANTIATE_TEST_SUITE_P(Builders, QuantizedTrees,
                         ::testing::Values(Case{BuildMethod::binned_sah, false, 0.0f},
                                           Case{BuildMethod::binned_sah, true, 0.0f},
                                           Case{BuildMethod::morton, false, 0.0f},
                                           Case{BuildMethod::binned_sah, false, 20000.0f},
                                           Case{BuildMethod::morton, true, 20000.0f}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             return std::string(build_method_name(info.param.method)) +
                                    (info.param.compact ? "_compact" : "_full") +
                                    (info.param.offset != 0.0f ? "_far" : "_near");
                         });

TEST(QuantizedTreeChecks, APlaneMovedInwardsIsCaughtAndRefitIsRefused) {
    testing::Meshes m = testing::three_meshes();
    BuildConfig config;
    config.quantized_nodes = true;
    TriangleBvh tree = build_triangle_bvh(TriangleSource(m.gathered), config);
    ASSERT_TRUE(tree.wide.quantized);
    ASSERT_EQ(validate(tree, m.gathered, config.leaf_size_max), "");
    // Every leaf slot of the root's first child node shrunk by one step on x: some triangle
    // sticks out (a leaf's box is as tight as the grid allows).
    bool moved = false;
    for (QuantizedWideNode<8>& node : tree.wide.quantized_nodes) {
        for (int i = 0; i < 8; ++i) {
            if (node.is_leaf(i) && node.axis[0].hi[i] > node.axis[0].lo[i]) {
                --node.axis[0].hi[i];
                moved = true;
            }
        }
        if (moved) break;
    }
    ASSERT_TRUE(moved);
    EXPECT_NE(validate(tree, m.gathered, config.leaf_size_max).find("outside"), std::string::npos);
    try {
        refit_wide(tree.wide, m.gathered, config.sah_costs());
        ADD_FAILURE() << "a quantised tree was refitted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("quantised"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace dynrt::bvh
