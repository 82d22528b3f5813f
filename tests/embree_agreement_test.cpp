// Embree 3 as an independent oracle: on the same posed triangles and camera rays, its closest
// hits must name the same object as dynrt's for (almost) every pixel, and its single-ray and
// 16-ray packet paths (4x4-pixel blocks) must agree exactly with each other, for camera and
// shadow rays, also on images whose size is not a multiple of the block.

#include <gtest/gtest.h>

#if DYNRT_HAVE_EMBREE

#include "dynrt/bench/hit_agreement.h"
#include "dynrt/embree/embree_tracer.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <string>

namespace dynrt::embree {
namespace {

struct Case {
    const char* spec;
    /// Pixels allowed to differ in hit/object, out of width x height.
    std::size_t object_differs_max;
    /// Whether some shadow rays are occluded (a lone convex sphere shadows nothing).
    bool casts_shadows = true;
    int width = 128;
    int height = 128;
};

class EmbreeAgreement : public testing::TestWithParam<Case> {};

TEST_P(EmbreeAgreement, HitsMatchDynrtAndPacketsMatchSingleRays) {
    const Case c = GetParam();
    const Scene scene = load_scene(c.spec);
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = c.width;
    options.height = c.height;
    const std::size_t pixels = std::size_t(options.width) * std::size_t(options.height);

    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);

    EmbreeTracer tracer;
    for (BuildQuality quality : {BuildQuality::low, BuildQuality::medium, BuildQuality::high}) {
        SCOPED_TRACE(quality_name(quality));
        EXPECT_GE(tracer.build(scene, quality), 0.0);
        PixelHits single, packet;
        tracer.intersect1(camera, options.width, options.height, single);
        tracer.intersect16(camera, options.width, options.height, packet);
        ASSERT_EQ(single.object.size(), pixels);

        const HitAgreement vs_dynrt =
            compare_hits(frame.object, frame.prim, single.object, single.prim);
        EXPECT_LE(vs_dynrt.object_differs, c.object_differs_max);
        EXPECT_LE(vs_dynrt.object_differs, pixels / 1000);  // <= 0.1% in any case
        // Shared-edge ties may pick either triangle, but only along edges.
        EXPECT_LE(vs_dynrt.prim_only_differs, pixels / 100);

        EXPECT_EQ(single.object, packet.object);
        EXPECT_EQ(single.prim, packet.prim);

        std::size_t shadow_rays = 0, shadow_rays_single = 0;
        std::vector<std::uint32_t> occluded_packet, occluded_single;
        const std::vector<PointLight> lights = effective_lights(scene, options);
        tracer.occluded16(camera, options.width, options.height, lights, single, shadow_rays,
                          &occluded_packet);
        tracer.occluded1(camera, options.width, options.height, lights, single,
                         shadow_rays_single, &occluded_single);
        // The same rule as dynrt's (one per hit and light on the lit side) on the same hits;
        // dynrt also leaves out those whose shading normal faces away from the light.
        if (vs_dynrt.object_differs == 0 && vs_dynrt.prim_only_differs == 0) {
            EXPECT_EQ(shadow_rays, frame.stats.shadow_rays + frame.stats.shadow_rays_shading_side);
        }
        EXPECT_GT(shadow_rays, 0u);
        EXPECT_EQ(shadow_rays_single, shadow_rays);
        ASSERT_EQ(occluded_packet.size(), pixels);
        EXPECT_EQ(occluded_single, occluded_packet);
        // The scenes cast shadows: some shadow rays are occluded, so the comparison above is
        // not one of two all-zero images.
        std::size_t shadowed = 0;
        for (std::uint32_t n : occluded_single) shadowed += n;
        if (c.casts_shadows) {
            EXPECT_GT(shadowed, 0u) << "no occluded shadow ray: the test compares nothing";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, EmbreeAgreement,
    testing::Values(Case{"sphere:20000", 0, false}, Case{"soup:5000", 16},
                    Case{"plane:4@0,-1,0,3+sphere:2000+soup:500@0.5,0.5,0.5,0.5", 16},
                    // Not a multiple of 4 (nor of 16) either way: partial blocks and tiles.
                    Case{"plane:4@0,-1,0,3+sphere:2000+soup:500@0.5,0.5,0.5,0.5", 12, true, 101, 77}),
    [](const testing::TestParamInfo<Case>& info) { return "scene" + std::to_string(info.index); });

}  // namespace
}  // namespace dynrt::embree

#else

TEST(EmbreeAgreement, SkippedWithoutEmbree) {
    GTEST_SKIP() << "this dynrt was built without Embree";
}

#endif
