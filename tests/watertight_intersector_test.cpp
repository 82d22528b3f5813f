// The watertight ray/triangle test: barycentrics and t, both faces, inclusive t range, zero
// direction components, degenerate triangles, and the property that gives it its name: rays
// through shared edges and vertices of closed meshes and fans never slip through.

#include "dynrt/bvh/watertight_intersector.h"

#include "bvh_test_geometry.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace dynrt::bvh {
namespace {

using testing::ClosedMesh;
using testing::count_hits;
using testing::random_direction;
using testing::kInf;
using testing::make_ray;
using testing::random_point;

bool intersect(const Ray& ray, const Triangle& tri, Hit& hit) {
    return intersect_watertight(WatertightRay(ray), tri, ray.tmin, ray.tmax, hit);
}

const Triangle kUnit{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

TEST(Watertight, HitsTheInteriorWithDocumentedBarycentrics) {
    Hit hit;
    ASSERT_TRUE(intersect(make_ray({0.25f, 0.5f, 1.0f}, {0, 0, -1}), kUnit, hit));
    EXPECT_FLOAT_EQ(hit.t, 1.0f);
    // p = (1-u-v) v0 + u v1 + v v2 with v1 = +x, v2 = +y.
    EXPECT_FLOAT_EQ(hit.u, 0.25f);
    EXPECT_FLOAT_EQ(hit.v, 0.5f);
    EXPECT_EQ(hit.prim, kInvalidId);  // left to the caller
}

TEST(Watertight, MissesOutsideTheTriangle) {
    Hit hit;
    EXPECT_FALSE(intersect(make_ray({0.75f, 0.5f, 1.0f}, {0, 0, -1}), kUnit, hit));
    EXPECT_FALSE(intersect(make_ray({-0.1f, 0.5f, 1.0f}, {0, 0, -1}), kUnit, hit));
    EXPECT_FALSE(intersect(make_ray({0.25f, -0.01f, 1.0f}, {0, 0, -1}), kUnit, hit));
    // Pointing away.
    EXPECT_FALSE(intersect(make_ray({0.25f, 0.25f, 1.0f}, {0, 0, 1}), kUnit, hit));
}

TEST(Watertight, BothFacesAreHit) {
    Hit front, back;
    ASSERT_TRUE(intersect(make_ray({0.2f, 0.3f, 2.0f}, {0, 0, -1}), kUnit, front));
    ASSERT_TRUE(intersect(make_ray({0.2f, 0.3f, -2.0f}, {0, 0, 1}), kUnit, back));
    EXPECT_FLOAT_EQ(front.t, 2.0f);
    EXPECT_FLOAT_EQ(back.t, 2.0f);
    EXPECT_FLOAT_EQ(front.u, back.u);
    EXPECT_FLOAT_EQ(front.v, back.v);
}

TEST(Watertight, BarycentricsReproduceTheHitPoint) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        const Triangle tri{random_point(rng, glm::vec3(-1), glm::vec3(1)),
                           random_point(rng, glm::vec3(-1), glm::vec3(1)),
                           random_point(rng, glm::vec3(-1), glm::vec3(1))};
        float a = u01(rng), b = u01(rng);
        if (a + b > 1.0f) {
            a = 1.0f - a;
            b = 1.0f - b;
        }
        const glm::vec3 target = (1.0f - a - b) * tri.v0 + a * tri.v1 + b * tri.v2;
        const glm::vec3 org = random_point(rng, glm::vec3(-3), glm::vec3(3));
        const glm::vec3 dir = target - org;
        const glm::vec3 n = glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
        // Skip grazing rays, whose barycentrics are ill-conditioned.
        if (std::fabs(glm::dot(glm::normalize(n), glm::normalize(dir))) < 0.1f) continue;
        Hit hit;
        ASSERT_TRUE(intersect(make_ray(org, dir), tri, hit)) << i;
        ++hits;
        EXPECT_NEAR(hit.t, 1.0f, 1e-4f) << i;
        EXPECT_NEAR(hit.u, a, 1e-4f) << i;
        EXPECT_NEAR(hit.v, b, 1e-4f) << i;
        const glm::vec3 from_t = org + hit.t * dir;
        const glm::vec3 from_uv = (1.0f - hit.u - hit.v) * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
        EXPECT_LT(glm::length(from_t - from_uv), 1e-4f) << i;
    }
    EXPECT_GT(hits, 1000);
}

