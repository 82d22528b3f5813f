// The wide tree (bvh/include/dynrt/bvh/wide_bvh.h) at both widths: collapsed from the binary
// tree, it must give the binary tree's hits bit for bit (t, u, v and the primitive, ties
// included) and the same any-hit answers, before and after refits; validate must hold after
// every build and refit and must catch a corrupted tree; refitted boxes must be tight.

#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/wide_bvh.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::bounds_of;
using testing::brute_force_closest;
using testing::make_ray;
using testing::random_direction;
using testing::random_point;
using testing::random_soup;

BuildConfig binary_config(std::uint32_t leaf_size_max, float cost_ratio = 1.0f) {
    BuildConfig c;
    c.leaf_size_max = leaf_size_max;
    c.cost_ratio = cost_ratio;
    c.wide = false;
    return c;
}

std::vector<Ray> random_rays(const std::vector<Triangle>& tris, std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    const Aabb b = bounds_of(tris);
    const glm::vec3 e = glm::max(b.extent(), glm::vec3(1e-30f));
    std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        Ray r;
        const Triangle& t = tris[pick(rng)];
        switch (i % 4) {
            case 0: r.org = random_point(rng, b.lo - e, b.hi + e); r.dir = t.centroid() - r.org; break;
            case 1: r.org = random_point(rng, b.lo, b.hi); r.dir = random_direction(rng); break;
            case 2: r.org = random_point(rng, b.lo - e, b.hi + e); r.dir = t.v1 - r.org; break;
            default:  // a window in t, so tmin and tmax cut through the scene
                r.org = random_point(rng, b.lo - e, b.hi + e);
                r.dir = random_direction(rng);
                r.tmin = unit(rng) * glm::length(e);
                r.tmax = r.tmin + unit(rng) * glm::length(e);
                break;
        }
        if (r.dir == glm::vec3(0.0f)) r.dir = glm::vec3(0, 0, 1);
        rays.push_back(r);
    }
    // Axis-parallel rays, whose zero direction components meet box planes.
    for (int i = 0; i < count / 8; ++i) {
        Ray r;
        r.org = tris[pick(rng)].v0;
        r.org[i % 3] = b.lo[i % 3] - e[i % 3];
        r.dir = glm::vec3(0.0f);
        r.dir[i % 3] = 1.0f;
        rays.push_back(r);
    }
    return rays;
}

std::string describe(const Ray& r) {
    return "ray org (" + std::to_string(r.org.x) + ", " + std::to_string(r.org.y) + ", " +
           std::to_string(r.org.z) + ") dir (" + std::to_string(r.dir.x) + ", " +
           std::to_string(r.dir.y) + ", " + std::to_string(r.dir.z) + ")";
}

/// The wide tree gives the binary tree's answers bit for bit on `rays` (`binary` built without
/// a wide tree, so it traces its binary tree); returns the failures.
template <int N>
int count_disagreements(const WideBvhOf<N>& wide, const TriangleBvh& binary,
                        const std::vector<Ray>& rays, const std::string& what) {
    int failures = 0;
    for (const Ray& ray : rays) {
        const Hit expected = intersect_closest(binary, ray);
        const Hit got = intersect_closest(wide, ray);
        const bool same = std::memcmp(&expected, &got, sizeof(Hit)) == 0;
        const bool any_same = intersect_any(wide, ray) == intersect_any(binary, ray);
        if (!same || !any_same) {
            if (++failures <= 3) {
                ADD_FAILURE() << what << ": " << describe(ray) << ": binary t " << expected.t
                              << " prim " << expected.prim << ", wide t " << got.t << " prim "
                              << got.prim << (any_same ? "" : " (any-hit differs)");
            }
        }
    }
    return failures;
}

template <class T>
class WideBvhTest : public ::testing::Test {};
template <int N>
struct Width {
    static constexpr int value = N;
};
using Widths = ::testing::Types<Width<4>, Width<8>>;
TYPED_TEST_SUITE(WideBvhTest, Widths);

