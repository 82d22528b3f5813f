#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace dynrt {
namespace {

/// A unit quad in the XY plane at z = 0 facing +Z, plus whatever extra triangles a test adds.
Scene quad_scene() {
    Scene scene;
    scene.source = "test";
    scene.materials.push_back(Material{});
    Object quad;
    quad.name = "quad";
    quad.mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.objects.push_back(quad);
    return scene;
}

Camera looking_down_z() {
    Camera camera;
    camera.eye = glm::vec3(0.0f, 0.0f, 4.0f);
    camera.target = glm::vec3(0.0f);
    camera.fov_y_deg = 40.0f;
    return camera;
}

/// The default framing of a sequence covers where the scene goes, not only frame 0: an
/// exploding sphere's fragments fly out by f 0.02 R (0.5 .. 1.5) along their normals, so by
/// frame 45 its box is about twice as wide; the last frame is always among those sampled.
TEST(Renderer, SequenceBoundsCoverEveryFrameTheSceneMovesThrough) {
    Scene scene = load_scene("sphere:200@3,0,0,1");
    const std::vector<std::string> motions = {"explode"};
    anim::add_procedural_motions(scene, motions);
    const anim::PoseSettings pose;
    const bvh::Aabb first = sequence_bounds(scene, pose, 0, 0);
    const bvh::Aabb all = sequence_bounds(scene, pose, 0, 45);
    const bvh::Aabb last = sequence_bounds(scene, pose, 45, 45);
    EXPECT_NEAR(first.lo.x, 2.0f, 1e-3f);
    EXPECT_NEAR(first.hi.x, 4.0f, 1e-3f);
    EXPECT_GT(last.hi.x - last.lo.x, 1.5f * (first.hi.x - first.lo.x));
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE(all.lo[a], std::min(first.lo[a], last.lo[a]));
        EXPECT_GE(all.hi[a], std::max(first.hi[a], last.hi[a]));
    }
    // A still scene is posed once and gives frame 0's bounds whatever the range.
    const Scene still = load_scene("sphere:200@3,0,0,1");
    const bvh::Aabb a = sequence_bounds(still, pose, 0, 0), b = sequence_bounds(still, pose, 0, 1000);
    EXPECT_EQ(a.lo, b.lo);
    EXPECT_EQ(a.hi, b.hi);
}

TEST(Renderer, DegenerateTrianglesAreSkippedAndCounted) {
    Scene scene = quad_scene();
    Object sliver;
    sliver.name = "sliver";
    // Collinear and coincident vertices: zero area, never hit, never in the tree.
    sliver.mesh.positions = {{0, 0, 1}, {0.5f, 0.5f, 1}, {1, 1, 1}, {0, 0, 1}};
    sliver.mesh.triangles = {{0, 1, 2}, {0, 3, 3}};
    scene.objects.push_back(sliver);
    RenderOptions options;
    options.width = options.height = 32;
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, looking_down_z(), 0, frame);
    EXPECT_EQ(frame.stats.degenerate_skipped, 2u);
    EXPECT_EQ(frame.stats.triangles, 4u);
    int quad_pixels = 0;
    for (std::size_t p = 0; p < frame.object.size(); ++p) {
        EXPECT_NE(frame.object[p], 1) << "pixel " << p << " hit a degenerate triangle";
        quad_pixels += frame.object[p] == 0;
    }
    EXPECT_GT(quad_pixels, 0);
}

TEST(Renderer, NonFiniteGeometryNamesObjectAndFrame) {
    Scene scene = quad_scene();
    scene.objects[0].name = "broken quad";
    scene.objects[0].mesh.positions.edit()[2].y = std::numeric_limits<float>::quiet_NaN();
    Renderer renderer(RenderOptions{});
    RenderedFrame frame;
    try {
        renderer.render(scene, looking_down_z(), 7, frame);
        FAIL() << "expected SceneError";
    } catch (const SceneError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("broken quad"), std::string::npos) << message;
        EXPECT_NE(message.find("frame 7"), std::string::npos) << message;
    }
}

TEST(Renderer, OutputsAgreeWithEachOtherAndTheReport) {
    const Scene scene = quad_scene();
    RenderOptions options;
    options.width = 21;
    options.height = 13;
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, looking_down_z(), 0, frame);
    ASSERT_EQ(frame.color.size(), 21u * 13u);
    std::size_t hits = 0;
    for (std::size_t p = 0; p < frame.color.size(); ++p) {
        const bool hit = frame.object[p] >= 0;
        hits += hit;
        EXPECT_EQ(hit, frame.prim[p] >= 0);
        EXPECT_EQ(hit, std::isfinite(frame.depth[p]));
        if (hit) {
            EXPECT_NEAR(frame.normal[p].z, 1.0f, 1e-6f);  // facing the eye
            EXPECT_GT(frame.depth[p], 3.99f);
        } else {
            EXPECT_EQ(frame.color[p], options.background);
        }
    }
    EXPECT_GT(hits, 0u);
    EXPECT_LT(hits, frame.color.size());
    EXPECT_EQ(frame.stats.primary_rays, 21u * 13u);
    // The default light is in front of the quad, so every hit traces exactly one shadow ray.
    EXPECT_EQ(frame.stats.shadow_rays, hits);
    EXPECT_EQ(frame.stats.triangles, 2u);
    // The stages the tables show make up the total (the rest is bookkeeping between them).
    const FrameStats& s = frame.stats;
    EXPECT_GE(s.update_ms, 0.0);
    EXPECT_GE(s.total_ms + 1e-9, s.update_ms + s.build_ms + s.primary_ms + s.shadow_ms + s.shade_ms);
}

TEST(Renderer, WithoutHitBuffersTheColourIsTheSame) {
    // The bundled scene has several objects, materials and shadows; 37x19 leaves partial tiles.
    const Scene scene = load_scene(default_scene_path().string());
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = 37;
    options.height = 19;
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        options.tracer = tracer;
        options.hit_buffers = true;
        RenderedFrame full;
        Renderer(options).render(scene, camera, 0, full);
        options.hit_buffers = false;
        RenderedFrame colour_only;
        // Reused buffers must shrink, not keep a previous frame's hits.
        colour_only = full;
        Renderer(options).render(scene, camera, 0, colour_only);
        EXPECT_TRUE(colour_only.depth.empty());
        EXPECT_TRUE(colour_only.object.empty());
        EXPECT_TRUE(colour_only.prim.empty());
        EXPECT_TRUE(colour_only.normal.empty());
        ASSERT_EQ(colour_only.color.size(), full.color.size());
        for (std::size_t p = 0; p < full.color.size(); ++p) {
            ASSERT_EQ(colour_only.color[p], full.color[p]) << "pixel " << p;
        }
        EXPECT_EQ(colour_only.stats.shadow_rays, full.stats.shadow_rays);
    }
}

TEST(Renderer, LightBehindTheSurfaceCastsNoShadowRays) {
    const Scene scene = quad_scene();
    RenderOptions options;
    options.width = options.height = 16;
    options.lights = {PointLight{glm::vec3(0.0f, 0.0f, -5.0f), 1.0f}};
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, looking_down_z(), 0, frame);
    EXPECT_EQ(frame.stats.shadow_rays, 0u);
    for (std::size_t p = 0; p < frame.color.size(); ++p) {
        if (frame.object[p] >= 0) {
            EXPECT_NEAR(frame.color[p].x, options.ambient * 0.8f, 1e-6f);  // ambient only
        }
    }
}

}  // namespace
}  // namespace dynrt
