// Refit of triangle and plain BVHs: after every motion (jitter, wave, large translation,
// collapse to a point) the tree satisfies validate, its boxes equal bit for bit those of a
// plain serial refit written here, closest hits agree with brute force over all triangles, and
// the reported SAH cost is sah_cost's. A refit of the build's own triangles gives back the
// build's boxes; skipped degenerate triangles that gain area and wrong counts are refused.

#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <oneapi/tbb/task_arena.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::bounds_of;
using testing::boxes_of;
using testing::brute_force_any;
using testing::brute_force_closest;
using testing::make_ray;
using testing::random_direction;
using testing::random_point;
using testing::random_soup;

/// These tests check the binary tree itself.
using testing::binary_config_with;

using Motion = std::function<glm::vec3(const glm::vec3&)>;


/// Applies `motion` to every vertex. A pure function of the position, so vertices shared by
/// neighbouring triangles of a closed mesh stay bit-identical (the mesh stays watertight).
std::vector<Triangle> moved(const std::vector<Triangle>& tris, const Motion& motion) {
    std::vector<Triangle> out;
    out.reserve(tris.size());
    for (const Triangle& t : tris) out.push_back({motion(t.v0), motion(t.v1), motion(t.v2)});
    return out;
}

/// A pseudo-random offset in [-amount, amount]^3 that depends only on the point's bits.
glm::vec3 noise(const glm::vec3& p, float amount) {
    std::uint32_t h = 0x811c9dc5u;
    glm::vec3 offset;
    for (int pass = 0; pass < 2; ++pass) {
        for (int a = 0; a < 3; ++a) {
            h = (h ^ std::bit_cast<std::uint32_t>(p[a])) * 0x01000193u;
            h ^= h >> 13;
            h *= 0x5bd1e995u;
            h ^= h >> 15;
            if (pass == 1) offset[a] = amount * (static_cast<float>(h >> 8) / 8388608.0f - 1.0f);
        }
    }
    return offset;
}

struct NamedMotion {
    std::string name;
    Motion motion;
};

/// The motions of the issue: small random jitter, a wave, a large translation of everything,
/// a translation of half the scene (boxes stretch, the SAH cost grows), a collapse to a point.
std::vector<NamedMotion> motions() {
    return {
        {"jitter", [](const glm::vec3& p) { return p + noise(p, 0.02f); }},
        {"wave",
         [](const glm::vec3& p) {
             return p + glm::vec3(0.0f, 0.2f * std::sin(6.0f * p.x + 1.0f), 0.05f * std::cos(4.0f * p.z));
         }},
        {"translate", [](const glm::vec3& p) { return p + glm::vec3(1000.0f, -500.0f, 2000.0f); }},
        {"tear", [](const glm::vec3& p) { return p.x > 0.5f ? p + glm::vec3(0.0f, 40.0f, 0.0f) : p; }},
        {"collapse", [](const glm::vec3&) { return glm::vec3(0.25f, 0.5f, 0.75f); }},
    };
}

/// The scenes: soups small and large (the large ones take the parallel path) and a closed mesh
/// away from the origin (no zero coordinates, so no +0/-0 ties can differ between min orders).
struct NamedScene {
    std::string name;
    std::vector<Triangle> tris;
    std::uint32_t leaf_size_max;
};

std::vector<NamedScene> scenes() {
    return {
        {"soup 1", random_soup(51, 1), 4},
        {"soup 300", random_soup(52, 300, 1.0f, 0.08f), 1},
        {"soup 30000", random_soup(53, 30000, 1.0f, 0.03f), 4},
        {"icosphere 5",
         testing::icosphere_mesh(5, 0.45f, glm::vec3(0.55f, 0.45f, 0.5f)).triangles(), 8},
    };
}

bool same_bits(const Aabb& a, const Aabb& b) { return std::memcmp(&a, &b, sizeof(Aabb)) == 0; }

std::string box_text(const Aabb& b) {
    return "[(" + std::to_string(b.lo.x) + ", " + std::to_string(b.lo.y) + ", " +
           std::to_string(b.lo.z) + "), (" + std::to_string(b.hi.x) + ", " +
           std::to_string(b.hi.y) + ", " + std::to_string(b.hi.z) + ")]";
}