TYPED_TEST(WideBvhTest, GivesTheBinaryTreesHitsBitForBit) {
    constexpr int N = TypeParam::value;
    struct Case {
        std::string name;
        std::vector<Triangle> tris;
    };
    std::vector<Case> cases = {
        {"small soup", random_soup(51, 7, 1.0f, 0.3f)},
        {"soup", random_soup(52, 3000, 1.0f, 0.06f)},
        {"dense soup", random_soup(53, 8000, 1.0f, 0.2f)},
        {"far soup", random_soup(54, 1500, 1.0f, 0.05f, glm::vec3(1e6f))},
        {"icosphere", testing::icosphere_mesh(4, 1.0f).triangles()},
        {"cube", testing::cube_mesh(-1.0f, 2.0f).triangles()},
    };
    // Exact duplicates at other indices: every hit on them is a tie the lower index must win.
    std::vector<Triangle> duplicated = random_soup(55, 500, 1.0f, 0.1f);
    for (int i = 0; i < 500; i += 3) duplicated.push_back(duplicated[static_cast<std::size_t>(i)]);
    cases.push_back({"duplicates", duplicated});
    for (const Case& c : cases) {
        for (std::uint32_t leaf : {1u, 4u, 8u, 32u}) {
            for (float ratio : {0.3f, 1.0f}) {
                const std::string what = c.name + " leaf " + std::to_string(leaf) + " ratio " +
                                          std::to_string(ratio) + " N " + std::to_string(N);
                const TriangleBvh binary = build_triangle_bvh(c.tris, binary_config(leaf, ratio));
                const WideBvhOf<N> wide = collapse_to_wide<N>(binary.bvh, binary.tris);
                ASSERT_EQ(validate(wide, c.tris, binary.bvh.prim_ids), "") << what;
                EXPECT_EQ(count_disagreements(wide, binary, random_rays(c.tris, leaf, 600), what), 0);
                // From the caller's triangles through the ids: the same tree, byte for byte.
                const WideBvhOf<N> by_id = collapse_to_wide_by_id<N>(binary.bvh, c.tris);
                ASSERT_EQ(by_id.nodes.size(), wide.nodes.size()) << what;
                ASSERT_EQ(by_id.blocks.size(), wide.blocks.size()) << what;
                // Each node's fields, not its padding (left unwritten).
                const std::size_t used = offsetof(WideNode<N>, blocks) + sizeof(wide.nodes[0].blocks);
                for (std::size_t k = 0; k < wide.nodes.size(); ++k) {
                    ASSERT_EQ(std::memcmp(&by_id.nodes[k], &wide.nodes[k], used), 0) << what << " node " << k;
                }
                EXPECT_EQ(std::memcmp(by_id.blocks.data(), wide.blocks.data(), wide.blocks.size() * sizeof(TriangleBlock)), 0)
                    << what;
                EXPECT_EQ(by_id.triangle_count, wide.triangle_count) << what;
                if constexpr (N == kWideWidth) {
                    // As build_triangle_bvh collapses, freeing its binary tree before it writes
                    // the blocks: the same tree again.
                    BuildConfig config = binary_config(leaf, ratio);
                    config.wide = true;
                    const WideBvhOf<N> built = build_triangle_bvh(c.tris, config).wide;
                    ASSERT_EQ(built.nodes.size(), wide.nodes.size()) << what;
                    ASSERT_EQ(built.blocks.size(), wide.blocks.size()) << what;
                    for (std::size_t k = 0; k < wide.nodes.size(); ++k) {
                        ASSERT_EQ(std::memcmp(&built.nodes[k], &wide.nodes[k], used), 0) << what << " node " << k;
                    }
                    EXPECT_EQ(std::memcmp(built.blocks.data(), wide.blocks.data(), wide.blocks.size() * sizeof(TriangleBlock)), 0)
                        << what;
                }
            }
        }
    }
}

