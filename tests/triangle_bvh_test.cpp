// Single-ray traversal of the triangle BVH against brute force over all triangles with the same
// watertight test: closest hits must agree bit for bit in t (and in the primitive, up to ties),
// any-hit queries exactly. Covers random soups and rays, origins inside boxes, t windows,
// zero direction components on box planes, degenerate triangles and closed meshes.

#include "dynrt/bvh/triangle_bvh.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::bounds_of;
using testing::brute_force_any;
using testing::brute_force_closest;
using testing::random_direction;
using testing::random_point;
using testing::kInf;
using testing::make_ray;
using testing::random_soup;

using testing::config_with;

/// Closest and any hit of `accel` agree with brute force over `tris` for `ray`.
::testing::AssertionResult agrees_with_brute_force(const TriangleBvh& accel,
                                                   const std::vector<Triangle>& tris,
                                                   const Ray& ray) {
    const Hit expected = brute_force_closest(tris, ray);
    const Hit got = intersect_closest(accel, ray);
    auto describe = [&] {
        return " for ray org (" + std::to_string(ray.org.x) + ", " + std::to_string(ray.org.y) +
               ", " + std::to_string(ray.org.z) + ") dir (" + std::to_string(ray.dir.x) + ", " +
               std::to_string(ray.dir.y) + ", " + std::to_string(ray.dir.z) + ") [" +
               std::to_string(ray.tmin) + ", " + std::to_string(ray.tmax) + "]";
    };
    if (expected.is_hit() != got.is_hit()) {
        return ::testing::AssertionFailure()
               << "brute force " << (expected.is_hit() ? "hits" : "misses") << ", BVH "
               << (got.is_hit() ? "hits" : "misses") << describe();
    }
    if (expected.is_hit()) {
        if (got.t != expected.t) {
            return ::testing::AssertionFailure() << "t " << got.t << " (prim " << got.prim
                                                 << ") != brute force " << expected.t << " (prim "
                                                 << expected.prim << ")" << describe();
        }
        if (got.prim != expected.prim) {
            // A tie: the BVH's primitive must be hit at exactly the same t.
            Hit check;
            const bool hit = intersect_watertight(WatertightRay(ray), tris[got.prim], ray.tmin,
                                                  ray.tmax, check);
            if (!hit || check.t != got.t || check.u != got.u || check.v != got.v) {
                return ::testing::AssertionFailure()
                       << "prim " << got.prim << " is not a tie with " << expected.prim << describe();
            }
        } else if (got.u != expected.u || got.v != expected.v) {
            return ::testing::AssertionFailure() << "barycentrics differ" << describe();
        }
    }
    if (intersect_any(accel, ray) != expected.is_hit()) {
        return ::testing::AssertionFailure() << "intersect_any disagrees" << describe();
    }
    if (brute_force_any(tris, ray) != expected.is_hit()) {
        return ::testing::AssertionFailure() << "brute-force any disagrees" << describe();
    }
    return ::testing::AssertionSuccess();
}

/// Rays of several kinds for a scene with bounds `b`: from outside through the scene, from
/// inside the scene (inside many boxes), aimed at triangle centroids (certain hits) and at
/// vertices (shared-edge cases in meshes).
std::vector<Ray> rays_for(const std::vector<Triangle>& tris, std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    const Aabb b = bounds_of(tris);
    const glm::vec3 c = b.center();
    const glm::vec3 e = glm::max(b.extent(), glm::vec3(1e-30f));
    std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        Ray r;
        switch (i % 4) {
            case 0:  // outside, toward a random point of the box
                r.org = c + e * random_direction(rng) * 1.5f;
                r.dir = random_point(rng, b.lo, b.hi) - r.org;
                break;
            case 1:  // inside, random direction
                r.org = random_point(rng, b.lo, b.hi);
                r.dir = random_direction(rng);
                break;
            case 2: {  // toward a centroid
                const Triangle& t = tris[pick(rng)];
                r.org = random_point(rng, b.lo - e, b.hi + e);
                r.dir = t.centroid() - r.org;
                break;
            }
            default: {  // toward a vertex
                const Triangle& t = tris[pick(rng)];
                r.org = random_point(rng, b.lo - e, b.hi + e);
                r.dir = (i % 8 == 3 ? t.v0 : t.v2) - r.org;
                break;
            }
        }
        if (r.dir == glm::vec3(0.0f)) r.dir = glm::vec3(0, 0, 1);
        rays.push_back(r);
    }
    return rays;
}