/// The plain serial refit the library's must match bit for bit: recursion from the root, a
/// leaf's box the union of its primitives' boxes in leaf order, an inner node's the union of
/// its left then right child's.
Aabb reference_refit(std::vector<Aabb>& out, const Bvh& bvh, std::uint32_t index,
                     const std::function<Aabb(std::uint32_t)>& prim_box) {
    const BvhNode& node = bvh.nodes[index];
    Aabb box;
    if (node.is_leaf()) {
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            box.extend(prim_box(bvh.prim_ids[k]));
        }
    } else {
        box = reference_refit(out, bvh, node.first, prim_box);
        box.extend(reference_refit(out, bvh, node.first + 1, prim_box));
    }
    out[index] = box;
    return box;
}

std::vector<Aabb> reference_boxes(const Bvh& bvh, std::span<const Triangle> tris) {
    std::vector<Aabb> out(bvh.nodes.size());
    if (!bvh.empty()) {
        reference_refit(out, bvh, 0, [&](std::uint32_t id) { return tris[id].bounds(); });
    }
    return out;
}

/// Node boxes of `bvh` equal `expected` bit for bit; names the first node that differs.
::testing::AssertionResult boxes_equal_bits(const Bvh& bvh, const std::vector<Aabb>& expected) {
    if (bvh.nodes.size() != expected.size()) {
        return ::testing::AssertionFailure() << bvh.nodes.size() << " nodes, expected "
                                             << expected.size();
    }
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (!same_bits(bvh.nodes[i].box, expected[i])) {
            return ::testing::AssertionFailure() << "node " << i << " box " << box_text(bvh.nodes[i].box)
                                                 << ", expected " << box_text(expected[i]);
        }
    }
    return ::testing::AssertionSuccess();
}

/// Node boxes equal as float values (so +0 and -0 compare equal), topology unchanged.
::testing::AssertionResult boxes_equal_values(const Bvh& got, const Bvh& expected) {
    if (got.nodes.size() != expected.nodes.size() || got.prim_ids != expected.prim_ids) {
        return ::testing::AssertionFailure() << "different topology";
    }
    for (std::size_t i = 0; i < got.nodes.size(); ++i) {
        const BvhNode& a = got.nodes[i];
        const BvhNode& b = expected.nodes[i];
        if (a.box.lo != b.box.lo || a.box.hi != b.box.hi || a.first != b.first || a.count != b.count) {
            return ::testing::AssertionFailure() << "node " << i << " box " << box_text(a.box)
                                                 << ", expected " << box_text(b.box);
        }
    }
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult sah_matches(double reported, const Bvh& bvh, const SahCosts& costs) {
    const double expected = sah_cost(bvh, costs);
    if (std::fabs(reported - expected) <= 1e-9 * expected) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "refit reported SAH " << reported << ", sah_cost gives "
                                         << expected;
}

/// Rays through the scene of `tris`: from outside toward random points of its bounds, from
/// inside in random directions, and toward triangle centroids (certain hits).
std::vector<Ray> rays_through(const std::vector<Triangle>& tris, std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    const Aabb b = bounds_of(tris);
    const glm::vec3 e = glm::max(b.extent(), glm::vec3(1e-3f));
    std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        Ray r;
        switch (i % 3) {
            case 0:
                r.org = b.center() + 1.5f * e * random_direction(rng);
                r.dir = random_point(rng, b.lo, b.hi) - r.org;
                break;
            case 1:
                r.org = random_point(rng, b.lo, b.hi);
                r.dir = random_direction(rng);
                break;
            default:
                r.org = random_point(rng, b.lo - e, b.hi + e);
                r.dir = tris[pick(rng)].centroid() - r.org;
                break;
        }
        if (r.dir == glm::vec3(0.0f)) r.dir = glm::vec3(0.0f, 0.0f, 1.0f);
        rays.push_back(r);
    }
    return rays;
}

/// Closest and any hit of `accel` agree with brute force over `tris`; returns the hit count.
int expect_hits_agree(const TriangleBvh& accel, const std::vector<Triangle>& tris, int ray_count,
                      const std::string& what) {
    int hits = 0, failures = 0;
    for (const Ray& ray : rays_through(tris, 61, ray_count)) {
        const Hit expected = brute_force_closest(tris, ray);
        const Hit got = intersect_closest(accel, ray);
        hits += expected.is_hit() ? 1 : 0;
        bool ok = got.is_hit() == expected.is_hit() && got.t == expected.t;
        if (ok && got.is_hit() && got.prim != expected.prim) {
            // A tie in t: the tree's triangle must be hit at exactly that t.
            Hit check;
            ok = intersect_watertight(WatertightRay(ray), tris[got.prim], ray.tmin, ray.tmax, check) &&
                 check.t == got.t;
        }
        ok = ok && intersect_any(accel, ray) == brute_force_any(tris, ray);
        EXPECT_TRUE(ok) << what << ": BVH t " << got.t << " prim " << got.prim << ", brute force t "
                        << expected.t << " prim " << expected.prim;
        if (!ok && ++failures > 5) break;
    }
    return hits;
}