/// The subtree queries continue a hit: visiting the root's children one by one, each query
/// starting from the hit the previous ones found (ray.tmax shortened to it), ends with the
/// whole tree's hit bit for bit, in either order of the children, and any hit below some child
/// exactly when the whole tree has one.
TYPED_TEST(WideBvhTest, SubtreeQueriesContinueAHitToTheWholeTreesHit) {
    constexpr int N = TypeParam::value;
    const std::vector<Triangle> tris = random_soup(61, 3000, 1.0f, 0.08f);
    const TriangleBvh binary = build_triangle_bvh(tris, binary_config(4));
    const WideBvhOf<N> wide = collapse_to_wide<N>(binary.bvh, binary.tris);
    const WideNode<N>& root = wide.nodes[0];
    int hits = 0;
    for (const Ray& ray : random_rays(tris, 62, 800)) {
        const Hit expected = intersect_closest(wide, ray);
        for (bool reversed : {false, true}) {
            Hit hit;
            bool any = false;
            WideTraversalStats work;
            for (int j = 0; j < N; ++j) {
                const int i = reversed ? N - 1 - j : j;
                if (root.is_empty(i)) continue;
                const WideSubtree below{root.child[i], root.blocks[i]};
                Ray shortened = ray;
                if (hit.is_hit()) shortened.tmax = hit.t;
                const Hit before = hit;
                if (!intersect_closest(wide, below, shortened, hit, &work)) {
                    EXPECT_EQ(std::memcmp(&before, &hit, sizeof(Hit)), 0)
                        << describe(ray) << ": a query that found nothing changed the hit";
                }
                any = intersect_any(wide, below, ray) || any;
            }
            ASSERT_EQ(std::memcmp(&expected, &hit, sizeof(Hit)), 0)
                << describe(ray) << ": whole tree t " << expected.t << " prim " << expected.prim
                << ", by subtrees t " << hit.t << " prim " << hit.prim;
            EXPECT_EQ(any, intersect_any(wide, ray)) << describe(ray);
            EXPECT_GT(work.nodes_visited + work.leaves_visited, 0u);
        }
        hits += expected.is_hit() ? 1 : 0;
    }
    EXPECT_GT(hits, 100);
}

TYPED_TEST(WideBvhTest, MatchesBruteForceWithDegenerateTriangles) {
    constexpr int N = TypeParam::value;
    std::vector<Triangle> tris = random_soup(56, 400, 1.0f, 0.1f);
    for (std::size_t i = 0; i < tris.size(); i += 5) tris[i].v2 = tris[i].v1;  // zero area
    for (std::size_t i = 2; i < tris.size(); i += 7) {                          // collinear
        tris[i].v2 = tris[i].v0 + 2.0f * (tris[i].v1 - tris[i].v0);
    }
    const TriangleBvh binary = build_triangle_bvh(tris, binary_config(4));
    const WideBvhOf<N> wide = collapse_to_wide<N>(binary.bvh, binary.tris);
    ASSERT_EQ(validate(wide, tris, binary.bvh.prim_ids), "");
    for (const Ray& ray : random_rays(tris, 56, 1000)) {
        const Hit expected = brute_force_closest(tris, ray);
        const Hit got = intersect_closest(wide, ray);
        ASSERT_EQ(got.is_hit(), expected.is_hit()) << describe(ray);
        if (got.is_hit()) {
            EXPECT_EQ(got.t, expected.t) << describe(ray);
        }
    }
}

TYPED_TEST(WideBvhTest, EmptyAndTinyTrees) {
    constexpr int N = TypeParam::value;
    const TriangleBvh empty = build_triangle_bvh(std::vector<Triangle>{}, binary_config(4));
    const WideBvhOf<N> wide_empty = collapse_to_wide<N>(empty.bvh, empty.tris);
    EXPECT_TRUE(wide_empty.empty());
    EXPECT_EQ(validate(wide_empty, std::vector<Triangle>{}, empty.bvh.prim_ids), "");
    EXPECT_FALSE(intersect_closest(wide_empty, make_ray(glm::vec3(0), glm::vec3(0, 0, 1))).is_hit());
    EXPECT_FALSE(intersect_any(wide_empty, make_ray(glm::vec3(0), glm::vec3(0, 0, 1))));

    const std::vector<Triangle> one = {{{-1, -1, 2}, {1, -1, 2}, {0, 1, 2}}};
    const TriangleBvh binary = build_triangle_bvh(one, binary_config(4));
    const WideBvhOf<N> wide = collapse_to_wide<N>(binary.bvh, binary.tris);
    ASSERT_EQ(validate(wide, one, binary.bvh.prim_ids), "");
    ASSERT_EQ(wide.nodes.size(), 1u);
    const Hit hit = intersect_closest(wide, make_ray(glm::vec3(0), glm::vec3(0, 0, 1)));
    EXPECT_EQ(hit.prim, 0u);
    EXPECT_EQ(hit.t, 2.0f);
}

