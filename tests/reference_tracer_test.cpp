// Tests of the oracle itself: the reference tracer, the reference renderer and the image
// comparison, against answers worked out by hand.

#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <vector>

namespace dynrt::reference {
namespace {

struct MeshSpec {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
};

Scene make_scene(std::initializer_list<MeshSpec> meshes) {
    Scene scene;
    scene.source = "reference test";
    scene.materials.push_back(Material{});
    for (const MeshSpec& spec : meshes) {
        Object object;
        object.name = "object " + std::to_string(scene.objects.size());
        object.mesh.positions = spec.positions;
        object.mesh.triangles = spec.triangles;
        scene.objects.push_back(object);
    }
    return scene;
}

/// Triangle (0,0,z) (1,0,z) (0,1,z).
MeshSpec triangle_at(float z) { return {{{0, 0, z}, {1, 0, z}, {0, 1, z}}, {{0, 1, 2}}}; }

/// Unit square [0,1]^2 at z, split along the diagonal (0,0)-(1,1): prim 0 is the lower-right
/// half (x > y), prim 1 the upper-left half.
MeshSpec unit_square_at(float z) {
    return {{{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}}, {{0, 1, 2}, {0, 2, 3}}};
}

/// Owns the posed scene the tracer was built from.
struct Traced {
    explicit Traced(Scene s) : scene(std::move(s)) {
        anim::pose_scene(scene, 0, posed);
        tracer = std::make_unique<ReferenceTracer>(scene, posed);
    }
    Scene scene;
    anim::PosedScene posed;
    std::unique_ptr<ReferenceTracer> tracer;
};

/// A ray straight down -z from (x, y, 3).
bvh::Ray down_at(float x, float y) {
    bvh::Ray ray;
    ray.org = glm::vec3(x, y, 3.0f);
    ray.dir = glm::vec3(0.0f, 0.0f, -1.0f);
    return ray;
}

TEST(ReferenceTracer, SingleTriangleHasKnownDistanceAndBarycentrics) {
    const Traced t(make_scene({triangle_at(1.0f)}));
    const ReferenceHit hit = t.tracer->closest(down_at(0.25f, 0.5f));
    ASSERT_TRUE(hit.is_hit());
    EXPECT_EQ(hit.object, 0);
    EXPECT_EQ(hit.prim, 0);
    EXPECT_DOUBLE_EQ(hit.t, 2.0);
    EXPECT_DOUBLE_EQ(hit.u, 0.25);
    EXPECT_DOUBLE_EQ(hit.v, 0.5);
    EXPECT_EQ(hit.ambiguity, Ambiguity::kNone);
}

TEST(ReferenceTracer, TIsInUnitsOfTheRayDirection) {
    const Traced t(make_scene({triangle_at(1.0f)}));
    bvh::Ray ray = down_at(0.25f, 0.25f);
    ray.dir *= 4.0f;
    EXPECT_DOUBLE_EQ(t.tracer->closest(ray).t, 0.5);
}

TEST(ReferenceTracer, BackFacesAreHit) {
    const Traced t(make_scene({triangle_at(1.0f)}));
    bvh::Ray ray = down_at(0.25f, 0.25f);
    ray.org.z = -1.0f;
    ray.dir = glm::vec3(0.0f, 0.0f, 1.0f);
    const ReferenceHit hit = t.tracer->closest(ray);
    EXPECT_TRUE(hit.is_hit());
    EXPECT_DOUBLE_EQ(hit.t, 2.0);
}

TEST(ReferenceTracer, ClearMissIsDetermined) {
    const Traced t(make_scene({triangle_at(1.0f)}));
    const ReferenceHit hit = t.tracer->closest(down_at(0.6f, 0.6f));  // beyond the hypotenuse
    EXPECT_FALSE(hit.is_hit());
    EXPECT_EQ(hit.object, -1);
    EXPECT_EQ(hit.prim, -1);
    EXPECT_TRUE(std::isinf(hit.t));
    EXPECT_EQ(hit.ambiguity, Ambiguity::kNone);
}

TEST(ReferenceTracer, UnitSquareReportsTheTriangleContainingTheRay) {
    const Traced t(make_scene({unit_square_at(0.0f)}));
    const ReferenceHit lower = t.tracer->closest(down_at(0.75f, 0.25f));
    const ReferenceHit upper = t.tracer->closest(down_at(0.25f, 0.75f));
    EXPECT_EQ(lower.prim, 0);
    EXPECT_EQ(upper.prim, 1);
    EXPECT_DOUBLE_EQ(lower.t, 3.0);
    EXPECT_DOUBLE_EQ(upper.t, 3.0);
    EXPECT_EQ(lower.ambiguity, Ambiguity::kNone);
    EXPECT_EQ(upper.ambiguity, Ambiguity::kNone);
}

TEST(ReferenceTracer, SharedDiagonalIsAHitOnEitherTriangle) {
    const Traced t(make_scene({unit_square_at(0.0f)}));
    for (float x : {0.5f, 0.5f + 1e-7f, 0.5f - 1e-7f}) {
        const ReferenceHit hit = t.tracer->closest(down_at(x, 0.5f));
        ASSERT_TRUE(hit.is_hit()) << x;
        EXPECT_EQ(hit.object, 0);
        EXPECT_EQ(hit.ambiguity, Ambiguity::kPrimitive) << "x = " << x;
        EXPECT_DOUBLE_EQ(hit.t, 3.0);
    }
    // Exactly on the diagonal both contain the point: the tie goes to the lower prim.
    EXPECT_EQ(t.tracer->closest(down_at(0.5f, 0.5f)).prim, 0);
}

TEST(ReferenceTracer, VertexInsideAClosedFanIsAHit) {
    // Four triangles around the centre (0.5, 0.5) of the unit square.
    const Traced t(make_scene({{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 0}},
                                {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}}}));
    const ReferenceHit hit = t.tracer->closest(down_at(0.5f, 0.5f));
    ASSERT_TRUE(hit.is_hit());
    EXPECT_EQ(hit.ambiguity, Ambiguity::kPrimitive);
    // A corner of the square is a vertex on the boundary: the ray may miss.
    EXPECT_EQ(t.tracer->closest(down_at(1.0f, 1.0f)).ambiguity, Ambiguity::kAny);
}