TEST(BvhRefit, UnchangedTrianglesGiveTheBuildsBoxes) {
    for (const NamedScene& scene : scenes()) {
        const BuildConfig config = binary_config_with(scene.leaf_size_max);
        const TriangleBvh built = build_triangle_bvh(scene.tris, config);
        TriangleBvh accel = built;
        // Scramble the copies first, so the refit must rewrite them.
        for (Triangle& t : accel.tris) t = Triangle{};
        for (BvhNode& n : accel.bvh.nodes) n.box = Aabb{};
        const RefitResult result = refit(accel, scene.tris, config.sah_costs());
        EXPECT_EQ(result.status, RefitStatus::refitted) << scene.name;
        EXPECT_FALSE(result.needs_rebuild()) << scene.name;
        EXPECT_TRUE(boxes_equal_values(accel.bvh, built.bvh)) << scene.name;
        EXPECT_EQ(std::memcmp(accel.tris.data(), built.tris.data(), built.tris.size() * sizeof(Triangle)), 0)
            << scene.name;
        EXPECT_EQ(validate(accel, scene.tris, scene.leaf_size_max), "") << scene.name;
        EXPECT_TRUE(sah_matches(result.sah_cost, built.bvh, config.sah_costs())) << scene.name;
    }
}

TEST(BvhRefit, EveryMotionGivesAValidTreeMatchingASerialRefitAndBruteForce) {
    for (const NamedScene& scene : scenes()) {
        const BuildConfig config = binary_config_with(scene.leaf_size_max, 0.5f);
        const TriangleBvh built = build_triangle_bvh(scene.tris, config);
        ASSERT_EQ(built.degenerate_skipped, 0u) << scene.name;
        for (const NamedMotion& m : motions()) {
            const std::string what = scene.name + ", " + m.name;
            const std::vector<Triangle> tris = moved(scene.tris, m.motion);
            TriangleBvh accel = built;
            const RefitResult result = refit(accel, tris, config.sah_costs());
            ASSERT_EQ(result.status, RefitStatus::refitted) << what;
            EXPECT_EQ(validate(accel, tris, scene.leaf_size_max), "") << what;
            EXPECT_TRUE(boxes_equal_bits(accel.bvh, reference_boxes(accel.bvh, tris))) << what;
            EXPECT_EQ(accel.bvh.prim_ids, built.bvh.prim_ids) << what;
            EXPECT_TRUE(sah_matches(result.sah_cost, accel.bvh, config.sah_costs())) << what;

            std::size_t became_degenerate = 0;
            for (const Triangle& t : tris) became_degenerate += is_degenerate(t) ? 1 : 0;
            if (m.name == "collapse") {
                // Every triangle is a point: nothing can be hit, by the tree or brute force.
                EXPECT_EQ(became_degenerate, tris.size()) << what;
                EXPECT_EQ(expect_hits_agree(accel, tris, 100, what), 0) << what;
                continue;
            }
            // Brute force skips degenerate triangles, the refitted tree still holds them: the
            // comparison below is only exact while the motion made none.
            ASSERT_EQ(became_degenerate, 0u) << what;
            const int hits = expect_hits_agree(accel, tris, 300, what);
            EXPECT_GT(hits, 50) << what;  // the rays do reach the moved triangles

            // Refitting back to the build's triangles restores the build's boxes.
            refit(accel, scene.tris, config.sah_costs());
            EXPECT_TRUE(boxes_equal_values(accel.bvh, built.bvh)) << what;
        }
    }
}

