// The binned SAH builder and the tree utilities (sah_cost, compute_stats, validate): every
// tree is checked with validate, including on inputs made to break binning (identical centres,
// huge and tiny coordinates, exponential spacing), and validate itself is checked to fail.

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/bvh.h"
#include "dynrt/bvh/triangle_bvh.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::boxes_of;
using testing::bounds_of;
using testing::random_soup;

/// These tests check the binary tree itself.
using testing::binary_config_with;

std::vector<glm::vec3> centers_of(const std::vector<Aabb>& boxes) {
    std::vector<glm::vec3> centers;
    for (const Aabb& b : boxes) centers.push_back(b.center());
    return centers;
}

Bvh build_boxes(const std::vector<Aabb>& boxes, const BuildConfig& config) {
    return build_binned_sah(boxes, centers_of(boxes), config);
}

bool box_is_finite(const Aabb& b) {
    return std::isfinite(b.lo.x) && std::isfinite(b.lo.y) && std::isfinite(b.lo.z) &&
           std::isfinite(b.hi.x) && std::isfinite(b.hi.y) && std::isfinite(b.hi.z);
}

/// Builds over `boxes` and checks everything the builder promises: validate, the root box is
/// the union of all boxes, no NaN anywhere.
void expect_valid_build(const std::vector<Aabb>& boxes, const BuildConfig& config,
                        const std::string& what) {
    const Bvh bvh = build_boxes(boxes, config);
    EXPECT_EQ(validate(bvh, boxes, config.leaf_size_max), "") << what;
    ASSERT_EQ(bvh.prim_ids.size(), boxes.size()) << what;
    if (boxes.empty()) {
        EXPECT_TRUE(bvh.empty()) << what;
        return;
    }
    Aabb all;
    for (const Aabb& b : boxes) all.extend(b);
    EXPECT_EQ(bvh.nodes[0].box.lo, all.lo) << what;
    EXPECT_EQ(bvh.nodes[0].box.hi, all.hi) << what;
    for (const BvhNode& n : bvh.nodes) EXPECT_TRUE(box_is_finite(n.box)) << what;
    EXPECT_LE(compute_stats(bvh).depth, kMaxDepth) << what;
}

TEST(BvhBuilder, EmptyInputGivesEmptyTree) {
    const Bvh bvh = build_binned_sah({}, {}, BuildConfig{});
    EXPECT_TRUE(bvh.empty());
    EXPECT_TRUE(bvh.prim_ids.empty());
    EXPECT_EQ(validate(bvh, {}, 8), "");
    EXPECT_EQ(sah_cost(bvh, SahCosts{}), 0.0);
    const BvhStats stats = compute_stats(bvh);
    EXPECT_EQ(stats.nodes, 0u);
    EXPECT_EQ(stats.depth, 0u);

    const TriangleBvh accel = build_triangle_bvh({}, binary_config_with(8));
    EXPECT_TRUE(accel.bvh.empty());
    EXPECT_TRUE(accel.tris.empty());
    EXPECT_EQ(accel.degenerate_skipped, 0u);
}

TEST(BvhBuilder, SinglePrimitiveIsOneLeaf) {
    for (std::uint32_t leaf_size_max : {1u, 8u}) {
        const std::vector<Aabb> boxes = {Aabb{glm::vec3(1, 2, 3), glm::vec3(4, 5, 6)}};
        const Bvh bvh = build_boxes(boxes, binary_config_with(leaf_size_max));
        ASSERT_EQ(bvh.nodes.size(), 1u);
        EXPECT_TRUE(bvh.nodes[0].is_leaf());
        EXPECT_EQ(bvh.nodes[0].count, 1u);
        EXPECT_EQ(bvh.prim_ids, std::vector<std::uint32_t>{0});
        EXPECT_EQ(validate(bvh, boxes, leaf_size_max), "");
        const BvhStats stats = compute_stats(bvh);
        EXPECT_EQ(stats.depth, 1u);
        EXPECT_EQ(stats.leaves, 1u);
    }
}