TEST(ReferenceTracer, OuterEdgeAndNearMissesAreAmbiguous) {
    const Traced t(make_scene({unit_square_at(0.0f)}));
    const ReferenceHit on_edge = t.tracer->closest(down_at(1.0f, 0.5f));
    EXPECT_TRUE(on_edge.is_hit());
    EXPECT_EQ(on_edge.ambiguity, Ambiguity::kAny);
    // scale = |(1, 0.5, 3) - (0.5, 0.5, 0)| + |(0.5, 0.5, 0)| ~ 3.75, so edge_rel 4e-6 reaches
    // 1.5e-5 beyond the edge.
    const ReferenceHit just_outside = t.tracer->closest(down_at(1.00001f, 0.5f));
    EXPECT_FALSE(just_outside.is_hit());
    EXPECT_EQ(just_outside.ambiguity, Ambiguity::kAny);
    const ReferenceHit just_inside = t.tracer->closest(down_at(0.99999f, 0.5f));
    EXPECT_TRUE(just_inside.is_hit());
    EXPECT_EQ(just_inside.ambiguity, Ambiguity::kAny);
    const ReferenceHit well_outside = t.tracer->closest(down_at(1.001f, 0.5f));
    EXPECT_FALSE(well_outside.is_hit());
    EXPECT_EQ(well_outside.ambiguity, Ambiguity::kNone);
}