void expect_agreement(const std::vector<Triangle>& tris, const BuildConfig& config,
                      std::uint32_t seed, int ray_count, const std::string& what) {
    const TriangleBvh accel = build_triangle_bvh(tris, config);
    ASSERT_EQ(validate(accel, tris, config.leaf_size_max), "") << what;
    int failures = 0;
    for (const Ray& ray : rays_for(tris, seed, ray_count)) {
        const auto result = agrees_with_brute_force(accel, tris, ray);
        EXPECT_TRUE(result) << what;
        if (!result && ++failures > 5) return;
    }
}

TEST(TriangleBvh, AgreesWithBruteForceOnRandomSoups) {
    for (std::uint32_t seed : {31u, 32u}) {
        for (std::size_t count : {1u, 2u, 10u, 1000u, 4000u}) {
            const std::vector<Triangle> tris = random_soup(seed, count, 1.0f, 0.08f);
            for (std::uint32_t leaf_size_max : {1u, 4u, 16u}) {
                for (float ratio : {0.1f, 1.0f}) {
                    const std::string what = "seed " + std::to_string(seed) + " n " +
                                             std::to_string(count) + " leaf " +
                                             std::to_string(leaf_size_max) + " ratio " +
                                             std::to_string(ratio);
                    expect_agreement(tris, config_with(leaf_size_max, ratio), seed, 300, what);
                }
            }
        }
    }
}

TEST(TriangleBvh, AgreesWithBruteForceOnADenseSoup) {
    // Many overlapping triangles, so ties and near-ties in t and deep trees are common.
    const std::vector<Triangle> tris = random_soup(33, 20000, 1.0f, 0.05f);
    expect_agreement(tris, config_with(4), 33, 1000, "dense soup");
}

TEST(TriangleBvh, AgreesWithBruteForceAtHugeAndTinyScales) {
    const std::vector<Triangle> far_away = random_soup(34, 2000, 1.0f, 0.05f, glm::vec3(1e6f));
    expect_agreement(far_away, config_with(4), 34, 500, "offset 1e6");
    const std::vector<Triangle> tiny = random_soup(35, 2000, 1e-6f, 5e-8f);
    expect_agreement(tiny, config_with(4), 35, 500, "scale 1e-6");
    const std::vector<Triangle> huge = random_soup(36, 2000, 1e6f, 5e4f, glm::vec3(-5e5f));
    expect_agreement(huge, config_with(4), 36, 500, "scale 1e6");
}

TEST(TriangleBvh, AgreesWithBruteForceOnClosedMeshes) {
    const std::vector<Triangle> sphere = testing::icosphere_mesh(3, 1.0f).triangles();
    expect_agreement(sphere, config_with(4), 37, 2000, "icosphere");
    const std::vector<Triangle> cube = testing::cube_mesh(-1.0f, 2.0f).triangles();
    expect_agreement(cube, config_with(1), 38, 1000, "cube");
}

TEST(TriangleBvh, RaysFromInsideAClosedMeshAlwaysHit) {
    // Conservative box tests and the watertight test together: no ray leaks out.
    const testing::ClosedMesh mesh = testing::icosphere_mesh(4, 2.0f, glm::vec3(1.0f, -3.0f, 0.5f));
    const std::vector<Triangle> tris = mesh.triangles();
    const TriangleBvh accel = build_triangle_bvh(tris, config_with(2));
    std::mt19937 rng(39);
    const glm::vec3 inside[] = {glm::vec3(1.0f, -3.0f, 0.5f), glm::vec3(2.2f, -2.5f, 0.0f)};
    for (const glm::vec3& org : inside) {
        for (const glm::vec3& v : mesh.vertices) {
            EXPECT_TRUE(intersect_closest(accel, make_ray(org, v - org)).is_hit());
            EXPECT_TRUE(intersect_any(accel, make_ray(org, v - org)));
        }
        for (const auto& [a, b] : mesh.edges()) {
            const glm::vec3 target = 0.5f * (mesh.vertices[a] + mesh.vertices[b]);
            EXPECT_TRUE(intersect_closest(accel, make_ray(org, target - org)).is_hit());
        }
        for (int i = 0; i < 500; ++i) {
            EXPECT_TRUE(intersect_closest(accel, make_ray(org, random_direction(rng))).is_hit());
        }
    }
}