TEST(BvhBuilder, TwoSeparateBoxesSplitIntoTwoLeaves) {
    const std::vector<Aabb> boxes = {Aabb{glm::vec3(0), glm::vec3(1)},
                                     Aabb{glm::vec3(10, 0, 0), glm::vec3(11, 1, 1)}};
    const Bvh bvh = build_boxes(boxes, binary_config_with(8));
    ASSERT_EQ(bvh.nodes.size(), 3u);
    EXPECT_FALSE(bvh.nodes[0].is_leaf());
    EXPECT_EQ(bvh.nodes[0].first, 1u);
    EXPECT_EQ(validate(bvh, boxes, 8), "");
    // Root half area 11 + 1 + 11 = 23, each child 3: 1 + 2 * 3/23 with unit costs.
    EXPECT_NEAR(sah_cost(bvh, SahCosts{1.0f, 1.0f}), 1.0 + 6.0 / 23.0, 1e-12);
}

TEST(BvhBuilder, RandomSoupsAreValidForEveryLeafSizeAndCostRatio) {
    for (std::uint32_t seed : {1u, 2u}) {
        for (std::size_t count : {2u, 3u, 17u, 300u, 3000u}) {
            const std::vector<Triangle> tris = random_soup(seed, count, 1.0f, 0.05f);
            const std::vector<Aabb> boxes = boxes_of(tris);
            for (std::uint32_t leaf_size_max : {1u, 2u, 4u, 8u, 16u, 32u}) {
                for (float ratio : {0.05f, 0.1f, 0.5f, 1.0f, 2.0f}) {
                    const std::string what = "seed " + std::to_string(seed) + " n " +
                                             std::to_string(count) + " leaf " +
                                             std::to_string(leaf_size_max) + " ratio " +
                                             std::to_string(ratio);
                    expect_valid_build(boxes, binary_config_with(leaf_size_max, ratio), what);
                    const TriangleBvh accel = build_triangle_bvh(tris, binary_config_with(leaf_size_max, ratio));
                    EXPECT_EQ(validate(accel, tris, leaf_size_max), "") << what;
                    EXPECT_EQ(validate(accel.bvh, boxes, leaf_size_max), "") << what;
                }
            }
        }
    }
}

TEST(BvhBuilder, EveryBinCountGivesAValidTree) {
    const std::vector<Aabb> boxes = boxes_of(random_soup(3, 2000));
    for (std::uint32_t bins : {2u, 3u, 4u, 16u, 32u, 64u, 1000u}) {
        expect_valid_build(boxes, binary_config_with(4, 1.0f, bins), "bins " + std::to_string(bins));
    }
}

TEST(BvhBuilder, LargeInputTakesTheParallelPaths) {
    // Above the parallel binning and task thresholds.
    const std::vector<Triangle> tris = random_soup(4, 100000, 1.0f, 0.01f);
    const TriangleBvh accel = build_triangle_bvh(tris, binary_config_with(4));
    EXPECT_EQ(validate(accel, tris, 4), "");
    const BvhStats stats = compute_stats(accel.bvh);
    EXPECT_EQ(stats.nodes, accel.bvh.nodes.size());
    EXPECT_LT(stats.depth, 40u);
}

TEST(BvhBuilder, BuildsAreDeterministic) {
    const std::vector<Triangle> tris = random_soup(5, 50000, 1.0f, 0.02f);
    const TriangleBvh a = build_triangle_bvh(tris, binary_config_with(4));
    const TriangleBvh b = build_triangle_bvh(tris, binary_config_with(4));
    // Node order may differ with task scheduling; primitive order and tree shape may not.
    EXPECT_EQ(a.bvh.prim_ids, b.bvh.prim_ids);
    EXPECT_EQ(sah_cost(a.bvh, SahCosts{}), sah_cost(b.bvh, SahCosts{}));
    EXPECT_EQ(compute_stats(a.bvh).depth, compute_stats(b.bvh).depth);
    EXPECT_EQ(a.bvh.nodes.size(), b.bvh.nodes.size());
}