TEST(ReferenceTracer, NearestOfStackedTrianglesWins) {
    const Traced t(make_scene({triangle_at(0.0f), triangle_at(1.0f), triangle_at(-1.0f)}));
    const ReferenceHit hit = t.tracer->closest(down_at(0.2f, 0.2f));
    EXPECT_EQ(hit.object, 1);
    EXPECT_DOUBLE_EQ(hit.t, 2.0);
    EXPECT_EQ(hit.ambiguity, Ambiguity::kNone);

    bvh::Ray limited = down_at(0.2f, 0.2f);
    limited.tmin = 2.5f;  // starts below the first triangle
    EXPECT_EQ(t.tracer->closest(limited).object, 0);
    limited.tmax = 2.9f;  // and ends above the second
    EXPECT_FALSE(t.tracer->closest(limited).is_hit());
}

TEST(ReferenceTracer, CoincidentTrianglesOfTwoObjectsAreATie) {
    const Traced t(make_scene({triangle_at(0.0f), triangle_at(0.0f)}));
    const ReferenceHit hit = t.tracer->closest(down_at(0.2f, 0.2f));
    EXPECT_EQ(hit.object, 0);  // equal t: the lower (object, prim)
    EXPECT_EQ(hit.ambiguity, Ambiguity::kAny);
    // Within one object, only the primitive is open.
    const Traced same(make_scene({{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 1, 2}}}}));
    const ReferenceHit same_hit = same.tracer->closest(down_at(0.2f, 0.2f));
    EXPECT_EQ(same_hit.prim, 0);
    EXPECT_EQ(same_hit.ambiguity, Ambiguity::kPrimitive);
}

TEST(ReferenceTracer, SilhouetteOfAClosedMeshIsAmbiguous) {
    // Tetrahedron with outward faces; seen from above, edge (1,0,0)-(0,1,0) is a silhouette.
    const Traced t(make_scene({{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                                {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}}}));
    const ReferenceHit inside = t.tracer->closest(down_at(0.2f, 0.2f));
    EXPECT_EQ(inside.prim, 3);
    // The slanted face x + y + z = 1 under the float ray at x = y = 0.2f.
    EXPECT_NEAR(inside.t, 3.0 - (1.0 - 2.0 * double(0.2f)), 1e-12);
    EXPECT_EQ(inside.ambiguity, Ambiguity::kNone);
    // The vertex (0,0,0), under which (0,0,1) lies: three silhouette edges meet there.
    EXPECT_EQ(t.tracer->closest(down_at(0.0f, 0.0f)).ambiguity, Ambiguity::kAny);
    // Over the silhouette edge x + y = 1.
    EXPECT_EQ(t.tracer->closest(down_at(0.5f, 0.5f)).ambiguity, Ambiguity::kAny);
    // Seen from (1, 1, -0.5) both the slanted face and the bottom face front the viewer, so the
    // edge (1,0,0)-(0,1,0) they share is interior: a ray through its midpoint certainly hits.
    bvh::Ray diagonal;
    diagonal.dir = -glm::normalize(glm::vec3(1.0f, 1.0f, -0.5f));
    diagonal.org = glm::vec3(0.5f, 0.5f, 0.0f) - 3.0f * diagonal.dir;
    const ReferenceHit interior = t.tracer->closest(diagonal);
    ASSERT_TRUE(interior.is_hit());
    EXPECT_EQ(interior.ambiguity, Ambiguity::kPrimitive);
}

TEST(ReferenceTracer, DegenerateTrianglesAreDropped) {
    const Traced t(make_scene({{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}},
                                {{0, 1, 2}, {0, 0, 3}, {0, 1, 3}}}}));
    EXPECT_EQ(t.tracer->triangle_count(), 1u);
    EXPECT_EQ(t.tracer->degenerate_count(), 2u);
    EXPECT_EQ(t.tracer->closest(down_at(0.2f, 0.2f)).prim, 2);
}