TEST(BvhRefit, ParallelRefitEqualsOneThreadRefitBitForBit) {
    // Large enough for many tasks; a one-thread arena runs the same code serially.
    const std::vector<Triangle> tris = random_soup(54, 60000, 1.0f, 0.02f);
    const BuildConfig config = binary_config_with(2);
    const TriangleBvh built = build_triangle_bvh(tris, config);
    for (const NamedMotion& m : motions()) {
        const std::vector<Triangle> after = moved(tris, m.motion);
        TriangleBvh parallel = built;
        TriangleBvh serial = built;
        const RefitResult parallel_result = refit(parallel, after, config.sah_costs());
        RefitResult serial_result;
        tbb::task_arena(1).execute([&] { serial_result = refit(serial, after, config.sah_costs()); });
        ASSERT_EQ(parallel.bvh.nodes.size(), serial.bvh.nodes.size());
        for (std::size_t i = 0; i < parallel.bvh.nodes.size(); ++i) {
            ASSERT_TRUE(same_bits(parallel.bvh.nodes[i].box, serial.bvh.nodes[i].box))
                << m.name << ", node " << i;
        }
        EXPECT_EQ(std::bit_cast<std::uint64_t>(parallel_result.sah_cost),
                  std::bit_cast<std::uint64_t>(serial_result.sah_cost))
            << m.name;
        EXPECT_TRUE(boxes_equal_bits(parallel.bvh, reference_boxes(parallel.bvh, after))) << m.name;
    }
}

TEST(BvhRefit, SahCostGrowsWhenTheMotionStretchesBoxes) {
    const std::vector<Triangle> tris = random_soup(55, 5000, 1.0f, 0.03f);
    const BuildConfig config = binary_config_with(4);
    TriangleBvh accel = build_triangle_bvh(tris, config);
    const double built_cost = sah_cost(accel.bvh, config.sah_costs());
    // Every other triangle swaps places with a far one: boxes grow to span the scene.
    std::vector<Triangle> shuffled = tris;
    for (std::size_t i = 0; i + 2500 < shuffled.size(); i += 2) std::swap(shuffled[i], shuffled[i + 2500]);
    const RefitResult result = refit(accel, shuffled, config.sah_costs());
    EXPECT_TRUE(sah_matches(result.sah_cost, accel.bvh, config.sah_costs()));
    EXPECT_GT(result.sah_cost, 3.0 * built_cost);
    EXPECT_GT(result.sah_cost, sah_cost(build_triangle_bvh(shuffled, config).bvh, config.sah_costs()));
    EXPECT_EQ(validate(accel, shuffled, 4), "");

    // Collapsed to a point, every weight is 1, as in sah_cost.
    const std::vector<Triangle> point = moved(tris, [](const glm::vec3&) { return glm::vec3(1.0f); });
    const RefitResult flat = refit(accel, point, SahCosts{1.0f, 2.0f});
    const double inner = static_cast<double>((accel.bvh.nodes.size() - 1) / 2);
    EXPECT_EQ(flat.sah_cost, inner + 2.0 * static_cast<double>(tris.size()));
    EXPECT_EQ(flat.sah_cost, sah_cost(accel.bvh, SahCosts{1.0f, 2.0f}));
}

/// A soup plus degenerate triangles: `coincident` ones (two equal vertices, degenerate under
/// any motion of points) and `collinear` ones.
struct SoupWithDegenerates {
    std::vector<Triangle> tris;
    std::vector<std::uint32_t> coincident, collinear;
};

SoupWithDegenerates soup_with_degenerates(std::size_t count) {
    SoupWithDegenerates s{random_soup(56, count, 1.0f, 0.05f), {}, {}};
    std::mt19937 rng(56);
    for (std::size_t i = 0; i < s.tris.size(); i += 7) {
        const glm::vec3 a = random_point(rng, glm::vec3(0.1f), glm::vec3(0.9f));
        const glm::vec3 d = random_point(rng, glm::vec3(0.01f), glm::vec3(0.05f));
        if ((i / 7) % 2 == 0) {
            s.tris[i] = Triangle{a, a + d, a};
            s.coincident.push_back(static_cast<std::uint32_t>(i));
        } else {
            // Only where rounding kept the points exactly collinear: an almost collinear sliver
            // could turn degenerate under the motions below, and brute force would then skip a
            // triangle the tree still holds.
            const Triangle t{a, a + d, a + 2.0f * d};
            if (!is_degenerate(t)) continue;
            s.tris[i] = t;
            s.collinear.push_back(static_cast<std::uint32_t>(i));
        }
    }
    return s;
}