TEST(BvhBuilder, BuildingIntoARecycledTreeGivesTheSameTree) {
    // Large (parallel paths) and small inputs, with degenerates, an empty one and an only-
    // degenerate one, each built into the previous result: every size change in both directions
    // and leftovers from a previous tree (skipped ids, triangles, nodes) that must not survive.
    std::vector<Triangle> with_degenerates = random_soup(21, 3000);
    for (int i = 0; i < 40; ++i) {
        const glm::vec3 a(static_cast<float>(i), 0.5f, 0.25f);
        with_degenerates.insert(with_degenerates.begin() + 7 * i, Triangle{a, a, a});
    }
    const std::vector<std::vector<Triangle>> inputs = {
        random_soup(20, 60000, 1.0f, 0.02f), with_degenerates, {},
        std::vector<Triangle>(5, Triangle{glm::vec3(1), glm::vec3(1), glm::vec3(2)}),
        random_soup(22, 60000, 1.0f, 0.02f), random_soup(23, 1)};
    TriangleBvh recycled;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        const std::vector<Triangle>& tris = inputs[k];
        const TriangleBvh fresh = build_triangle_bvh(tris, binary_config_with(4));
        recycled = build_triangle_bvh(tris, binary_config_with(4), std::move(recycled));
        SCOPED_TRACE("input " + std::to_string(k));
        EXPECT_EQ(validate(recycled, tris, 4), "");
        EXPECT_EQ(recycled.bvh.prim_ids, fresh.bvh.prim_ids);
        EXPECT_EQ(recycled.bvh.nodes.size(), fresh.bvh.nodes.size());
        EXPECT_EQ(sah_cost(recycled.bvh, SahCosts{}), sah_cost(fresh.bvh, SahCosts{}));
        EXPECT_EQ(recycled.skipped_ids, fresh.skipped_ids);
        EXPECT_EQ(recycled.degenerate_skipped, fresh.degenerate_skipped);
        ASSERT_EQ(recycled.tris.size(), fresh.tris.size());
        for (std::size_t i = 0; i < fresh.tris.size(); ++i) {
            ASSERT_TRUE(recycled.tris[i].v0 == fresh.tris[i].v0 && recycled.tris[i].v1 == fresh.tris[i].v1 &&
                        recycled.tris[i].v2 == fresh.tris[i].v2)
                << "triangle " << i;
        }
    }
}

TEST(BvhBuilder, IdenticalTrianglesFallBackToMedianSplits) {
    const Triangle t{{0.1f, 0.2f, 0.3f}, {1.1f, 0.2f, 0.3f}, {0.1f, 1.2f, 0.3f}};
    const std::vector<Triangle> tris(1000, t);
    for (std::uint32_t leaf_size_max : {1u, 4u, 32u}) {
        const TriangleBvh accel = build_triangle_bvh(tris, binary_config_with(leaf_size_max));
        EXPECT_EQ(validate(accel, tris, leaf_size_max), "");
        const BvhStats stats = compute_stats(accel.bvh);
        EXPECT_LE(stats.leaf_prims_max, leaf_size_max);
        // Median splits halve the count: the depth is the balanced one.
        const auto leaves = (1000 + leaf_size_max - 1) / leaf_size_max;
        EXPECT_EQ(stats.depth, 1u + static_cast<std::uint32_t>(std::ceil(std::log2(leaves))));
    }
}