TEST(ReferenceTracer, OcclusionByATriangleBetweenPointAndLight) {
    // Occluder at z = 1 over [0,1]^2-ish; segments from z = 0 to z = 2.
    const Traced t(make_scene({unit_square_at(1.0f)}));
    const ReferenceOcclusion blocked = t.tracer->occluded({0.3, 0.6, 0.0}, {0.3, 0.6, 2.0});
    EXPECT_TRUE(blocked.occluded);
    EXPECT_FALSE(blocked.ambiguous);
    // Through the shared diagonal: still certainly blocked.
    const ReferenceOcclusion diagonal = t.tracer->occluded({0.5, 0.5, 0.0}, {0.5, 0.5, 2.0});
    EXPECT_TRUE(diagonal.occluded);
    EXPECT_FALSE(diagonal.ambiguous);
    // Beside it.
    const ReferenceOcclusion beside = t.tracer->occluded({1.5, 0.5, 0.0}, {1.5, 0.5, 2.0});
    EXPECT_FALSE(beside.occluded);
    EXPECT_FALSE(beside.ambiguous);
    // The light below the occluder.
    const ReferenceOcclusion short_segment = t.tracer->occluded({0.3, 0.6, 0.0}, {0.3, 0.6, 0.5});
    EXPECT_FALSE(short_segment.occluded);
    EXPECT_FALSE(short_segment.ambiguous);
    // Grazing its outer edge, and ending right at it.
    EXPECT_TRUE(t.tracer->occluded({1.0, 0.5, 0.0}, {1.0, 0.5, 2.0}).ambiguous);
    EXPECT_TRUE(t.tracer->occluded({0.3, 0.6, 0.0}, {0.3, 0.6, 1.0 - 1e-7}).ambiguous);
    EXPECT_TRUE(t.tracer->occluded({0.3, 0.6, 1.0 + 1e-7}, {0.3, 0.6, 2.0}).ambiguous);
}

TEST(ReferenceTracer, OcclusionIgnoresTheSurfaceTheRayLeaves) {
    // A ground square at z = 0 and a blocker at z = 1 over x < 0.5 only.
    const Traced t(make_scene({unit_square_at(0.0f),
                               {{{0, 0, 1}, {0.5f, 0, 1}, {0.5f, 1, 1}, {0, 1, 1}},
                                {{0, 1, 2}, {0, 2, 3}}}}));
    const TriangleRef ground_upper{0, 1};
    // Leaving the ground at a point on the shared diagonal, toward a light far above and to
    // the right: the coplanar neighbour (prim 0) is no occluder.
    const ReferenceOcclusion lit = t.tracer->occluded({0.7, 0.7, 0.0}, {1.7, 0.7, 5.0}, ground_upper);
    EXPECT_FALSE(lit.occluded);
    EXPECT_FALSE(lit.ambiguous);
    const ReferenceOcclusion shadowed =
        t.tracer->occluded({0.2, 0.7, 0.0}, {0.2, 0.7, 5.0}, ground_upper);
    EXPECT_TRUE(shadowed.occluded);
    EXPECT_FALSE(shadowed.ambiguous);
    // Without the exclusion the ray starts on the ground itself: a graze at t = 0.
    EXPECT_TRUE(t.tracer->occluded({0.7, 0.7, 0.0}, {1.7, 0.7, 5.0}).ambiguous);
}

TEST(ReferenceTracer, OcclusionNearTheOriginIsAmbiguous) {
    // A thin wall standing on the ground at x = 0.5, crossing it: a point right next to the
    // wall's foot cannot tell whether a float renderer's offset origin clears it.
    const Traced t(make_scene({unit_square_at(0.0f),
                               {{{0.5f, -1, -1}, {0.5f, 2, -1}, {0.5f, 0.5f, 2}}, {{0, 1, 2}}}}));
    const ReferenceOcclusion touching =
        t.tracer->occluded({0.5 + 1e-6, 0.3, 0.0}, {-2.0, 0.3, 1.0}, TriangleRef{0, 0});
    EXPECT_TRUE(touching.occluded);
    EXPECT_TRUE(touching.ambiguous);
    const ReferenceOcclusion clear =
        t.tracer->occluded({0.6, 0.3, 0.0}, {-2.0, 0.3, 1.0}, TriangleRef{0, 0});
    EXPECT_TRUE(clear.occluded);
    EXPECT_FALSE(clear.ambiguous);
}