TEST(BvhRefit, SkippedTrianglesAreRecordedAndStayOutWhileDegenerate) {
    const SoupWithDegenerates s = soup_with_degenerates(20000);
    ASSERT_GT(s.collinear.size(), 100u);
    const TriangleBvh built = build_triangle_bvh(s.tris, binary_config_with(4));
    EXPECT_EQ(built.degenerate_skipped, s.coincident.size() + s.collinear.size());
    std::vector<std::uint32_t> expected_ids;
    for (std::uint32_t i = 0; i < s.tris.size(); ++i) {
        if (is_degenerate(s.tris[i])) expected_ids.push_back(i);
    }
    EXPECT_EQ(built.skipped_ids, expected_ids);
    EXPECT_EQ(validate(built, s.tris, 4), "");

    // Moving only the other triangles (and the coincident ones, which stay degenerate) is a
    // plain refit; the skipped triangles stay out and the tree stays valid.
    std::vector<Triangle> after = moved(s.tris, [](const glm::vec3& p) { return p + noise(p, 0.01f); });
    for (const std::uint32_t id : s.collinear) after[id] = s.tris[id];
    TriangleBvh accel = built;
    const RefitResult result = refit(accel, after, SahCosts{});
    EXPECT_EQ(result.status, RefitStatus::refitted);
    EXPECT_EQ(result.triangle_with_area, kInvalidId);
    EXPECT_EQ(accel.skipped_ids, built.skipped_ids);
    EXPECT_EQ(accel.degenerate_skipped, built.degenerate_skipped);
    EXPECT_EQ(validate(accel, after, 4), "");
    EXPECT_TRUE(boxes_equal_bits(accel.bvh, reference_boxes(accel.bvh, after)));
    EXPECT_GT(expect_hits_agree(accel, after, 300, "degenerates kept out"), 50);
}

TEST(BvhRefit, ASkippedTriangleGainingAreaNeedsARebuildAndChangesNothing) {
    const SoupWithDegenerates s = soup_with_degenerates(20000);
    const TriangleBvh built = build_triangle_bvh(s.tris, binary_config_with(4));
    std::vector<Triangle> after = moved(s.tris, [](const glm::vec3& p) { return p + glm::vec3(0.5f); });
    for (const std::uint32_t id : s.collinear) after[id] = s.tris[id];
    // Two skipped triangles get area; the lower index is reported.
    const std::uint32_t first = s.collinear[s.collinear.size() / 2];
    const std::uint32_t second = s.coincident.back();
    ASSERT_LT(first, second);
    after[second].v2 += glm::vec3(0.0f, 0.0f, 0.1f);
    after[first].v1 += glm::vec3(0.0f, 1e-3f, 0.0f);
    ASSERT_FALSE(is_degenerate(after[first]));
    ASSERT_FALSE(is_degenerate(after[second]));

    TriangleBvh accel = built;
    const RefitResult result = refit(accel, after, SahCosts{});
    EXPECT_TRUE(result.needs_rebuild());
    EXPECT_EQ(result.status, RefitStatus::skipped_triangle_has_area);
    EXPECT_EQ(result.triangle_with_area, first);
    // Untouched: still the tree of the build's triangles.
    EXPECT_TRUE(boxes_equal_bits(accel.bvh, reference_boxes(built.bvh, s.tris)));
    EXPECT_EQ(std::memcmp(accel.tris.data(), built.tris.data(), built.tris.size() * sizeof(Triangle)), 0);
    EXPECT_EQ(validate(accel, s.tris, 4), "");

    // A rebuild takes the triangle in.
    const TriangleBvh rebuilt = build_triangle_bvh(after, binary_config_with(4));
    EXPECT_EQ(rebuilt.degenerate_skipped, built.degenerate_skipped - 2);
    EXPECT_EQ(validate(rebuilt, after, 4), "");
    const glm::vec3 target = after[first].centroid();
    const Ray ray = make_ray(target + glm::vec3(0.0f, 0.0f, 3.0f), glm::vec3(0.0f, 0.0f, -1.0f));
    EXPECT_EQ(intersect_closest(rebuilt, ray).t, brute_force_closest(after, ray).t);
}