TEST(BvhBuilder, CoincidentCentresOfDifferentBoxes) {
    // Nested boxes around one centre: no bin separates them.
    std::vector<Aabb> boxes;
    for (int i = 1; i <= 100; ++i) {
        const float r = static_cast<float>(i);
        boxes.push_back(Aabb{glm::vec3(5.0f - r), glm::vec3(5.0f + r)});
    }
    for (std::uint32_t leaf_size_max : {1u, 2u, 8u}) {
        expect_valid_build(boxes, binary_config_with(leaf_size_max), "nested");
    }
    // Centres equal along one axis only (a flat layer of boxes).
    std::vector<Aabb> layer;
    std::mt19937 rng(6);
    for (int i = 0; i < 500; ++i) {
        const glm::vec3 c(std::uniform_real_distribution<float>(0, 1)(rng), 0.5f,
                          std::uniform_real_distribution<float>(0, 1)(rng));
        layer.push_back(Aabb{c - 0.01f, c + 0.01f});
    }
    expect_valid_build(layer, binary_config_with(4), "layer");
}

TEST(BvhBuilder, ExplicitCentresDrivetheBinning) {
    // Centres at the boxes' low corners, not their middles: still valid.
    const std::vector<Aabb> boxes = boxes_of(random_soup(7, 1000));
    std::vector<glm::vec3> corners;
    for (const Aabb& b : boxes) corners.push_back(b.lo);
    const Bvh bvh = build_binned_sah(boxes, corners, binary_config_with(4));
    EXPECT_EQ(validate(bvh, boxes, 4), "");
}

TEST(BvhBuilder, CollinearAndDegenerateTrianglesAreSkipped) {
    std::vector<Triangle> tris = random_soup(8, 200);
    std::size_t degenerate = 0;
    for (int i = 0; i < 50; ++i) {
        const glm::vec3 a(static_cast<float>(i), 0.5f, 0.25f);
        // Collinear along an axis, coincident vertices, and a point triangle.
        tris.push_back({a, a + glm::vec3(1, 0, 0), a + glm::vec3(2, 0, 0)});
        tris.push_back({a, a, a + glm::vec3(0, 1, 0)});
        tris.push_back({a, a, a});
        degenerate += 3;
        // Collinear along a diagonal with exactly representable steps.
        tris.push_back({a, a + glm::vec3(0.5f, 0.25f, 1), a + glm::vec3(1, 0.5f, 2)});
        ++degenerate;
        // Nearly collinear is not degenerate.
        tris.push_back({a, a + glm::vec3(1, 0, 0), a + glm::vec3(2, 1e-6f, 0)});
    }
    for (std::uint32_t leaf_size_max : {1u, 4u}) {
        const TriangleBvh accel = build_triangle_bvh(tris, binary_config_with(leaf_size_max));
        EXPECT_EQ(accel.degenerate_skipped, degenerate);
        EXPECT_EQ(accel.tris.size(), tris.size() - degenerate);
        EXPECT_EQ(validate(accel, tris, leaf_size_max), "");
    }
    // Only degenerate triangles: nothing to build.
    const std::vector<Triangle> only_degenerate(10, Triangle{glm::vec3(1), glm::vec3(1), glm::vec3(2)});
    const TriangleBvh empty = build_triangle_bvh(only_degenerate, binary_config_with(8));
    EXPECT_TRUE(empty.bvh.empty());
    EXPECT_EQ(empty.degenerate_skipped, 10u);
    EXPECT_EQ(validate(empty, only_degenerate, 8), "");
}