TEST(TriangleBvh, TminAndTmaxClipTheSegment) {
    // Ten parallel squares at z = 1 ... 10, each two triangles.
    std::vector<Triangle> tris;
    for (int k = 1; k <= 10; ++k) {
        const float z = static_cast<float>(k);
        tris.push_back({{-1, -1, z}, {1, -1, z}, {1, 1, z}});
        tris.push_back({{-1, -1, z}, {1, 1, z}, {-1, 1, z}});
    }
    const TriangleBvh accel = build_triangle_bvh(tris, config_with(1));
    const glm::vec3 org(0.25f, -0.5f, 0.0f);
    const glm::vec3 dir(0, 0, 1);
    auto closest_t = [&](float tmin, float tmax) {
        return intersect_closest(accel, make_ray(org, dir, tmin, tmax)).t;
    };
    EXPECT_EQ(closest_t(0.0f, kInf), 1.0f);
    EXPECT_EQ(closest_t(3.5f, kInf), 4.0f);
    EXPECT_EQ(closest_t(4.0f, kInf), 4.0f);  // inclusive tmin
    EXPECT_EQ(closest_t(std::nextafter(4.0f, 5.0f), kInf), 5.0f);
    EXPECT_EQ(closest_t(0.0f, 1.0f), 1.0f);  // inclusive tmax
    EXPECT_EQ(closest_t(2.5f, 2.9f), kInf);
    EXPECT_FALSE(intersect_closest(accel, make_ray(org, dir, 0.0f, std::nextafter(1.0f, 0.0f))).is_hit());
    EXPECT_FALSE(intersect_any(accel, make_ray(org, dir, 2.5f, 2.9f)));
    EXPECT_TRUE(intersect_any(accel, make_ray(org, dir, 2.5f, 3.0f)));
    EXPECT_FALSE(intersect_any(accel, make_ray(org, dir, 10.5f, kInf)));
    // Backwards from z = 11.
    EXPECT_EQ(intersect_closest(accel, make_ray({0.1f, 0.1f, 11.0f}, {0, 0, -2})).t, 0.5f);

    // Random windows on a soup against brute force.
    const std::vector<Triangle> soup = random_soup(40, 3000, 1.0f, 0.08f);
    const TriangleBvh soup_accel = build_triangle_bvh(soup, config_with(4));
    std::mt19937 rng(40);
    std::uniform_real_distribution<float> u(0.0f, 2.0f);
    for (Ray ray : rays_for(soup, 40, 1000)) {
        ray.tmin = u(rng);
        ray.tmax = ray.tmin + u(rng);
        EXPECT_TRUE(agrees_with_brute_force(soup_accel, soup, ray));
    }
}

TEST(TriangleBvh, ZeroDirectionComponentsOnBoxPlanes) {
    // A grid of unit squares in z = 0 with integer coordinates: node boxes have faces on the
    // grid lines, so axis-aligned rays start exactly on box planes (0 * inf in the slab test).
    std::vector<Triangle> grid;
    for (int i = 0; i < 16; ++i) {
        for (int j = 0; j < 16; ++j) {
            const float x = static_cast<float>(i), y = static_cast<float>(j);
            grid.push_back({{x, y, 0}, {x + 1, y, 0}, {x + 1, y + 1, 0}});
            grid.push_back({{x, y, 0}, {x + 1, y + 1, 0}, {x, y + 1, 0}});
        }
    }
    // Vertical walls too, so rays along x and y cross boxes lying on their planes.
    for (int i = 0; i <= 16; i += 4) {
        const float x = static_cast<float>(i);
        grid.push_back({{x, 0, 0}, {x, 16, 0}, {x, 0, 4}});
        grid.push_back({{0, x, 0}, {16, x, 4}, {0, x, 4}});
    }
    for (std::uint32_t leaf_size_max : {1u, 4u}) {
        const TriangleBvh accel = build_triangle_bvh(grid, config_with(leaf_size_max));
        for (int i = 0; i <= 16; ++i) {
            for (int j = 0; j <= 16; ++j) {
                const float x = static_cast<float>(i), y = static_cast<float>(j);
                // Straight down through grid vertices and edge midpoints: always a hit.
                for (const glm::vec3 org : {glm::vec3(x, y, 5), glm::vec3(x + 0.5f, y, 5), glm::vec3(x, y + 0.5f, 5)}) {
                    if (org.x > 16 || org.y > 16) continue;
                    for (const glm::vec3 dir : {glm::vec3(0, 0, -1), glm::vec3(-0.0f, 0.0f, -3)}) {
                        const Ray ray = make_ray(org, dir);
                        EXPECT_TRUE(agrees_with_brute_force(accel, grid, ray));
                        EXPECT_TRUE(intersect_closest(accel, ray).is_hit()) << x << "," << y;
                    }
                }
                // Along x and y inside the plane z = 0.5 and exactly in the plane z = 0.
                for (const float z : {0.0f, 0.5f}) {
                    EXPECT_TRUE(agrees_with_brute_force(accel, grid, make_ray({-1, y, z}, {1, 0, 0})));
                    EXPECT_TRUE(agrees_with_brute_force(accel, grid, make_ray({x, 17, z}, {0, -1, 0})));
                    EXPECT_TRUE(agrees_with_brute_force(accel, grid, make_ray({x, y, z}, {0, 1, 0})));
                }
            }
        }
    }
}

