// Shadow rays cut without changing a pixel (issue 39): the occluder cache per light
// (rendering/occluder_cache.h) gives the same frames as tracing without it while objects move
// between frames and through it, and answers rays; lights of intensity 0 and hits facing away
// from a light cast no shadow ray, leave the image as it is, and are counted by reason.

#include "moving_scene.h"
#include "same_bits.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "rendering/occluder_cache.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace dynrt {
namespace {

using dynrt::test::same_bits;

using test::moving_scene;  // the occluders: rigid, deforming and exploding over a floor

RenderOptions options_with_lights() {
    RenderOptions options;
    options.width = 96;
    options.height = 80;
    options.reuse.mode = PixelReuse::off;  // every shadow ray traced, every frame
    // The last just above the rigid sphere, whose shadow then covers whole tiles of the floor.
    options.lights = {PointLight{{2.0f, 3.0f, 1.0f}, 0.6f}, PointLight{{-2.5f, 2.0f, -1.5f}, 0.5f},
                      PointLight{{-0.8f, 0.5f, 0.3f}, 0.4f}};
    return options;
}

TEST(OccluderCache, MovingOccludersGiveTheFramesOfAnUncachedTrace) {
    const Scene scene = moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = options_with_lights();
    options.width = options.height = 512;
    options.occluder_cache = false;
    Renderer plain(options);
    options.occluder_cache = true;
    Renderer cached(options);
    RenderedFrame a, b;
    std::size_t tested = 0, answered = 0;
    // Frames out of order and repeated: a cell's triangle from another frame would be stale.
    for (const int f : {0, 1, 7, 3, 3, 20}) {
        SCOPED_TRACE("frame " + std::to_string(f));
        plain.render(scene, camera, f, a);
        cached.render(scene, camera, f, b);
        EXPECT_TRUE(same_bits(a.color, b.color));
        EXPECT_EQ(a.stats.shadow_rays, b.stats.shadow_rays);
        EXPECT_EQ(a.stats.shadow_rays_cache_tested, 0u);
        tested += b.stats.shadow_rays_cache_tested;
        answered += b.stats.shadow_rays_cache_answered;
    }
    EXPECT_GT(tested, 0u);
    EXPECT_GT(answered, 0u) << "the cache never answered a ray: the test shows nothing";
    EXPECT_LE(answered, tested);
}

TEST(OccluderCache, CellsCoverEveryDirectionOnce) {
    std::set<int> cells;
    for (int face = 0; face < 6; ++face) {
        for (int i = 0; i < detail::OccluderCache::kCellsPerSide; ++i) {
            for (int j = 0; j < detail::OccluderCache::kCellsPerSide; ++j) {
                const float u = -1.0f + (2.0f * float(i) + 1.0f) / float(detail::OccluderCache::kCellsPerSide);
                const float v = -1.0f + (2.0f * float(j) + 1.0f) / float(detail::OccluderCache::kCellsPerSide);
                float d[3];
                const int major = face / 2;
                d[major] = face % 2 == 0 ? 1.0f : -1.0f;
                d[(major + 1) % 3] = u;
                d[(major + 2) % 3] = v;
                const int cell = detail::OccluderCache::cell_of(d[0], d[1], d[2]);
                ASSERT_GE(cell, 0);
                ASSERT_LT(cell, detail::OccluderCache::kCells);
                cells.insert(cell);
            }
        }
    }
    EXPECT_EQ(cells.size(), std::size_t(detail::OccluderCache::kCells));
    // A direction's length does not matter; nothing finite and non-zero is left out.
    EXPECT_EQ(detail::OccluderCache::cell_of(0.3f, -2.0f, 0.1f), detail::OccluderCache::cell_of(3.0f, -20.0f, 1.0f));
    EXPECT_EQ(detail::OccluderCache::cell_of(0.0f, 0.0f, 0.0f), -1);
    EXPECT_EQ(detail::OccluderCache::cell_of(1.0f, std::nanf(""), 0.0f), -1);
    EXPECT_EQ(detail::OccluderCache::cell_of(1.0f, 0.0f, std::numeric_limits<float>::infinity()), -1);
}

TEST(ShadowRayCuts, ADarkLightCastsNoRayAndChangesNoBit) {
    const Scene scene = moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = options_with_lights();
    Renderer without(options);
    options.lights.push_back(PointLight{{1.0f, 2.0f, 2.0f}, 0.0f});
    Renderer with_dark(options);
    RenderedFrame a, b;
    for (const int f : {0, 5}) {
        without.render(scene, camera, f, a);
        with_dark.render(scene, camera, f, b);
        EXPECT_TRUE(same_bits(a.color, b.color));
        EXPECT_EQ(a.stats.shadow_rays, b.stats.shadow_rays);
        EXPECT_EQ(a.stats.shadow_rays_dark_light, 0u);
        // One per hit pixel for the dark light.
        std::size_t hits = 0;
        for (const std::int32_t o : b.object) hits += o >= 0;
        EXPECT_EQ(b.stats.shadow_rays_dark_light, hits);
        EXPECT_EQ(a.stats.shadow_rays_back_side, b.stats.shadow_rays_back_side);
        // Three lights, one of them low among the objects: many hits face away from one.
        EXPECT_GT(a.stats.shadow_rays_back_side, 0u);
        EXPECT_EQ(a.stats.shadow_rays + a.stats.shadow_rays_back_side + a.stats.shadow_rays_shading_side, 3 * hits);
    }
}

}  // namespace
}  // namespace dynrt