TEST(BvhBuilder, HugeOffsetsAndTinyScales) {
    struct Case {
        float extent, size;
        glm::vec3 offset;
    };
    const Case cases[] = {
        {1e-6f, 1e-7f, glm::vec3(0.0f)},          // tiny scene at the origin
        {1.0f, 0.05f, glm::vec3(1e6f)},           // 1e6 offset: ulp 0.0625
        {1e-6f, 1e-7f, glm::vec3(1e6f, -1e6f, 1e6f)},  // tiny scene far away: coordinates collapse
        {1e6f, 1e5f, glm::vec3(0.0f)},            // huge scene
        {1e18f, 1e17f, glm::vec3(-1e18f)},        // areas near the float limit
        {1e30f, 1e29f, glm::vec3(0.0f)},          // areas overflow to infinity
        {1e-30f, 1e-31f, glm::vec3(0.0f)},        // areas underflow to zero
    };
    for (const Case& c : cases) {
        const std::vector<Triangle> tris = random_soup(9, 2000, c.extent, c.size, c.offset);
        const std::vector<Aabb> boxes = boxes_of(tris);
        for (std::uint32_t leaf_size_max : {1u, 4u}) {
            const std::string what = "extent " + std::to_string(c.extent) + " offset " +
                                     std::to_string(c.offset.x) + " leaf " +
                                     std::to_string(leaf_size_max);
            expect_valid_build(boxes, binary_config_with(leaf_size_max), what);
            const TriangleBvh accel = build_triangle_bvh(tris, binary_config_with(leaf_size_max));
            EXPECT_EQ(validate(accel, tris, leaf_size_max), "") << what;
        }
    }
}

TEST(BvhBuilder, DepthStaysBoundedOnExponentiallySpacedPrimitives) {
    // Centres at 2^-120 ... 2^120: binning puts all but the largest in bin 0 at every level,
    // so an unguarded SAH build would peel one primitive per level (depth ~ 240).
    std::vector<Aabb> boxes;
    for (int i = -120; i <= 120; ++i) {
        const float x = std::ldexp(1.0f, i);
        boxes.push_back(Aabb{glm::vec3(x, 0, 0), glm::vec3(x * 1.5f, 1, 1)});
    }
    for (std::uint32_t leaf_size_max : {1u, 2u, 8u}) {
        const Bvh bvh = build_boxes(boxes, binary_config_with(leaf_size_max));
        EXPECT_EQ(validate(bvh, boxes, leaf_size_max), "");
        EXPECT_LE(compute_stats(bvh).depth, kMaxDepth);
    }
}

TEST(BvhBuilder, SmallerCostRatioGivesBiggerLeavesAndShallowerTrees) {
    const std::vector<Aabb> boxes = boxes_of(random_soup(10, 20000, 1.0f, 0.02f));
    const BvhStats cheap = compute_stats(build_boxes(boxes, binary_config_with(32, 0.1f)));
    const BvhStats costly = compute_stats(build_boxes(boxes, binary_config_with(32, 1.0f)));
    EXPECT_GT(cheap.leaf_prims_mean, costly.leaf_prims_mean);
    EXPECT_LT(cheap.depth, costly.depth);
    EXPECT_LT(cheap.nodes, costly.nodes);
}

TEST(BvhBuilder, LeafSizeMinMakesEveryNodeThatSmallALeaf) {
    // Over 100k primitives: the parallel and serial paths, and the small nodes' exhaustive one.
    const std::vector<Aabb> boxes = boxes_of(random_soup(12, 100000, 1.0f, 0.01f));
    const Bvh plain = build_boxes(boxes, binary_config_with(8));
    BuildConfig config = binary_config_with(8);
    // Four and eight: the static group's lean builds (lean_leaf_size_min, static_group_layout.h).
    std::size_t nodes_at_four = 0;
    for (const std::uint32_t min : {4u, 8u}) {
        SCOPED_TRACE("leaf_size_min " + std::to_string(min));
        config.leaf_size_min = min;
        const Bvh coarse = build_boxes(boxes, config);
        EXPECT_EQ(validate(coarse, boxes, config.leaf_size_max), "");
        // No inner node over `min` primitives or fewer.
        int small_inner = 0;
        const auto prims_below = [&](auto&& self, std::uint32_t i) -> std::uint32_t {
            const BvhNode& n = coarse.nodes[i];
            if (n.is_leaf()) return n.count;
            const std::uint32_t below = self(self, n.first) + self(self, n.first + 1);
            small_inner += below <= min ? 1 : 0;
            return below;
        };
        EXPECT_EQ(prims_below(prims_below, 0), boxes.size());
        EXPECT_EQ(small_inner, 0);
        EXPECT_LT(coarse.nodes.size(), (min == 4 ? plain.nodes.size() : nodes_at_four) * 7 / 10);
        nodes_at_four = coarse.nodes.size();
    }
    // Above leaf_size_max it is leaf_size_max; 0 is refused.
    config.leaf_size_min = 20;
    const Bvh capped = build_boxes(boxes, config);
    EXPECT_EQ(validate(capped, boxes, config.leaf_size_max), "");
    config.leaf_size_min = 0;
    EXPECT_THROW(build_boxes(boxes, config), std::invalid_argument);
}

