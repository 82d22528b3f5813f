// The Morton-order builder (bvh/src/morton_builder.cpp): its trees are valid on every input
// shape (random and clustered soups, all centres equal, flat scenes, huge and tiny scales,
// every leaf size), shallow enough, the same whatever the thread count, reuse recycled
// storage, and trace to exactly the hits of brute force and of the binned-SAH tree (the same
// watertight test and tie rule: smallest t, then smallest index), binary and wide. Its SAH
// cost stays within a bound of the binned-SAH tree's, so a builder that degenerates (a wrong
// split search, codes not interleaved) fails here and not only in a benchmark.

#include "dynrt/bvh/morton_builder.h"
#include "dynrt/bvh/triangle_bvh.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::boxes_of;
using testing::bounds_of;
using testing::brute_force_any;
using testing::brute_force_closest;
using testing::random_direction;
using testing::random_point;
using testing::random_soup;

BuildConfig morton_config(std::uint32_t leaf_size_max = 8, bool wide = true) {
    BuildConfig config;
    config.method = BuildMethod::morton;
    config.leaf_size_max = leaf_size_max;
    config.wide = wide;
    return config;
}

/// The two wide trees' nodes hold the same bits (their padding aside).
bool same_nodes(const WideBvh& a, const WideBvh& b) {
    if (a.nodes.size() != b.nodes.size()) return false;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const WideNode<kWideWidth>& x = a.nodes[i];
        const WideNode<kWideWidth>& y = b.nodes[i];
        const bool same = std::memcmp(x.lo_x, y.lo_x, sizeof x.lo_x * 6) == 0 &&
                          std::memcmp(x.child, y.child, sizeof x.child) == 0 &&
                          std::memcmp(x.blocks, y.blocks, sizeof x.blocks) == 0;
        if (!same) return false;
    }
    return true;
}

std::vector<glm::vec3> centers_of(const std::vector<Aabb>& boxes) {
    std::vector<glm::vec3> centers;
    for (const Aabb& b : boxes) centers.push_back(b.center());
    return centers;
}

std::uint32_t depth_of(const Bvh& bvh, std::uint32_t index = 0) {
    const BvhNode& node = bvh.nodes[index];
    if (node.is_leaf()) return 1;
    return 1 + std::max(depth_of(bvh, node.first), depth_of(bvh, node.first + 1));
}

/// Rays from outside and inside the scene's box, toward triangles and at random.
std::vector<Ray> rays_for(const std::vector<Triangle>& tris, std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    const Aabb b = bounds_of(tris);
    const glm::vec3 e = glm::max(b.extent(), glm::vec3(1e-30f));
    std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        Ray r;
        r.org = random_point(rng, b.lo - e, b.hi + e);
        r.dir = i % 3 == 0 ? random_direction(rng) : tris[pick(rng)].centroid() - r.org;
        if (r.dir == glm::vec3(0.0f)) r.dir = glm::vec3(0, 0, 1);
        rays.push_back(r);
    }
    return rays;
}

/// Every ray's closest hit through the Morton tree (wide and binary) equals the binned-SAH
/// tree's and brute force's, bit for bit; any-hit answers equal brute force's.
void expect_same_hits(const std::vector<Triangle>& tris, std::uint32_t leaf_size_max,
                      const std::string& what) {
    const TriangleBvh morton = build_triangle_bvh(tris, morton_config(leaf_size_max));
    ASSERT_EQ(validate(morton, tris, std::min(leaf_size_max, 8u)), "") << what;
    const TriangleBvh morton_binary = build_triangle_bvh(tris, morton_config(leaf_size_max, false));
    ASSERT_EQ(validate(morton_binary, tris, std::min(leaf_size_max, 8u)), "") << what;
    BuildConfig sah_config;
    sah_config.leaf_size_max = leaf_size_max;
    const TriangleBvh sah = build_triangle_bvh(tris, sah_config);
    int failures = 0;
    for (const Ray& ray : rays_for(tris, 7, 400)) {
        const Hit expected = brute_force_closest(tris, ray);
        const Hit sah_hit = intersect_closest(sah, ray);
        for (const Hit& got : {intersect_closest(morton, ray), intersect_closest(morton_binary, ray)}) {
            const bool same = got.is_hit() == expected.is_hit() &&
                              (!got.is_hit() || (got.t == expected.t && got.prim == sah_hit.prim &&
                                                 got.u == sah_hit.u && got.v == sah_hit.v));
            EXPECT_TRUE(same) << what << ": morton " << got.t << " prim " << got.prim
                              << ", sah " << sah_hit.t << " prim " << sah_hit.prim
                              << ", brute force " << expected.t;
            if (!same && ++failures > 5) return;
        }
        EXPECT_EQ(intersect_any(morton, ray), brute_force_any(tris, ray)) << what;
    }
}