TYPED_TEST(WideBvhTest, CollapseUsesTheWidthAndMergesSmallLeaves) {
    constexpr int N = TypeParam::value;
    // A closed mesh: neighbouring triangles share their parent's box almost entirely, so one
    // block over several one-triangle binary leaves is cheaper under the SAH than a slot each.
    const std::vector<Triangle> tris = testing::icosphere_mesh(5, 1.0f).triangles();
    const TriangleBvh binary = build_triangle_bvh(tris, binary_config(1));
    const WideBvhOf<N> wide = collapse_to_wide<N>(binary.bvh, binary.tris);
    ASSERT_EQ(validate(wide, tris, binary.bvh.prim_ids), "");
    const WideStats stats = compute_stats(wide);
    const BvhStats binary_stats = compute_stats(binary.bvh);
    // One-triangle binary leaves are merged into blocks: far fewer leaves, fuller blocks.
    EXPECT_LT(stats.leaves, binary_stats.leaves / 2) << stats.block_fill;
    EXPECT_GT(stats.block_fill, 0.5) << stats.leaves;
    EXPECT_GT(stats.children_mean, N / 2.0);
    EXPECT_LT(stats.nodes, binary_stats.nodes / N);
    // No leaf above leaf_prims_max (16) once merged: the binary leaves here hold one.
    for (const WideNode<N>& node : wide.nodes) {
        for (int i = 0; i < N; ++i) {
            if (node.is_leaf(i)) {
                EXPECT_LE(node.blocks[i], 4);
            }
        }
    }
}

TYPED_TEST(WideBvhTest, RefitKeepsTheBinaryTreesHitsAndTightBoxes) {
    constexpr int N = TypeParam::value;
    const testing::ClosedMesh mesh = testing::icosphere_mesh(4, 1.0f);
    std::vector<Triangle> tris = mesh.triangles();
    TriangleBvh binary = build_triangle_bvh(tris, binary_config(4));
    WideBvhOf<N> wide = collapse_to_wide<N>(binary.bvh, binary.tris);
    std::mt19937 rng(58);
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    for (int frame = 0; frame < 3; ++frame) {
        // Move every vertex of the mesh (shared vertices move together, so it stays closed).
        std::vector<glm::vec3> moved = mesh.vertices;
        for (glm::vec3& v : moved) v += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
        for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
            tris[f] = {moved[mesh.faces[f][0]], moved[mesh.faces[f][1]], moved[mesh.faces[f][2]]};
        }
        ASSERT_FALSE(refit(binary, tris, SahCosts{}).needs_rebuild());
        const SahCosts costs{1.0f, 1.5f};
        // The refit's SAH cost is sah_cost's, bit for bit, and it changes with the boxes.
        const double before = sah_cost(wide, costs);
        const double refitted = refit_wide(wide, tris, costs).sah_cost;
        EXPECT_EQ(refitted, sah_cost(wide, costs));
        EXPECT_NE(refitted, before);
        EXPECT_GT(refitted, costs.traversal);
        const std::string what = "frame " + std::to_string(frame);
        ASSERT_EQ(validate(wide, tris, binary.bvh.prim_ids), "") << what;
        EXPECT_EQ(count_disagreements(wide, binary, random_rays(tris, 58 + frame, 800), what), 0);
        // Tight: each slot box is exactly the union of what lies below it.
        for (const WideNode<N>& node : wide.nodes) {
            for (int i = 0; i < N; ++i) {
                if (node.is_empty(i)) continue;
                Aabb below;
                if (node.is_leaf(i)) {
                    for (std::uint32_t b = node.child[i]; b < node.child[i] + node.blocks[i]; ++b) {
                        for (int lane = 0; lane < kBlockLanes; ++lane) {
                            if (wide.blocks[b].prim[lane] != kInvalidId) {
                                below.extend(wide.blocks[b].triangle(lane).bounds());
                            }
                        }
                    }
                } else {
                    const WideNode<N>& child = wide.nodes[node.child[i]];
                    for (int j = 0; j < N; ++j) {
                        if (!child.is_empty(j)) below.extend(child.box(j));
                    }
                }
                ASSERT_TRUE(node.box(i).contains(below) && below.contains(node.box(i))) << what;
            }
        }
    }
}