TEST(BvhBuilder, ABuildThatHandsItsReferencesBackAsItGoesIsTheSameTree) {
    // Over 64 MB of references (2.2M triangles): build_triangle_bvh lets the builder hand them
    // back range by range as it finishes with them (they read as zeros after). The ids, the
    // nodes and the leaf-order copy must be those of a build that keeps its references to the
    // end (build_binned_sah over the same boxes and centres); a range handed back too early
    // would show as wrong ids.
    const std::vector<Triangle> tris = random_soup(21, 2200000, 1.0f, 0.002f);
    BuildConfig config = binary_config_with(8);
    const TriangleBvh built = build_triangle_bvh(tris, config);
    const std::vector<Aabb> boxes = boxes_of(tris);
    const Bvh kept = build_binned_sah(boxes, centers_of(boxes), config);
    ASSERT_EQ(built.degenerate_skipped, 0u);
    EXPECT_EQ(validate(built, tris, config.leaf_size_max), "");
    ASSERT_EQ(built.bvh.prim_ids.size(), kept.prim_ids.size());
    EXPECT_EQ(std::memcmp(built.bvh.prim_ids.data(), kept.prim_ids.data(), kept.prim_ids.size() * 4), 0);
    // The same tree; its nodes' places in the array may differ with thread timing.
    const auto depth_first = [](const Bvh& bvh) {
        std::vector<BvhNode> out;
        std::vector<std::uint32_t> stack{0};
        while (!stack.empty()) {
            BvhNode n = bvh.nodes[stack.back()];
            stack.pop_back();
            if (!n.is_leaf()) {
                stack.push_back(n.first + 1);
                stack.push_back(n.first);
                n.first = 0;
            }
            out.push_back(n);
        }
        return out;
    };
    const std::vector<BvhNode> a = depth_first(built.bvh), b = depth_first(kept);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(BvhNode)), 0);
}

TEST(BvhBuilder, SahCostOfAHandBuiltTree) {
    // Root [0,2]x[0,1]x[0,1] (half area 5) over two unit cubes (half area 3 each), the left
    // leaf with two primitives, the right with one.
    Bvh bvh;
    bvh.nodes.resize(3);
    bvh.nodes[0] = BvhNode{Aabb{glm::vec3(0), glm::vec3(2, 1, 1)}, 1, 0};
    bvh.nodes[1] = BvhNode{Aabb{glm::vec3(0), glm::vec3(1)}, 0, 2};
    bvh.nodes[2] = BvhNode{Aabb{glm::vec3(1, 0, 0), glm::vec3(2, 1, 1)}, 2, 1};
    bvh.prim_ids = {2, 0, 1};
    // 1 * traversal + 3/5 * 2 * isect + 3/5 * 1 * isect with traversal 1, isect 2.
    EXPECT_NEAR(sah_cost(bvh, SahCosts{1.0f, 2.0f}), 1.0 + 2.4 + 1.2, 1e-12);
    EXPECT_NEAR(sah_cost(bvh, SahCosts{0.5f, 1.0f}), 0.5 + 1.2 + 0.6, 1e-12);

    const BvhStats stats = compute_stats(bvh);
    EXPECT_EQ(stats.nodes, 3u);
    EXPECT_EQ(stats.leaves, 2u);
    EXPECT_DOUBLE_EQ(stats.leaf_prims_mean, 1.5);
    EXPECT_EQ(stats.leaf_prims_max, 2u);
    EXPECT_EQ(stats.depth, 2u);

    const std::vector<Aabb> prims = {Aabb{glm::vec3(0.5f), glm::vec3(1)},
                                     Aabb{glm::vec3(1.5f, 0, 0), glm::vec3(2, 1, 1)},
                                     Aabb{glm::vec3(0), glm::vec3(0.5f)}};
    EXPECT_EQ(validate(bvh, prims, 2), "");
    EXPECT_NE(validate(bvh, prims, 1), "");  // the two-primitive leaf exceeds 1
}