TEST(MortonBuilder, HitsEqualBruteForceAndTheSahTree) {
    for (std::size_t count : {1u, 2u, 5u, 100u, 3000u}) {
        for (std::uint32_t leaf : {1u, 2u, 4u, 16u}) {
            const std::string what = "n " + std::to_string(count) + " leaf " + std::to_string(leaf);
            expect_same_hits(random_soup(11, count, 1.0f, 0.06f), leaf, what);
        }
    }
    expect_same_hits(testing::icosphere_mesh(4).triangles(), 8, "icosphere");
    // Far from the origin and at tiny and huge scales: the grid is over the centres' bounds.
    expect_same_hits(random_soup(12, 2000, 1e-3f, 1e-5f, glm::vec3(1e5f)), 8, "far and tiny");
    expect_same_hits(random_soup(13, 2000, 1e6f, 1e4f), 8, "huge");
}

TEST(MortonBuilder, TreesAreValidOnEveryShapeOfInput) {
    struct Input {
        std::string name;
        std::vector<Triangle> tris;
    };
    std::vector<Input> inputs;
    inputs.push_back({"soup", random_soup(21, 5000)});
    // Every centre equal: no code bit differs, so only middle splits remain.
    inputs.push_back({"coincident", std::vector<Triangle>(5000, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})});
    // A flat scene (one axis has no extent) and a line of triangles.
    std::vector<Triangle> flat = random_soup(22, 3000);
    for (Triangle& t : flat) t.v0.z = t.v1.z = t.v2.z = 0.5f;
    inputs.push_back({"flat", flat});
    std::vector<Triangle> line;
    for (int i = 0; i < 3000; ++i) {
        const float x = float(i);
        line.push_back({{x, 0, 0}, {x + 0.5f, 1, 0}, {x, 0, 1}});
    }
    inputs.push_back({"line", line});
    // Clusters far apart: most codes share their top bits.
    std::vector<Triangle> clusters = random_soup(23, 2000, 1e-3f, 1e-4f);
    const std::vector<Triangle> far = random_soup(24, 2000, 1e-3f, 1e-4f, glm::vec3(1e4f));
    clusters.insert(clusters.end(), far.begin(), far.end());
    inputs.push_back({"clusters", clusters});
    for (const Input& input : inputs) {
        for (std::uint32_t leaf : {1u, 3u, 8u}) {
            SCOPED_TRACE(input.name + ", leaf " + std::to_string(leaf));
            const TriangleBvh accel = build_triangle_bvh(input.tris, morton_config(leaf));
            EXPECT_EQ(validate(accel, input.tris, std::min(leaf, 8u)), "");
            EXPECT_LE(compute_stats(accel).depth, kMaxDepth);
            const TriangleBvh binary = build_triangle_bvh(input.tris, morton_config(leaf, false));
            EXPECT_EQ(validate(binary, input.tris, std::min(leaf, 8u)), "");
            EXPECT_LE(depth_of(binary.bvh), kMaxDepth);
            // From boxes and centres too.
            const std::vector<Aabb> boxes = boxes_of(input.tris);
            const Bvh bvh = build_morton(boxes, centers_of(boxes), morton_config(leaf));
            EXPECT_EQ(validate(bvh, boxes, std::min(leaf, 8u)), "");
        }
    }
}

TEST(MortonBuilder, LeafOrderFollowsTheMortonCurve) {
    // Two clusters: the tree's first half of leaf positions must be one cluster, the second
    // half the other (a builder that ignored the codes would interleave them).
    std::vector<Triangle> tris = random_soup(31, 1000, 1.0f, 0.01f);
    const std::vector<Triangle> far = random_soup(32, 1000, 1.0f, 0.01f, glm::vec3(10.0f));
    tris.insert(tris.end(), far.begin(), far.end());
    const TriangleBvh accel = build_triangle_bvh(tris, morton_config(8, false));
    ASSERT_EQ(accel.bvh.prim_ids.size(), 2000u);
    std::size_t near_first = 0;
    for (std::size_t k = 0; k < 1000; ++k) near_first += accel.bvh.prim_ids[k] < 1000 ? 1 : 0;
    EXPECT_TRUE(near_first == 0 || near_first == 1000) << near_first;
    // The root splits the clusters apart.
    const BvhNode& root = accel.bvh.nodes[0];
    ASSERT_FALSE(root.is_leaf());
    const Aabb& a = accel.bvh.nodes[root.first].box;
    const Aabb& b = accel.bvh.nodes[root.first + 1].box;
    const bool apart = a.hi.x < b.lo.x || b.hi.x < a.lo.x || a.hi.y < b.lo.y || b.hi.y < a.lo.y ||
                       a.hi.z < b.lo.z || b.hi.z < a.lo.z;
    EXPECT_TRUE(apart);
}