TEST(Watertight, AxisAlignedRaysWithZeroDirectionComponents) {
    const Triangle in_xy{{0, 0, 3}, {2, 0, 3}, {0, 2, 3}};
    const Triangle in_yz{{5, 0, 0}, {5, 2, 0}, {5, 0, 2}};
    const Triangle in_xz{{0, -4, 0}, {0, -4, 2}, {2, -4, 0}};
    Hit hit;
    ASSERT_TRUE(intersect(make_ray({0.5f, 0.5f, 0}, {0, 0, 1}), in_xy, hit));
    EXPECT_EQ(hit.t, 3.0f);
    ASSERT_TRUE(intersect(make_ray({0, 0.5f, 0.5f}, {1, 0, 0}), in_yz, hit));
    EXPECT_EQ(hit.t, 5.0f);
    ASSERT_TRUE(intersect(make_ray({0.5f, 0, 0.5f}, {0, -2, 0}), in_xz, hit));
    EXPECT_EQ(hit.t, 2.0f);  // t in units of |dir|
    // Negative zeros and negative directions.
    ASSERT_TRUE(intersect(make_ray({0.5f, 0.5f, 10}, {-0.0f, 0.0f, -1}), in_xy, hit));
    EXPECT_EQ(hit.t, 7.0f);
    EXPECT_FALSE(intersect(make_ray({0.5f, 0.5f, 10}, {0, 0, 1}), in_xy, hit));
    EXPECT_FALSE(intersect(make_ray({3.0f, 0.5f, 0}, {0, 0, 1}), in_xy, hit));
    // Exactly on a vertex and an edge along axis-aligned rays.
    ASSERT_TRUE(intersect(make_ray({0, 0, 0}, {0, 0, 1}), in_xy, hit));
    EXPECT_EQ(hit.u, 0.0f);
    EXPECT_EQ(hit.v, 0.0f);
    ASSERT_TRUE(intersect(make_ray({1, 0, 0}, {0, 0, 1}), in_xy, hit));
    EXPECT_EQ(hit.u, 0.5f);
    EXPECT_EQ(hit.v, 0.0f);
}

TEST(Watertight, TRangeEndpointsAreInclusive) {
    const Triangle tri{{-1, -1, 2}, {3, -1, 2}, {-1, 3, 2}};
    const Ray base = make_ray({0, 0, 0}, {0, 0, 1});
    Hit hit;
    Ray r = base;
    r.tmax = 2.0f;
    EXPECT_TRUE(intersect(r, tri, hit));
    EXPECT_EQ(hit.t, 2.0f);
    r.tmax = std::nextafter(2.0f, 0.0f);
    EXPECT_FALSE(intersect(r, tri, hit));
    r = base;
    r.tmin = 2.0f;
    EXPECT_TRUE(intersect(r, tri, hit));
    r.tmin = std::nextafter(2.0f, 3.0f);
    EXPECT_FALSE(intersect(r, tri, hit));
    r = base;
    r.tmin = 2.0f;
    r.tmax = 2.0f;
    EXPECT_TRUE(intersect(r, tri, hit));
    // Behind the origin is outside [0, inf).
    r = make_ray({0, 0, 3}, {0, 0, 1});
    EXPECT_FALSE(intersect(r, tri, hit));
    r.tmin = -5.0f;
    ASSERT_TRUE(intersect(r, tri, hit));
    EXPECT_EQ(hit.t, -1.0f);
}

TEST(Watertight, HitsExactlyOnVerticesAndEdges) {
    // Directions with power-of-two ratios make the shear exact, so these rays pass exactly
    // through the vertex or edge point: edge functions are exactly zero there.
    const Triangle tri{{1, 2, 3}, {5, 2, 3}, {1, 6, 3}};
    const glm::vec3 dirs[] = {{0, 0, 1}, {0.5f, 0.25f, 1}, {-1, 2, 4}, {1, 1, -1}};
    const glm::vec3 targets[] = {tri.v0, tri.v1, tri.v2, {3, 2, 3}, {3, 4, 3}, {1, 4, 3}};
    for (const glm::vec3& d : dirs) {
        for (const glm::vec3& p : targets) {
            const glm::vec3 org = p - 4.0f * d;
            Hit hit;
            ASSERT_TRUE(intersect(make_ray(org, d), tri, hit)) << p.x << "," << p.y;
            EXPECT_EQ(hit.t, 4.0f);
            const glm::vec3 from_uv = (1.0f - hit.u - hit.v) * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
            EXPECT_EQ(from_uv, p);
        }
    }
}