// ---- Secondary rays (closest_leaving) and a deviating shadow origin ------------------------

/// A unit-direction double ray leaving `from`.
RayD leaving(glm::dvec3 from, glm::dvec3 dir) { return RayD{from, glm::normalize(dir)}; }

TEST(ReferenceTracer, LeavingRaySkipsItsTriangleAndItsPlane) {
    // Object 0, the unit square at z = 0; object 1, a triangle at z = 1 above it.
    const Traced t(make_scene({unit_square_at(0.0f), triangle_at(1.0f)}));
    const TriangleRef from{0, 0};  // the half x > y
    const ReferenceHit up =
        t.tracer->closest_leaving(leaving({0.6, 0.2, 0.0}, {0, 0, 1}), from, {});
    ASSERT_TRUE(up.is_hit());
    EXPECT_EQ(up.object, 1);
    EXPECT_DOUBLE_EQ(up.t, 1.0);
    EXPECT_EQ(up.ambiguity, Ambiguity::kNone);
    // Rising at 1e-3 across the square's other half: the coplanar neighbour is no candidate,
    // so the miss is determined (closest() finds the square itself at the origin).
    const RayD skim = leaving({0.6, 0.2, 0.0}, {-1.0, 0.5, 1e-3});
    const ReferenceHit skimming = t.tracer->closest_leaving(skim, from, {});
    EXPECT_FALSE(skimming.is_hit());
    EXPECT_EQ(skimming.ambiguity, Ambiguity::kNone);
    EXPECT_EQ(t.tracer->closest(skim).object, 0);
    // With no deviation and no triangle to leave it is closest().
    const RayD down{{0.6, 0.2, 3.0}, {0.0, 0.0, -1.0}};
    EXPECT_EQ(t.tracer->closest_leaving(down, TriangleRef{}, {}).t, t.tracer->closest(down).t);
}

TEST(ReferenceTracer, LeavingRayLeavesSurfacesWithinItsOriginZoneOpen) {
    // A second surface 1e-4 above the square: a float ray starting up to `along` off the
    // exact point may start beyond it.
    const Traced t(make_scene({unit_square_at(0.0f), triangle_at(1e-4f)}));
    const RayD up = leaving({0.6, 0.2, 0.0}, {0, 0, 1});
    const ReferenceHit exact = t.tracer->closest_leaving(up, TriangleRef{0, 0}, {});
    EXPECT_EQ(exact.object, 1);
    EXPECT_EQ(exact.ambiguity, Ambiguity::kNone);
    RayDeviation pushed;
    pushed.along = 1e-3;
    EXPECT_EQ(t.tracer->closest_leaving(up, TriangleRef{0, 0}, pushed).ambiguity, Ambiguity::kAny);
}

TEST(ReferenceTracer, LeavingRayToleranceGrowsWithDistance) {
    // Straight up from the square, passing 0.01 inside the edge y = 0 of a triangle 10 away.
    const Traced t(make_scene({unit_square_at(0.0f), triangle_at(10.0f)}));
    const RayD up = leaving({0.5, 0.01, 0.0}, {0, 0, 1});
    RayDeviation deviation;
    deviation.angle = 1e-4;  // 1e-3 sideways at the triangle
    EXPECT_EQ(t.tracer->closest_leaving(up, TriangleRef{0, 0}, deviation).ambiguity,
              Ambiguity::kNone);
    deviation.angle = 2e-3;  // 0.02 sideways: the float ray may pass outside the edge
    const ReferenceHit open = t.tracer->closest_leaving(up, TriangleRef{0, 0}, deviation);
    EXPECT_EQ(open.object, 1);
    EXPECT_EQ(open.ambiguity, Ambiguity::kAny);
    deviation.angle = 0.0;
    deviation.lateral = 0.02;  // the same from a displaced origin
    EXPECT_EQ(t.tracer->closest_leaving(up, TriangleRef{0, 0}, deviation).ambiguity,
              Ambiguity::kAny);
}