TEST(MortonBuilder, SameTreeWhateverTheThreadCount) {
    const std::vector<Triangle> tris = random_soup(41, 60000, 1.0f, 0.01f);
    TriangleBvh one, two;
    tbb::task_arena(1).execute([&] { one = build_triangle_bvh(tris, morton_config()); });
    tbb::task_arena(2).execute([&] { two = build_triangle_bvh(tris, morton_config()); });
    EXPECT_EQ(sah_cost(one, {}), sah_cost(two, {}));
    ASSERT_EQ(one.wide.nodes.size(), two.wide.nodes.size());
    EXPECT_TRUE(same_nodes(one.wide, two.wide));
    ASSERT_EQ(one.wide.blocks.size(), two.wide.blocks.size());
    for (std::size_t i = 0; i < one.wide.blocks.size(); ++i) {
        ASSERT_EQ(0, std::memcmp(&one.wide.blocks[i], &two.wide.blocks[i], sizeof(TriangleBlock)));
    }
}

TEST(MortonBuilder, RecycledStorageGivesTheSameTree) {
    const std::vector<Triangle> big = random_soup(51, 20000);
    const std::vector<Triangle> small = random_soup(52, 3000);
    const TriangleBvh fresh = build_triangle_bvh(small, morton_config());
    TriangleBvh recycled = build_triangle_bvh(big, morton_config());
    recycled = build_triangle_bvh(small, morton_config(), std::move(recycled));
    EXPECT_EQ(validate(recycled, small, 8), "");
    ASSERT_EQ(recycled.wide.nodes.size(), fresh.wide.nodes.size());
    ASSERT_EQ(recycled.wide.blocks.size(), fresh.wide.blocks.size());
    EXPECT_TRUE(same_nodes(recycled.wide, fresh.wide));
    EXPECT_EQ(0, std::memcmp(recycled.wide.blocks.data(), fresh.wide.blocks.data(),
                             fresh.wide.blocks.size() * sizeof(TriangleBlock)));
    EXPECT_EQ(sah_cost(recycled, {}), sah_cost(fresh, {}));
}

TEST(MortonBuilder, DegenerateTrianglesAreSkippedAsByTheSahBuilder) {
    std::vector<Triangle> tris = random_soup(61, 500);
    for (std::size_t i = 0; i < tris.size(); i += 7) tris[i].v2 = tris[i].v0;
    const TriangleBvh accel = build_triangle_bvh(tris, morton_config());
    EXPECT_EQ(validate(accel, tris, 8), "");
    EXPECT_EQ(accel.degenerate_skipped, (tris.size() + 6) / 7);
    std::vector<Triangle> all_degenerate(10, Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
    const TriangleBvh none = build_triangle_bvh(all_degenerate, morton_config());
    EXPECT_TRUE(none.bvh.empty());
    EXPECT_TRUE(none.wide.empty());
    EXPECT_EQ(none.degenerate_skipped, 10u);
}

TEST(MortonBuilder, SahCostStaysNearTheBinnedSahTree) {
    // Measured: about 1.1-1.3x on these inputs for the binary trees, 1.1-1.7x for the wide
    // ones. Bounds of 1.6x and 2x still catch a builder whose splits stop following space (a
    // reversed comparison in the split search, codes with the axes not interleaved gave
    // 90-120x, a middle split everywhere 2.6x for the binary trees and 2.7-3.6x for the wide).
    const std::vector<std::pair<std::string, std::vector<Triangle>>> inputs = {
        {"icosphere", testing::icosphere_mesh(5).triangles()},
        {"soup", random_soup(71, 50000, 1.0f, 0.01f)},
    };
    for (const auto& [name, tris] : inputs) {
        for (bool wide : {false, true}) {
            BuildConfig sah_config;
            sah_config.leaf_size_max = 4;
            sah_config.wide = wide;
            const double sah = sah_cost(build_triangle_bvh(tris, sah_config), {});
            const double morton = sah_cost(build_triangle_bvh(tris, morton_config(4, wide)), {});
            EXPECT_GT(sah, 1.0) << name;
            const double bound = wide ? 2.0 : 1.6;
            EXPECT_LT(morton, bound * sah) << name << ": morton " << morton << ", sah " << sah;
            std::printf("[ SAH cost ] %s %s: morton %.2f, binned SAH %.2f (%.2fx)\n", name.c_str(),
                        wide ? "wide" : "binary", morton, sah, morton / sah);
        }
    }
}

TEST(MortonBuilder, RejectsBadInput) {
    const std::vector<Aabb> boxes(3, Aabb{{0, 0, 0}, {1, 1, 1}});
    const std::vector<glm::vec3> centers(2, glm::vec3(0.5f));
    EXPECT_THROW(build_morton(boxes, centers, morton_config()), std::invalid_argument);
    BuildConfig bad = morton_config();
    bad.leaf_size_max = 0;
    EXPECT_THROW(build_morton(boxes, std::vector<glm::vec3>(3, glm::vec3(0.5f)), bad),
                 std::invalid_argument);
    EXPECT_TRUE(build_morton({}, {}, morton_config()).empty());
}

}  // namespace
}  // namespace dynrt::bvh