TEST(Watertight, RaysInTheTrianglePlaneMiss) {
    Hit hit;
    // det == 0: the ray lies in the plane z = 0 and crosses the triangle.
    EXPECT_FALSE(intersect(make_ray({-1, 0.25f, 0}, {1, 0, 0}), kUnit, hit));
    EXPECT_FALSE(intersect(make_ray({-1, -1, 0}, {1, 1, 0}), kUnit, hit));
}

TEST(Watertight, DegenerateTrianglesAreNeverHit) {
    // Two coincident vertices project to the same point, which makes one edge function exactly
    // zero and the other two exact negatives: det = 0 for every ray. A triangle collinear
    // along an axis projects onto an exact line whenever that axis is not the ray's dominant
    // one (kz), and the edge functions' signs then follow the vertex order along the line,
    // never all equal. (A general collinear triangle may project, after rounding, onto a sliver
    // of nonzero area; that is why triangle BVHs leave degenerate triangles out.)
    struct Case {
        Triangle tri;
        int line_axis;  // -1: coincident vertices, any ray
    };
    const glm::vec3 a(0.5f, 0.25f, 1.0f);
    const Case cases[] = {
        {{a, a, a}, -1},
        {{a, a, a + glm::vec3(1, 0, 0)}, -1},
        {{a, a + glm::vec3(0.3f, 0.7f, -0.1f), a}, -1},
        {{a + glm::vec3(0.3f, 0.7f, -0.1f), a, a}, -1},
        {{a, a + glm::vec3(1, 0, 0), a + glm::vec3(2, 0, 0)}, 0},
        {{a, a + glm::vec3(0, 0, 0.5f), a + glm::vec3(0, 0, -1)}, 2},
        {{a + glm::vec3(0, 0.1f, 0), a + glm::vec3(0, 0.7f, 0), a}, 1},
    };
    std::mt19937 rng(22);
    int tested = 0;
    for (const Case& c : cases) {
        const Triangle& tri = c.tri;
        ASSERT_TRUE(is_degenerate(tri));
        const glm::vec3 targets[] = {tri.v0, tri.v1, tri.v2, (tri.v0 + tri.v1) * 0.5f,
                                     (tri.v1 + tri.v2) * 0.5f};
        for (const glm::vec3& target : targets) {
            for (int i = 0; i < 300; ++i) {
                const glm::vec3 d = random_direction(rng);
                const Ray ray = make_ray(target - 3.0f * d, d);
                if (c.line_axis >= 0 && WatertightRay(ray).kz == c.line_axis) continue;
                Hit hit;
                EXPECT_FALSE(intersect(ray, tri, hit));
                ++tested;
            }
            for (const glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, -1)}) {
                Hit hit;
                EXPECT_FALSE(intersect(make_ray(target - 2.0f * d, d), tri, hit));
            }
        }
    }
    EXPECT_GT(tested, 5000);
}

TEST(Watertight, IsDegenerateIsExact) {
    EXPECT_TRUE(is_degenerate({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}}));
    EXPECT_TRUE(is_degenerate({{1e6f, 0, 0}, {1e6f, 0, 0}, {0, 1, 0}}));
    // The smallest possible deviation from collinearity is not degenerate.
    EXPECT_FALSE(is_degenerate({{0, 0, 0}, {1, 1, 1}, {3, 3, std::nextafter(3.0f, 4.0f)}}));
    EXPECT_FALSE(is_degenerate({{0, 0, 0}, {1e-20f, 0, 0}, {0, 1e-20f, 0}}));
    EXPECT_FALSE(is_degenerate(kUnit));
    EXPECT_TRUE(is_finite(kUnit));
    EXPECT_FALSE(is_finite({{0, 0, 0}, {kInf, 0, 0}, {0, 1, 0}}));
    EXPECT_FALSE(is_finite({{0, 0, 0}, {0, 0, 0}, {0, std::nanf(""), 0}}));
}

/// Every ray from `org` toward `target` must hit at least `min_hits` triangles of `tris`.
void expect_hits(const std::vector<Triangle>& tris, glm::vec3 org, glm::vec3 target, int min_hits,
                 const char* what) {
    const Ray ray = make_ray(org, target - org);
    EXPECT_GE(count_hits(tris, ray), min_hits)
        << what << ": org (" << org.x << ", " << org.y << ", " << org.z << ") target ("
        << target.x << ", " << target.y << ", " << target.z << ")";
}