TYPED_TEST(WideBvhTest, ValidateCatchesCorruption) {
    constexpr int N = TypeParam::value;
    const std::vector<Triangle> tris = random_soup(59, 2000, 1.0f, 0.05f);
    const TriangleBvh binary = build_triangle_bvh(tris, binary_config(4));
    const WideBvhOf<N> good = collapse_to_wide<N>(binary.bvh, binary.tris);
    ASSERT_EQ(validate(good, tris, binary.bvh.prim_ids), "");
    auto first_inner_slot = [&](const WideBvhOf<N>& w) {
        for (int i = 0; i < N; ++i) {
            if (!w.nodes[0].is_empty(i) && !w.nodes[0].is_leaf(i)) return i;
        }
        return -1;
    };
    const int inner = first_inner_slot(good);
    ASSERT_GE(inner, 0);
    {
        WideBvhOf<N> w = good;  // a slot box shrunk below its children
        w.nodes[0].hi_x[inner] = w.nodes[0].lo_x[inner];
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    {
        WideBvhOf<N> w = good;  // a triangle moved without a refit
        w.blocks[0].v0[1][0] += 0.5f;
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    {
        WideBvhOf<N> w = good;  // a primitive twice, another missing
        w.blocks[1].prim[0] = w.blocks[0].prim[0];
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    {
        WideBvhOf<N> w = good;  // a child index pointing back up
        w.nodes[0].child[inner] = 0;
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    {
        WideBvhOf<N> w = good;  // an empty slot before a used one
        w.nodes[0].child[0] = kInvalidId;
        w.nodes[0].blocks[0] = 0;
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    {
        WideBvhOf<N> w = good;  // a leaf reaching past the blocks
        for (WideNode<N>& node : w.nodes) {
            for (int i = 0; i < N; ++i) {
                if (node.is_leaf(i)) node.child[i] = static_cast<std::uint32_t>(w.blocks.size());
            }
        }
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    {
        WideBvhOf<N> w = good;  // a triangle count that is not the blocks'
        w.triangle_count += 1;
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
        EXPECT_THROW(refit_wide(w, tris, SahCosts{}), std::invalid_argument);
    }
    {
        WideBvhOf<N> w = good;  // an unused lane marked used again
        bool marked = false;
        for (TriangleBlock& block : w.blocks) {
            if (!marked && block.prim[kBlockLanes - 1] == kInvalidId) {
                block.prim[kBlockLanes - 1] = block.prim[0];
                marked = true;
            }
        }
        ASSERT_TRUE(marked);
        EXPECT_NE(validate(w, tris, binary.bvh.prim_ids), "");
    }
    // A refit throws on a primitive out of range instead of reading past the triangles.
    WideBvhOf<N> w = good;
    w.blocks[0].prim[0] = static_cast<std::uint32_t>(tris.size());
    EXPECT_THROW(refit_wide(w, tris, SahCosts{}), std::invalid_argument);
}

TEST(WideBvh, TriangleBvhTracesItsWideTreeAndCountsTheWork) {
    const std::vector<Triangle> tris = random_soup(60, 5000, 1.0f, 0.04f);
    BuildConfig config;
    const TriangleBvh accel = build_triangle_bvh(tris, config);
    ASSERT_FALSE(accel.wide.empty());
    // The binary tree it was collapsed from is not kept.
    EXPECT_TRUE(accel.bvh.empty());
    EXPECT_TRUE(accel.tris.empty());
    EXPECT_EQ(accel.triangle_count(), tris.size());
    ASSERT_EQ(validate(accel, tris, config.leaf_size_max), "");
    config.wide = false;
    const TriangleBvh binary_only = build_triangle_bvh(tris, config);
    EXPECT_TRUE(binary_only.wide.empty());
    TraversalStats wide_work, binary_work;
    int hits = 0;
    for (const Ray& ray : random_rays(tris, 60, 500)) {
        const Hit a = intersect_closest(accel, ray, wide_work);
        const Hit b = intersect_closest(binary_only, ray, binary_work);
        ASSERT_EQ(std::memcmp(&a, &b, sizeof(Hit)), 0) << describe(ray);
        EXPECT_EQ(intersect_any(accel, ray), intersect_any(binary_only, ray)) << describe(ray);
        hits += a.is_hit() ? 1 : 0;
    }
    EXPECT_GT(hits, 100);
    // The wide tree visits fewer nodes per ray than the binary one.
    EXPECT_GT(wide_work.nodes_visited, 0u);
    EXPECT_LT(wide_work.nodes_visited, binary_work.nodes_visited);
    EXPECT_GT(wide_work.triangles_tested, 0u);

    // A refit through the TriangleBvh refits the wide tree too.
    std::vector<Triangle> moved = tris;
    for (Triangle& t : moved) {
        t.v0.y += 0.01f;
        t.v1.y += 0.01f;
        t.v2.y += 0.01f;
    }
    TriangleBvh refitted = accel;
    const RefitResult result = refit(refitted, moved, config.sah_costs());
    ASSERT_FALSE(result.needs_rebuild());
    EXPECT_EQ(result.sah_cost, sah_cost(refitted, config.sah_costs()));
    EXPECT_EQ(validate(refitted, moved, config.leaf_size_max), "");
    // A stale tree (the triangles moved, no refit) fails validation.
    EXPECT_NE(validate(accel, moved, config.leaf_size_max), "");
    // A refit with the wrong number of triangles is refused before anything changes.
    moved.pop_back();
    EXPECT_THROW(refit(refitted, moved, config.sah_costs()), std::invalid_argument);
}

/// cover_boxes: at most the parts asked for, together holding every triangle, the largest of
/// them smaller as more are allowed; the same for the binary tree.
TEST(WideBvh, CoverBoxesHoldEveryTriangleInAtMostTheAskedParts) {
    const std::vector<Triangle> tris = random_soup(63, 4000, 1.0f, 0.02f);
    for (bool wide : {true, false}) {
        BuildConfig config;
        config.wide = wide;
        const TriangleBvh accel = build_triangle_bvh(tris, config);
        double previous_area = 0.0;
        for (std::size_t parts : {1u, 8u, 16u, 64u}) {
            std::vector<Aabb> boxes;
            cover_boxes(accel, parts, boxes);
            ASSERT_FALSE(boxes.empty());
            EXPECT_LE(boxes.size(), parts) << wide;
            for (const Triangle& t : tris) {
                bool held = false;
                for (const Aabb& b : boxes) held = held || b.contains(t.bounds());
                ASSERT_TRUE(held) << "wide " << wide << " parts " << parts;
            }
            double largest = 0.0;
            for (const Aabb& b : boxes) largest = std::max(largest, static_cast<double>(b.half_area()));
            if (parts == 1) {
                EXPECT_EQ(boxes.size(), 1u);
            } else {
                EXPECT_GT(boxes.size(), parts / 2) << "wide " << wide << " parts " << parts;
                EXPECT_LT(largest, previous_area) << "wide " << wide << " parts " << parts;
            }
            previous_area = largest;
        }
    }
    std::vector<Aabb> none;
    cover_boxes(build_triangle_bvh(std::vector<Triangle>{}, BuildConfig{}), 8, none);
    EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace dynrt::bvh