TEST(BvhBuilder, SahCostOfAFlatSceneCountsEveryNode) {
    // All boxes in the plane z = 0 along a line: zero root area, every node weighs 1.
    Bvh bvh;
    bvh.nodes = {BvhNode{Aabb{glm::vec3(0), glm::vec3(2, 0, 0)}, 1, 0},
                 BvhNode{Aabb{glm::vec3(0), glm::vec3(1, 0, 0)}, 0, 1},
                 BvhNode{Aabb{glm::vec3(1, 0, 0), glm::vec3(2, 0, 0)}, 1, 1}};
    bvh.prim_ids = {0, 1};
    EXPECT_DOUBLE_EQ(sah_cost(bvh, SahCosts{1.0f, 1.0f}), 3.0);
}

/// A valid tree to corrupt, with its primitive boxes.
struct Corruptible {
    std::vector<Aabb> boxes = boxes_of(random_soup(11, 500));
    Bvh bvh = build_boxes(boxes, binary_config_with(4));

    /// Index of some inner node other than the root, and of some leaf.
    std::uint32_t inner() const {
        for (std::uint32_t i = 1; i < bvh.nodes.size(); ++i) {
            if (!bvh.nodes[i].is_leaf()) return i;
        }
        return 0;
    }
    std::uint32_t leaf(std::uint32_t min_count = 1) const {
        for (std::uint32_t i = 0; i < bvh.nodes.size(); ++i) {
            if (bvh.nodes[i].count >= min_count) return i;
        }
        return 0;
    }
};