TEST(BvhRefit, TreesOfOnlyDegenerateTriangles) {
    const std::vector<Triangle> points(5, Triangle{glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(2.0f)});
    TriangleBvh accel = build_triangle_bvh(points, binary_config_with(8));
    ASSERT_TRUE(accel.bvh.empty());
    EXPECT_EQ(accel.skipped_ids, (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(validate(accel, points, 8), "");
    const RefitResult still = refit(accel, moved(points, [](const glm::vec3& p) { return 2.0f * p; }),
                                    SahCosts{});
    EXPECT_EQ(still.status, RefitStatus::refitted);
    EXPECT_EQ(still.sah_cost, 0.0);

    std::vector<Triangle> opened = points;
    opened[3].v1 = glm::vec3(1.0f, 2.0f, 1.0f);
    const RefitResult result = refit(accel, opened, SahCosts{});
    EXPECT_EQ(result.status, RefitStatus::skipped_triangle_has_area);
    EXPECT_EQ(result.triangle_with_area, 3u);

    TriangleBvh empty = build_triangle_bvh({}, binary_config_with(8));
    EXPECT_EQ(refit(empty, {}, SahCosts{}).status, RefitStatus::refitted);
}

TEST(BvhRefit, WrongCountsAndMalformedTreesThrow) {
    const std::vector<Triangle> tris = random_soup(57, 100);
    const TriangleBvh built = build_triangle_bvh(tris, binary_config_with(4));
    TriangleBvh accel = built;
    const std::vector<Triangle> fewer(tris.begin(), tris.end() - 1);
    std::vector<Triangle> more = tris;
    more.push_back(tris[0]);
    EXPECT_THROW(refit(accel, fewer, SahCosts{}), std::invalid_argument);
    EXPECT_THROW(refit(accel, more, SahCosts{}), std::invalid_argument);
    EXPECT_THROW(refit(accel, std::span<const Triangle>{}, SahCosts{}), std::invalid_argument);
    EXPECT_TRUE(boxes_equal_bits(accel.bvh, reference_boxes(built.bvh, tris)));

    TriangleBvh no_ids = built;
    no_ids.degenerate_skipped = 1;  // claims a skipped triangle it has no id for
    std::vector<Triangle> one_more = tris;
    one_more.push_back(tris[0]);
    EXPECT_THROW(refit(no_ids, one_more, SahCosts{}), std::invalid_argument);

    TriangleBvh bad_child = built;
    ASSERT_FALSE(bad_child.bvh.nodes[0].is_leaf());
    bad_child.bvh.nodes[0].first = static_cast<std::uint32_t>(bad_child.bvh.nodes.size());
    EXPECT_THROW(refit(bad_child, tris, SahCosts{}), std::invalid_argument);

    TriangleBvh cycle = built;
    for (BvhNode& n : cycle.bvh.nodes) {
        if (n.is_leaf()) {
            n = BvhNode{n.box, 1, 0};  // every leaf becomes an inner node over nodes 1 and 2
        }
    }
    EXPECT_THROW(refit(cycle, tris, SahCosts{}), std::invalid_argument);

    const std::vector<Aabb> boxes = boxes_of(tris);
    std::vector<glm::vec3> centers;
    for (const Aabb& b : boxes) centers.push_back(b.center());
    Bvh boxes_tree = build_binned_sah(boxes, centers, binary_config_with(4));
    EXPECT_THROW(refit(boxes_tree, std::span<const Aabb>(boxes).first(99), SahCosts{}),
                 std::invalid_argument);
}

TEST(BvhRefit, PlainBvhFromBoxes) {
    const std::vector<Triangle> tris = random_soup(58, 20000, 1.0f, 0.03f);
    const std::vector<Aabb> boxes = boxes_of(tris);
    std::vector<glm::vec3> centers;
    for (const Aabb& b : boxes) centers.push_back(b.center());
    const BuildConfig config = binary_config_with(4);
    const Bvh built = build_binned_sah(boxes, centers, config);

    Bvh bvh = built;
    const RefitResult same = refit(bvh, boxes, config.sah_costs());
    EXPECT_EQ(same.status, RefitStatus::refitted);
    EXPECT_TRUE(boxes_equal_values(bvh, built));
    EXPECT_TRUE(sah_matches(same.sah_cost, built, config.sah_costs()));

    for (const NamedMotion& m : motions()) {
        const std::vector<Aabb> after = boxes_of(moved(tris, m.motion));
        const RefitResult result = refit(bvh, after, config.sah_costs());
        EXPECT_EQ(validate(bvh, after, 4), "") << m.name;
        std::vector<Aabb> expected(bvh.nodes.size());
        reference_refit(expected, bvh, 0, [&](std::uint32_t id) { return after[id]; });
        EXPECT_TRUE(boxes_equal_bits(bvh, expected)) << m.name;
        EXPECT_TRUE(sah_matches(result.sah_cost, bvh, config.sah_costs())) << m.name;
    }
}

}  // namespace
}  // namespace dynrt::bvh