TEST(Watertight, RaysThroughTheSharedEdgesOfAFanHitAtLeastOneTriangle) {
    // Seven triangles around a centre vertex, tilted out of any axis plane, irregular ring.
    const glm::vec3 centre(0.137f, -0.219f, 0.311f);
    std::vector<glm::vec3> ring;
    for (int i = 0; i < 7; ++i) {
        const float angle = 2.0f * 3.14159265f * (static_cast<float>(i) + 0.3f * std::sin(i * 1.7f)) / 7.0f;
        const float r = 1.0f + 0.3f * std::cos(i * 2.3f);
        ring.push_back(centre + glm::vec3(r * std::cos(angle), 0.4f * r * std::sin(angle),
                                          r * std::sin(angle) + 0.2f * r * std::cos(angle)));
    }
    std::vector<Triangle> fan;
    for (int i = 0; i < 7; ++i) fan.push_back({centre, ring[i], ring[(i + 1) % 7]});

    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u01(0.05f, 0.95f);
    for (int i = 0; i < 3000; ++i) {
        // Origins on both sides, far and near.
        const glm::vec3 org = centre + random_direction(rng) * (0.5f + 10.0f * u01(rng));
        expect_hits(fan, org, centre, 1, "centre vertex");
        const int spoke = i % 7;
        const float f = u01(rng);
        expect_hits(fan, org, centre + f * (ring[spoke] - centre), 1, "spoke");
        expect_hits(fan, org, centre + 0.5f * (ring[spoke] - centre), 1, "spoke midpoint");
    }
}

/// Rays from inside a closed mesh toward every vertex, every edge midpoint and random
/// directions must hit at least one triangle.
void expect_closed_from_inside(const ClosedMesh& mesh, glm::vec3 inside, std::mt19937& rng,
                               const char* what) {
    const std::vector<Triangle> tris = mesh.triangles();
    for (const glm::vec3& v : mesh.vertices) expect_hits(tris, inside, v, 1, what);
    for (const auto& [a, b] : mesh.edges()) {
        expect_hits(tris, inside, 0.5f * (mesh.vertices[a] + mesh.vertices[b]), 1, what);
    }
    for (int i = 0; i < 500; ++i) expect_hits(tris, inside, inside + random_direction(rng), 1, what);
}

TEST(Watertight, ClosedCubeIsHitThroughEveryEdgeAndVertex) {
    const ClosedMesh cube = testing::cube_mesh(0.0f, 1.0f);
    std::mt19937 rng(24);
    expect_closed_from_inside(cube, glm::vec3(0.5f), rng, "cube from centre");
    for (int i = 0; i < 20; ++i) {
        expect_closed_from_inside(cube, random_point(rng, glm::vec3(0.01f), glm::vec3(0.99f)), rng,
                                  "cube from inside");
    }
    // From outside through the face diagonals (shared edges of coplanar triangles): the ray
    // enters and leaves, so at least two hits.
    const std::vector<Triangle> tris = cube.triangles();
    std::uniform_real_distribution<float> u01(0.05f, 0.95f);
    for (int i = 0; i < 2000; ++i) {
        const float f = u01(rng);
        const glm::vec3 on_diagonal(f, f, 0.0f);  // the z = 0 face's diagonal
        const glm::vec3 org = on_diagonal + glm::vec3(0.5f - u01(rng), 0.5f - u01(rng), -1.0f - u01(rng));
        expect_hits(tris, org, on_diagonal, 2, "face diagonal");
    }
}

TEST(Watertight, ClosedTetrahedronIsHitThroughEveryEdgeAndVertex) {
    const ClosedMesh tet = testing::tetrahedron_mesh();
    const glm::vec3 centroid = 0.25f * (tet.vertices[0] + tet.vertices[1] + tet.vertices[2] + tet.vertices[3]);
    std::mt19937 rng(25);
    expect_closed_from_inside(tet, centroid, rng, "tetrahedron from centroid");
    // Rays from outside through inner points pass through the solid: two hits at least.
    const std::vector<Triangle> tris = tet.triangles();
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 org = centroid + random_direction(rng) * 5.0f;
        expect_hits(tris, org, centroid, 2, "through the centroid");
    }
}

TEST(Watertight, ClosedIcosphereIsHitFromInside) {
    const ClosedMesh sphere = testing::icosphere_mesh(2, 1.3f, glm::vec3(0.3f, -0.7f, 0.2f));
    std::mt19937 rng(26);
    expect_closed_from_inside(sphere, glm::vec3(0.3f, -0.7f, 0.2f), rng, "icosphere from centre");
    expect_closed_from_inside(sphere, glm::vec3(0.9f, -0.5f, 0.1f), rng, "icosphere off centre");
}

}  // namespace
}  // namespace dynrt::bvh