TEST(BvhBuilder, ValidateDetectsCorruptedTrees) {
    {
        Corruptible c;
        ASSERT_EQ(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a primitive listed twice (and another missing)
        Corruptible c;
        c.bvh.prim_ids[1] = c.bvh.prim_ids[0];
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a primitive id out of range
        Corruptible c;
        c.bvh.prim_ids[3] = 500;
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a primitive missing from prim_ids
        Corruptible c;
        c.bvh.prim_ids.pop_back();
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a child box sticking out of its parent
        Corruptible c;
        const std::uint32_t child = c.bvh.nodes[0].first;
        c.bvh.nodes[child].box.hi.x = c.bvh.nodes[0].box.hi.x + 1.0f;
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a leaf box that no longer contains its primitives
        Corruptible c;
        const std::uint32_t l = c.leaf();
        c.bvh.nodes[l].box.lo = c.bvh.nodes[l].box.hi;
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a NaN box
        Corruptible c;
        c.bvh.nodes[c.inner()].box.lo.y = std::nanf("");
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a leaf above leaf_size_max
        Corruptible c;
        EXPECT_NE(validate(c.bvh, c.boxes, 1), "");
    }
    {  // a leaf range outside prim_ids
        Corruptible c;
        c.bvh.nodes[c.leaf()].first = static_cast<std::uint32_t>(c.bvh.prim_ids.size());
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // two leaves sharing positions
        Corruptible c;
        const std::uint32_t l = c.leaf(2);
        c.bvh.nodes[l].first += 1;
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a cycle: an inner node pointing back at the root's children
        Corruptible c;
        c.bvh.nodes[c.inner()].first = c.bvh.nodes[0].first;
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // a child index pointing at the root
        Corruptible c;
        c.bvh.nodes[c.inner()].first = 0;
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // child index out of range
        Corruptible c;
        c.bvh.nodes[c.inner()].first = static_cast<std::uint32_t>(c.bvh.nodes.size() - 1);
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // an unreachable node
        Corruptible c;
        c.bvh.nodes.push_back(c.bvh.nodes.back());
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
    {  // an empty tree for a non-empty set of primitives
        Corruptible c;
        c.bvh.nodes.clear();
        EXPECT_NE(validate(c.bvh, c.boxes, 4), "");
    }
}

TEST(BvhBuilder, ValidateDetectsTreesDeeperThanTheLimit) {
    // A chain of kMaxDepth + 1 levels: every inner node has a leaf on the left and the rest of
    // the chain on the right; all boxes equal so only the depth is wrong.
    const std::uint32_t inner_count = kMaxDepth;  // leaves at depth kMaxDepth + 1
    const Aabb box{glm::vec3(0), glm::vec3(1)};
    Bvh bvh;
    bvh.nodes.push_back(BvhNode{box, 1, 0});
    for (std::uint32_t i = 0; i < inner_count; ++i) {
        const bool last = i + 1 == inner_count;
        bvh.nodes.push_back(BvhNode{box, i, 1});  // left: leaf over prim position i
        bvh.nodes.push_back(last ? BvhNode{box, i + 1, 1}
                                 : BvhNode{box, static_cast<std::uint32_t>(bvh.nodes.size() + 1), 0});
    }
    const std::uint32_t prims = inner_count + 1;
    for (std::uint32_t i = 0; i < prims; ++i) bvh.prim_ids.push_back(i);
    const std::vector<Aabb> boxes(prims, box);
    EXPECT_EQ(compute_stats(bvh).depth, kMaxDepth + 1);
    EXPECT_NE(validate(bvh, boxes, 1), "");

    // One level fewer is fine.
    Bvh shallower = bvh;
    shallower.nodes.resize(bvh.nodes.size() - 2);
    shallower.nodes.back() = BvhNode{box, inner_count - 1, 2};
    EXPECT_EQ(compute_stats(shallower).depth, kMaxDepth);
    EXPECT_EQ(validate(shallower, boxes, 2), "");
}

TEST(BvhBuilder, ValidateOfTriangleBvhDetectsBadCopies) {
    const std::vector<Triangle> tris = random_soup(12, 300);
    TriangleBvh accel = build_triangle_bvh(tris, binary_config_with(4));
    ASSERT_EQ(validate(accel, tris, 4), "");
    TriangleBvh wrong_copy = accel;
    std::swap(wrong_copy.tris[0], wrong_copy.tris[1]);
    EXPECT_NE(validate(wrong_copy, tris, 4), "");
    TriangleBvh wrong_count = accel;
    wrong_count.degenerate_skipped = 1;
    EXPECT_NE(validate(wrong_count, tris, 4), "");
    TriangleBvh missing = accel;
    missing.bvh.prim_ids.pop_back();
    missing.tris.pop_back();
    EXPECT_NE(validate(missing, tris, 4), "");
}

TEST(BvhBuilder, RejectsInvalidConfigurationsAndInputs) {
    const std::vector<Aabb> boxes = boxes_of(random_soup(13, 10));
    EXPECT_THROW(build_boxes(boxes, binary_config_with(0)), std::invalid_argument);
    EXPECT_THROW(build_boxes(boxes, binary_config_with(4, 0.0f)), std::invalid_argument);
    EXPECT_THROW(build_boxes(boxes, binary_config_with(4, -1.0f)), std::invalid_argument);
    EXPECT_THROW(build_boxes(boxes, binary_config_with(4, std::nanf(""))), std::invalid_argument);
    EXPECT_THROW(build_boxes(boxes, binary_config_with(4, 1.0f, 1)), std::invalid_argument);
    const std::vector<glm::vec3> too_few(3);
    EXPECT_THROW(build_binned_sah(boxes, too_few, BuildConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt::bvh