TEST(ReferenceTracer, OcclusionFromADeviatingPointWidensItsOriginTolerance) {
    // A blocker whose edge x = 0.02 passes 0.02 beside the segment, 0.05 from its origin.
    const Traced t(
        make_scene({{{{0.02f, -1, 0.05f}, {2, -1, 0.05f}, {0.02f, 1, 0.05f}}, {{0, 1, 2}}}}));
    const ReferenceOcclusion exact = t.tracer->occluded({0, 0, 0}, {0, 0, 10});
    EXPECT_FALSE(exact.occluded);
    EXPECT_FALSE(exact.ambiguous);
    const ReferenceOcclusion deviating = t.tracer->occluded({0, 0, 0}, {0, 0, 10}, {}, {}, 0.05);
    EXPECT_FALSE(deviating.occluded);
    EXPECT_TRUE(deviating.ambiguous);
}

// ---- Reference renderer --------------------------------------------------------------------

/// A 1x1 image from (0,0,2) looking down -z: the one ray is exactly (0,0,-1) and hits the
/// ground at p = (0,0,0) with t = 2.
struct OnePixel {
    Camera camera() const {
        Camera c;
        c.eye = glm::vec3(0.0f, 0.0f, 2.0f);
        c.target = glm::vec3(0.0f);
        c.up = glm::vec3(0.0f, 1.0f, 0.0f);
        return c;
    }
    ReferenceShading shading() const {
        ReferenceShading s;
        s.lights = {PointLight{glm::vec3(0.0f, 3.0f, 4.0f), 2.0f}};
        s.background = glm::dvec3(0.01, 0.02, 0.03);
        s.ambient = 0.1;
        return s;
    }
};

Scene ground_scene(bool with_blocker) {
    // One big ground triangle, so p = (0,0,0) is far from every edge.
    Scene scene = make_scene({{{{-5, -5, 0}, {5, -5, 0}, {0, 6, 0}}, {{0, 1, 2}}}});
    scene.materials[0].diffuse = glm::vec3(0.5f, 0.25f, 1.0f);
    scene.materials[0].specular = glm::vec3(0.125f);
    scene.materials[0].shininess = 2.0f;
    if (with_blocker) {
        Object blocker;
        blocker.name = "blocker";
        blocker.mesh.positions = {{-1, 0, 1}, {1, 0, 1}, {0, 3, 1}};  // crosses p -> light
        blocker.mesh.triangles = {{0, 1, 2}};
        scene.objects.push_back(blocker);
    }
    return scene;
}

TEST(ReferenceRenderer, PhongColourMatchesHandComputation) {
    const Traced t(ground_scene(false));
    const OnePixel view;
    const ReferenceFrame frame = render_reference(t.scene, *t.tracer, view.camera(), 1, 1,
                                                  view.shading());
    const ReferencePixel& p = frame.at(0, 0);
    ASSERT_TRUE(p.hit.is_hit());
    EXPECT_DOUBLE_EQ(p.hit.t, 2.0);
    EXPECT_FALSE(p.shading_ambiguous);
    EXPECT_EQ(p.normal, glm::dvec3(0.0, 0.0, 1.0));
    // l = (0, 0.6, 0.8), n.l = 0.8, r = 2 (0.8) n - l = (0, -0.6, 0.8), v = (0, 0, 1), r.v = 0.8:
    // colour = 0.1 kd + 2 (0.8 kd + 0.125 * 0.8^2) = 1.7 kd + 0.16.
    EXPECT_NEAR(p.color.x, 1.7 * 0.5 + 0.16, 1e-12);
    EXPECT_NEAR(p.color.y, 1.7 * 0.25 + 0.16, 1e-12);
    EXPECT_NEAR(p.color.z, 1.7 * 1.0 + 0.16, 1e-12);
}