TEST(TriangleBvh, DegenerateTrianglesAreSkippedAndNeverHit) {
    std::vector<Triangle> tris = random_soup(41, 500, 1.0f, 0.08f);
    std::vector<std::uint32_t> degenerate_ids;
    std::mt19937 rng(41);
    for (int i = 0; i < 100; ++i) {
        const glm::vec3 a = random_point(rng, glm::vec3(0), glm::vec3(1));
        const glm::vec3 d = random_point(rng, glm::vec3(-0.1f), glm::vec3(0.1f));
        degenerate_ids.push_back(static_cast<std::uint32_t>(tris.size()));
        tris.push_back(i % 2 ? Triangle{a, a, a + d} : Triangle{a, a + d, a + 2.0f * d});
    }
    std::size_t expected_skipped = 0;
    for (const Triangle& t : tris) expected_skipped += is_degenerate(t) ? 1 : 0;
    ASSERT_GE(expected_skipped, 50u);
    const TriangleBvh accel = build_triangle_bvh(tris, config_with(4));
    EXPECT_EQ(accel.degenerate_skipped, expected_skipped);
    EXPECT_EQ(validate(accel, tris, 4), "");
    for (const std::uint32_t id : degenerate_ids) {
        if (!is_degenerate(tris[id])) continue;
        for (int k = 0; k < 10; ++k) {
            const glm::vec3 target = tris[id].v1;
            const glm::vec3 org = target - random_direction(rng);
            const Ray ray = make_ray(org, target - org);
            const Hit hit = intersect_closest(accel, ray);
            EXPECT_NE(hit.prim, id);
            EXPECT_TRUE(agrees_with_brute_force(accel, tris, ray));
        }
    }
}

TEST(TriangleBvh, EmptyAndSingleTriangleAccelerators) {
    const TriangleBvh empty = build_triangle_bvh({}, BuildConfig{});
    const Ray ray = make_ray({0.25f, 0.25f, 1}, {0, 0, -1});
    EXPECT_FALSE(intersect_closest(empty, ray).is_hit());
    EXPECT_FALSE(intersect_any(empty, ray));

    const std::vector<Triangle> one = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    const TriangleBvh single = build_triangle_bvh(one, BuildConfig{});
    const Hit hit = intersect_closest(single, ray);
    ASSERT_TRUE(hit.is_hit());
    EXPECT_EQ(hit.prim, 0u);
    EXPECT_EQ(hit.t, 1.0f);
    EXPECT_EQ(hit.u, 0.25f);
    EXPECT_EQ(hit.v, 0.25f);
    EXPECT_TRUE(intersect_any(single, ray));
    EXPECT_FALSE(intersect_any(single, make_ray({2, 2, 1}, {0, 0, -1})));
}

TEST(TriangleBvh, HitsReportTheCallersIndices) {
    // Triangles listed far from leaf order; each ray aims at one triangle's centroid from
    // straight above, where nothing else is.
    std::vector<Triangle> tris;
    for (int i = 99; i >= 0; --i) {
        const float x = static_cast<float>((i * 37) % 100);
        tris.push_back({{x, 0, 0}, {x + 0.5f, 0, 0}, {x, 0.5f, 0}});
    }
    const TriangleBvh accel = build_triangle_bvh(tris, config_with(2));
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
        const glm::vec3 c = tris[i].centroid();
        const Hit hit = intersect_closest(accel, make_ray(c + glm::vec3(0, 0, 1), {0, 0, -1}));
        ASSERT_TRUE(hit.is_hit());
        EXPECT_EQ(hit.prim, i);
    }
}

TEST(TriangleBvh, CountingTraversalReportsWorkAndTheSameHits) {
    const std::vector<Triangle> tris = random_soup(42, 2000, 1.0f, 0.05f);
    const TriangleBvh accel = build_triangle_bvh(tris, config_with(4));
    TraversalStats stats;
    int hits = 0;
    const std::vector<Ray> rays = rays_for(tris, 42, 400);
    for (const Ray& ray : rays) {
        const Hit plain = intersect_closest(accel, ray);
        const Hit counted = intersect_closest(accel, ray, stats);
        EXPECT_EQ(plain.t, counted.t);
        EXPECT_EQ(plain.prim, counted.prim);
        hits += plain.is_hit() ? 1 : 0;
    }
    EXPECT_GT(hits, 100);
    // Every ray that meets the root visits it; hits need at least a leaf with a triangle.
    EXPECT_GE(stats.nodes_visited, static_cast<std::uint64_t>(hits));
    EXPECT_GE(stats.triangles_tested, static_cast<std::uint64_t>(hits));
    // Far fewer tests than brute force.
    EXPECT_LT(stats.triangles_tested, rays.size() * tris.size() / 10);
}

}  // namespace
}  // namespace dynrt::bvh
