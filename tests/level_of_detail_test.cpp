// Level of detail (RenderOptions::lod_pixels; engine/src/rendering/level_of_detail.h and
// simplified_levels.h): the levels a mesh gets, which objects get them, the level chosen from
// the camera, and that a change of level between frames leaves no stale tree or pixel behind.

#include "rendering/simplified_levels.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "reference_shot.h"
#include "same_bits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace dynrt {
namespace {

using dynrt::test::renderer_shot;
using dynrt::test::same_bits;

RenderOptions lod_options(float pixels) {
    RenderOptions options;
    options.width = 96;
    options.height = 96;
    options.lod_pixels = pixels;
    return options;
}

/// Looking down -Z at the origin from `distance` away.
Camera camera_at(float distance) {
    Camera camera;
    camera.eye = glm::vec3(0.0f, 0.0f, distance);
    camera.target = glm::vec3(0.0f);
    camera.fov_y_deg = 40.0f;
    return camera;
}

TEST(SimplifiedLevels, EachLevelIsCoarserOverTheMeshsOwnVertices) {
    const Scene scene = load_scene("sphere:20000");
    const Mesh& mesh = scene.objects.at(0).mesh;
    const std::vector<SimplifiedLevel> levels = simplified_levels(mesh);
    ASSERT_GE(levels.size(), 3u);
    std::size_t before = mesh.triangles.size();
    float error = 0.0f;
    for (const SimplifiedLevel& level : levels) {
        EXPECT_LT(level.triangles.size(), before);
        EXPECT_LE(3 * level.triangles.size(), 2 * before);  // at least a third fewer
        EXPECT_GE(level.triangles.size(), 32u);
        for (const glm::uvec3& t : level.triangles) {
            ASSERT_LT(std::max(t.x, std::max(t.y, t.z)), mesh.positions.size());
        }
        // An error in object units: a unit sphere simplified loses well under its radius.
        EXPECT_GT(level.error, 0.0f);
        EXPECT_GE(level.error, error);
        EXPECT_LT(level.error, 0.5f);
        error = level.error;
        before = level.triangles.size();
    }
    // The coarsest level is far coarser than the mesh, and its error far larger than the first's.
    EXPECT_LT(levels.back().triangles.size(), mesh.triangles.size() / 32);
    EXPECT_GT(levels.back().error, 4.0f * levels.front().error);
}

TEST(SimplifiedLevels, SmallMeshesAndSoupsGetNone) {
    EXPECT_TRUE(simplified_levels(load_scene("sphere:200").objects.at(0).mesh).empty());
    EXPECT_TRUE(simplified_levels(load_scene("soup:5000").objects.at(0).mesh).empty());
    EXPECT_TRUE(simplified_levels(Mesh{}).empty());
}

TEST(LevelOfDetail, FarObjectsAreTracedWithFewerTrianglesNearOnesWithTheirOwn) {
    const Scene scene = load_scene("sphere:20000");
    const std::size_t full = scene.triangle_count();
    const RenderedFrame off = renderer_shot(scene, camera_at(40.0f), lod_options(0.0f));
    EXPECT_EQ(off.stats.triangles, full);
    const RenderedFrame far = renderer_shot(scene, camera_at(12.0f), lod_options(1.0f));
    EXPECT_LT(far.stats.triangles, full / 16);
    // Allowing more error gives a coarser level, never a finer one.
    const RenderedFrame coarser = renderer_shot(scene, camera_at(12.0f), lod_options(8.0f));
    EXPECT_LT(coarser.stats.triangles, far.stats.triangles);
    const RenderedFrame nearer = renderer_shot(scene, camera_at(4.0f), lod_options(1.0f));
    EXPECT_GT(nearer.stats.triangles, far.stats.triangles);
    // Inside the object's bounding sphere the mesh itself is traced, whatever the allowance.
    const RenderedFrame inside = renderer_shot(scene, camera_at(0.5f), lod_options(1000.0f));
    EXPECT_EQ(inside.stats.triangles, full);
}

TEST(LevelOfDetail, TheFarImageStaysCloseToTheExactOne) {
    const Scene scene = load_scene("sphere:20000");
    const RenderedFrame exact = renderer_shot(scene, camera_at(12.0f), lod_options(0.0f));
    const RenderedFrame lod = renderer_shot(scene, camera_at(12.0f), lod_options(0.5f));
    ASSERT_LT(lod.stats.triangles, exact.stats.triangles);
    std::size_t covered_differs = 0, pixels = 0;
    double error = 0.0;
    for (std::size_t p = 0; p < exact.color.size(); ++p) {
        if ((exact.object[p] < 0) != (lod.object[p] < 0)) ++covered_differs;
        if (exact.object[p] >= 0) ++pixels;
        const glm::vec3 d = exact.color[p] - lod.color[p];
        error += double(d.x * d.x + d.y * d.y + d.z * d.z);
    }
    ASSERT_GT(pixels, 200u);
    // Half a pixel of error moves the silhouette by at most a pixel: a thin ring of the disc.
    EXPECT_LT(double(covered_differs), 0.1 * double(pixels));
    EXPECT_LT(std::sqrt(error / double(exact.color.size())), 0.05);
}

TEST(LevelOfDetail, AChangeOfLevelBetweenFramesLeavesNoStaleTreeOrPixel) {
    const Scene scene = load_scene("sphere:20000+sphere:3000@2.5,0,0,0.5");
    for (const bool reuse : {false, true}) {
        RenderOptions options = lod_options(1.0f);
        options.reuse.mode = reuse ? PixelReuse::exact : PixelReuse::off;
        const float distances[] = {40.0f, 6.0f, 40.0f, 0.5f, 25.0f};
        Renderer renderer(options);
        std::size_t last = 0;
        bool changed = false;
        for (int k = 0; k < 5; ++k) {
            SCOPED_TRACE("reuse " + std::to_string(reuse) + ", step " + std::to_string(k));
            RenderedFrame followed;
            renderer.render(scene, camera_at(distances[k]), k, followed);
            if (k > 0 && followed.stats.triangles != last) changed = true;
            last = followed.stats.triangles;
            const RenderedFrame fresh = renderer_shot(scene, camera_at(distances[k]), options);
            EXPECT_EQ(followed.stats.triangles, fresh.stats.triangles);
            EXPECT_TRUE(same_bits(followed.color, fresh.color));
            EXPECT_EQ(followed.prim, fresh.prim);
        }
        EXPECT_TRUE(changed);
    }
}

TEST(LevelOfDetail, CopiesOfAMeshTakeTheLevelOfTheirOwnDistance) {
    // Nine copies on a grid; the camera close to one of them, looking across the others.
    const Scene scene = load_scene("sphere:4000*9");
    const std::size_t full = scene.objects.at(0).mesh.triangles.size();
    Camera camera;
    camera.eye = glm::vec3(-4.0f, 1.0f, -4.0f);
    camera.target = glm::vec3(4.0f, 0.0f, 4.0f);
    camera.fov_y_deg = 50.0f;
    const RenderedFrame exact = renderer_shot(scene, camera, lod_options(0.0f));
    EXPECT_EQ(exact.stats.triangles, 9 * full);
    const RenderedFrame lod = renderer_shot(scene, camera, lod_options(1.0f));
    EXPECT_LT(lod.stats.triangles, 9 * full);
    // Not all at one level: the nearest copy is finer than a far copy's level.
    EXPECT_GT(lod.stats.triangles, 9 * simplified_levels(scene.objects.at(0).mesh).front().triangles.size() / 2);
}

TEST(LevelOfDetail, MovingShapesKeepTheirTriangles) {
    Scene scene = load_scene("sphere:20000");
    anim::add_procedural_motions(scene, std::vector<std::string>{"explode"});
    const RenderedFrame far = renderer_shot(scene, camera_at(40.0f), lod_options(8.0f));
    EXPECT_EQ(far.stats.triangles, scene.triangle_count());
}

TEST(LevelOfDetail, SwitchedOffMidSequenceTheFramesAreExactAgain) {
    const Scene scene = load_scene("sphere:20000");
    const RenderedFrame exact = renderer_shot(scene, camera_at(12.0f), lod_options(0.0f));
    Renderer renderer(lod_options(2.0f));
    RenderedFrame out;
    renderer.render(scene, camera_at(12.0f), 0, out);
    ASSERT_LT(out.stats.triangles, exact.stats.triangles);
    renderer.set_options(lod_options(0.0f));
    renderer.render(scene, camera_at(12.0f), 1, out);
    EXPECT_EQ(out.stats.triangles, exact.stats.triangles);
    EXPECT_TRUE(same_bits(out.color, exact.color));
    // And on again: the levels come back.
    renderer.set_options(lod_options(2.0f));
    renderer.render(scene, camera_at(12.0f), 2, out);
    EXPECT_LT(out.stats.triangles, exact.stats.triangles);
}

TEST(LevelOfDetail, ABadAllowanceIsRefused) {
    for (const float pixels : {-1.0f, std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity()}) {
        EXPECT_THROW(Renderer{lod_options(pixels)}, std::invalid_argument);
    }
}

}  // namespace
}  // namespace dynrt