TEST(ReferenceRenderer, ShadowedPointGetsAmbientOnly) {
    const Traced t(ground_scene(true));
    const OnePixel view;
    // The blocker sits between eye and ground too: look from below the blocker instead.
    Camera camera = view.camera();
    camera.eye.z = 0.5f;
    const ReferenceFrame frame = render_reference(t.scene, *t.tracer, camera, 1, 1,
                                                  view.shading());
    const ReferencePixel& p = frame.at(0, 0);
    ASSERT_TRUE(p.hit.is_hit());
    EXPECT_EQ(p.hit.object, 0);
    EXPECT_FALSE(p.shading_ambiguous);
    EXPECT_NEAR(p.color.x, 0.05, 1e-12);
    EXPECT_NEAR(p.color.y, 0.025, 1e-12);
    EXPECT_NEAR(p.color.z, 0.1, 1e-12);
}

TEST(ReferenceRenderer, MissIsBackgroundAndLightBehindIsUnlit) {
    const Traced t(ground_scene(false));
    const OnePixel view;
    Camera up = view.camera();
    up.target = glm::vec3(0.0f, 0.0f, 3.0f);  // looking away from the ground
    const ReferenceFrame miss = render_reference(t.scene, *t.tracer, up, 1, 1, view.shading());
    EXPECT_FALSE(miss.at(0, 0).hit.is_hit());
    EXPECT_EQ(miss.at(0, 0).color, view.shading().background);

    ReferenceShading below = view.shading();
    below.lights[0].position = glm::vec3(0.0f, 0.0f, -4.0f);
    const ReferenceFrame unlit = render_reference(t.scene, *t.tracer, view.camera(), 1, 1, below);
    EXPECT_NEAR(unlit.at(0, 0).color.x, 0.05, 1e-12);  // ambient only, no shadow ray needed
    EXPECT_FALSE(unlit.at(0, 0).shading_ambiguous);
}

// ---- Comparison ----------------------------------------------------------------------------

RenderedFrame copy_as_rendered(const ReferenceFrame& ref) {
    RenderedFrame out;
    out.width = ref.width;
    out.height = ref.height;
    for (const ReferencePixel& p : ref.pixels) {
        out.color.push_back(glm::vec3(p.color));
        out.depth.push_back(float(p.hit.t));
        out.object.push_back(p.hit.object);
        out.prim.push_back(p.hit.prim);
        out.normal.push_back(glm::vec3(p.normal));
    }
    return out;
}

TEST(ReferenceImageComparison, CountsEachKindOfDisagreement) {
    const Traced t(make_scene({unit_square_at(0.0f)}));
    Camera camera;
    // Every pixel centre lands inside the square and at least 0.03 from its diagonal.
    camera.eye = glm::vec3(0.45f, 0.5f, 3.0f);
    camera.target = glm::vec3(0.45f, 0.5f, 0.0f);
    camera.fov_y_deg = 16.0f;
    ReferenceShading shading;
    shading.lights = {PointLight{glm::vec3(0.3f, 0.2f, 5.0f), 1.0f}};
    const ReferenceFrame ref = render_reference(t.scene, *t.tracer, camera, 8, 8, shading);

    RenderedFrame same = copy_as_rendered(ref);
    const ImageComparison clean = compare_images(same, ref);
    EXPECT_TRUE(clean.passed()) << clean.summary();
    EXPECT_EQ(clean.color_checked, 64);

    RenderedFrame bad = same;
    bad.prim[9] = 1 - bad.prim[9];   // pixel (1,1): wrong triangle
    bad.depth[10] *= 1.001f;         // pixel (2,1): wrong depth
    bad.color[11].x += 0.01f;        // pixel (3,1): wrong colour
    const ImageComparison found = compare_images(bad, ref);
    EXPECT_FALSE(found.passed());
    EXPECT_EQ(found.prim_mismatches, 1);
    EXPECT_EQ(found.unambiguous_mismatches, 1);
    EXPECT_EQ(found.t_mismatches, 1);
    EXPECT_EQ(found.color_mismatches, 1);
    EXPECT_EQ(found.bad_pixels.size(), 3u);
    EXPECT_NE(found.summary().find("(1,1) hit mismatch"), std::string::npos) << found.summary();
}

}  // namespace
}  // namespace dynrt::reference
