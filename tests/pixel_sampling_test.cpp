// Samples per pixel and area lights (issue 40; dynrt/engine/pixel_sampling.h): the sample
// positions stratify the pixel, the filters' distributions are what they say and sum to one,
// a frame of samples is the same on any number of threads, adaptive anti-aliasing refines the
// edges and keeps the rest, area lights' soft shadows converge to the exact reference's
// integral over the light, and bad settings and lights are refused by name.

#include "moving_scene.h"
#include "same_bits.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"
#include "rendering/pixel_samples.h"
#include "rendering/sampled_frame.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt {
namespace {

using test::same_bits;

TEST(PixelSamples, EveryPowerOfTwoCountFillsEachStratumOnce) {
    for (const std::uint32_t pixel : {0u, 1u, 77u, 123456u}) {
        const std::uint32_t sx = detail::sample_hash(pixel, 1u), sy = detail::sample_hash(pixel, 2u);
        for (const int n : {4, 16, 64}) {
            // Every elementary interval shape of area 1/n: (n / k) columns by k rows.
            for (int rows = 1; rows <= n; rows *= 2) {
                const int cols = n / rows;
                std::set<int> cells;
                for (int s = 0; s < n; ++s) {
                    const glm::vec2 u = detail::scrambled_point(std::uint32_t(s), sx, sy);
                    ASSERT_GE(u.x, 0.0f);
                    ASSERT_LT(u.x, 1.0f);
                    ASSERT_GE(u.y, 0.0f);
                    ASSERT_LT(u.y, 1.0f);
                    cells.insert(int(u.y * float(rows)) * cols + int(u.x * float(cols)));
                }
                EXPECT_EQ(cells.size(), std::size_t(n)) << "pixel " << pixel << ", " << n << " samples, "
                                                        << cols << "x" << rows << " strata";
            }
        }
    }
}

TEST(PixelSamples, OneSamplePerPixelIsTheCentre) {
    const PixelSampling one;
    for (const std::uint32_t pixel : {0u, 5u, 99999u}) {
        EXPECT_EQ(detail::pixel_sample_offset(one, pixel, 0), glm::vec2(0.0f));
    }
}

TEST(PixelFilters, DistributionsIntegrateToOneAndOffsetsFollowThem) {
    for (const PixelFilter filter : {PixelFilter::box, PixelFilter::tent, PixelFilter::blackman_harris}) {
        SCOPED_TRACE(pixel_filter_name(filter));
        // The density's integral: the weights of the samples sum to one.
        double integral = 0.0;
        constexpr int kSteps = 40000;
        const double dx = 4.0 / kSteps;
        for (int i = 0; i < kSteps; ++i) integral += double(detail::filter_density(filter, float(-2.0 + (i + 0.5) * dx))) * dx;
        EXPECT_NEAR(integral, 1.0, 2e-3);
        // Offsets from evenly spread u: monotone, within the support, and their histogram the
        // density's (each bin's share within 0.01 of the density's integral over it).
        constexpr int kSamples = 100000, kBins = 20;
        std::vector<double> histogram(kBins, 0.0);
        float last = -std::numeric_limits<float>::infinity();
        for (int i = 0; i < kSamples; ++i) {
            const float u = (float(i) + 0.5f) / float(kSamples);
            const float x = detail::filter_offset(filter, glm::vec2(u, 0.5f)).x;
            ASSERT_GE(x, last);
            last = x;
            ASSERT_LE(std::abs(x), 1.0f);
            histogram[std::size_t(std::clamp(int((x + 1.0f) * 0.5f * kBins), 0, kBins - 1))] += 1.0 / kSamples;
        }
        for (int b = 0; b < kBins; ++b) {
            double expected = 0.0;
            const double x0 = -1.0 + 2.0 * b / kBins, x1 = x0 + 2.0 / kBins;
            for (int i = 0; i < 200; ++i) {
                expected += double(detail::filter_density(filter, float(x0 + (i + 0.5) * (x1 - x0) / 200))) * (x1 - x0) / 200;
            }
            EXPECT_NEAR(histogram[std::size_t(b)], expected, 0.01) << "bin " << b;
        }
    }
}

RenderOptions sampling_options() {
    RenderOptions options;
    options.width = 96;
    options.height = 72;
    options.reuse.mode = PixelReuse::off;
    return options;
}

TEST(SampledFrames, TheSameBitsOnAnyNumberOfThreads) {
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = sampling_options();
    options.sampling.spp = 8;
    options.lights = {PointLight{{2.0f, 3.0f, 1.0f}, 0.7f}};
    options.lights[0].shape = PointLight::Shape::sphere;
    options.lights[0].radius = 0.5f;
    RenderedFrame one, two;
    tbb::task_arena(1).execute([&] { Renderer(options).render(scene, camera, 3, one); });
    tbb::task_arena(2).execute([&] { Renderer(options).render(scene, camera, 3, two); });
    EXPECT_TRUE(same_bits(one.color, two.color));
    EXPECT_EQ(one.stats.samples_per_pixel, 8);
    EXPECT_EQ(one.stats.primary_rays, std::size_t(8 * 96 * 72));
    EXPECT_EQ(one.stats.pixels_refined, std::size_t(96 * 72));
}

TEST(SampledFrames, PixelsAreTheMeanOfTheirSamples) {
    // A view of nothing but the background: every sample is the background, so is every
    // pixel's mean (the weights sum to one).
    const Scene scene = test::moving_scene();
    Camera camera = default_camera(scene_bounds(scene));
    camera.target = camera.eye + (camera.eye - camera.target);  // looking away from the scene
    RenderOptions options = sampling_options();
    options.sampling.spp = 16;
    RenderedFrame frame;
    Renderer(options).render(scene, camera, 0, frame);
    for (const glm::vec3& c : frame.color) {
        ASSERT_NEAR(c.x, options.background.x, 1e-6f);
        ASSERT_NEAR(c.y, options.background.y, 1e-6f);
        ASSERT_NEAR(c.z, options.background.z, 1e-6f);
    }
    // And a view of the scene: samples that differ (edges) make pixels no single sample gives.
    Camera scene_camera = default_camera(scene_bounds(scene));
    RenderedFrame one, many;
    options.sampling.spp = 1;
    Renderer(options).render(scene, scene_camera, 0, one);
    options.sampling.spp = 16;
    Renderer(options).render(scene, scene_camera, 0, many);
    EXPECT_FALSE(same_bits(one.color, many.color));
}

TEST(SampledFrames, ExactReuseGivesTheFullRendersBitsWithAreaLights) {
    // Objects move rigidly, deform and explode between the frames; an area light and a point
    // light. Each sample's pass keeps its own memory: the frames must be a full render's.
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = sampling_options();
    options.sampling.spp = 4;
    options.sampling.filter = PixelFilter::tent;  // the widest reach: a pixel's samples leave it
    options.lights = {PointLight{{2.0f, 3.0f, 1.0f}, 0.5f}, PointLight{{-2.0f, 2.5f, -1.0f}, 0.6f}};
    options.lights[1].shape = PointLight::Shape::quad;
    options.lights[1].edge_u = {0.8f, 0.0f, 0.0f};
    options.lights[1].edge_v = {0.0f, 0.2f, 0.7f};
    Renderer full(options);
    options.reuse.mode = PixelReuse::exact;
    Renderer reusing(options);
    RenderedFrame a, b;
    std::size_t reused = 0;
    for (const int f : {0, 1, 2, 2, 9, 10}) {
        SCOPED_TRACE("frame " + std::to_string(f));
        full.render(scene, camera, f, a);
        reusing.render(scene, camera, f, b);
        EXPECT_TRUE(same_bits(a.color, b.color));
        EXPECT_TRUE(same_bits(a.depth, b.depth));
        EXPECT_TRUE(same_bits(a.object, b.object));
        EXPECT_EQ(b.stats.reuse_mode, "exact");
        reused += b.stats.pixels_reused;
    }
    EXPECT_GT(reused, 0u);  // the passes kept pixels: the test compares reuse, not full traces
}

TEST(SampledFrames, ExactReuseSeesChangesNearAnAreaLightsEdge) {
    // A wide quad light over a floor and, under one of its corners, a soup that explodes: it
    // changes the soft shadows of floor points whose rays from the light's centre pass far
    // from it. Exact reuse must re-trace those shadow rays (the light's whole area counts).
    const std::string soup = "soup:200@2.4,2.3,2.4,0.35#40c060";
    Scene scene = load_scene("plane:8@0,-1,0,4#808080+" + soup);
    anim::add_procedural_motions(scene, std::vector<std::string>{"explode:" + soup});
    const Camera camera{{0.0f, 6.0f, 7.0f}, {0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    RenderOptions options = sampling_options();
    options.sampling.spp = 1;
    PointLight quad{{0.0f, 3.0f, 0.0f}, 0.9f};
    quad.shape = PointLight::Shape::quad;
    quad.edge_u = {6.0f, 0.0f, 0.0f};
    quad.edge_v = {0.0f, 0.0f, 6.0f};
    options.lights = {quad};
    for (const int spp : {1, 4}) {
        SCOPED_TRACE(std::to_string(spp) + " spp");
        options.sampling.spp = spp;
        options.reuse.mode = PixelReuse::off;
        Renderer full(options);
        options.reuse.mode = PixelReuse::exact;
        Renderer reusing(options);
        RenderedFrame a, b;
        std::size_t reused = 0;
        for (int f = 0; f < 6; ++f) {
            full.render(scene, camera, f, a);
            reusing.render(scene, camera, f, b);
            EXPECT_TRUE(same_bits(a.color, b.color)) << "frame " << f;
            reused += b.stats.pixels_reused;
        }
        EXPECT_GT(reused, 0u);
    }
}

TEST(SampledFrames, TileSharesGatherIntoTheWholeFrame) {
    // A frame split across processes (TraceSettings::tiles), each share sampled and reusing
    // pixels on its own, gathers into the whole frame's bits.
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = sampling_options();
    options.sampling.spp = 4;
    options.reuse.mode = PixelReuse::exact;
    Renderer whole(options);
    std::vector<std::unique_ptr<Renderer>> shares;
    for (int k = 0; k < 3; ++k) {
        options.tiles = packet::TileShare{k, 3};
        shares.push_back(std::make_unique<Renderer>(options));
    }
    RenderedFrame all, part, gathered;
    for (const int f : {0, 1, 1}) {
        whole.render(scene, camera, f, all);
        gathered = all;
        std::fill(gathered.color.begin(), gathered.color.end(), glm::vec3(-1.0f));
        for (int k = 0; k < 3; ++k) {
            shares[std::size_t(k)]->render(scene, camera, f, part);
            packet::Tiling(all.width, all.height, packet::TileShare{k, 3}).for_each_pixel([&](std::size_t p) {
                gathered.color[p] = part.color[p];
            });
        }
        EXPECT_TRUE(same_bits(all.color, gathered.color)) << "frame " << f;
    }
}

TEST(SampledFrames, ApproximateReuseTracesEveryPixelAndSaysWhy) {
    // The render cache and frameless mode keep one sample per pixel: with several, every pixel
    // is traced, and the report names samples per pixel as the reason.
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = sampling_options();
    options.sampling.spp = 4;
    options.reuse = parse_reuse("cache:0.25");
    Renderer renderer(options);
    RenderedFrame frame;
    for (const int f : {0, 1}) {
        renderer.render(scene, camera, f, frame);
        EXPECT_EQ(frame.stats.reuse_reason, "samples per pixel");
        EXPECT_EQ(frame.stats.pixels_traced, std::size_t(96 * 72));
    }
}

/// Mean absolute difference over the channels of two images.
double mean_channel_difference(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const glm::vec3 d = glm::abs(a[i] - b[i]);
        sum += double(d.x + d.y + d.z) / 3.0;
    }
    return sum / double(a.size());
}

TEST(AdaptiveAntiAliasing, RefinesEdgesKeepsTheRestAndNearsTheFullSampling) {
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = sampling_options();
    options.width = options.height = 128;
    options.sampling.spp = 16;
    RenderedFrame full, adaptive, first;
    Renderer(options).render(scene, camera, 2, full);
    options.sampling.adaptive_contrast = 0.05f;
    Renderer(options).render(scene, camera, 2, adaptive);
    const std::size_t pixels = std::size_t(128 * 128);
    EXPECT_GT(adaptive.stats.pixels_refined, 0u);
    EXPECT_LT(adaptive.stats.pixels_refined, pixels / 2);
    EXPECT_EQ(adaptive.stats.primary_rays, pixels + 15 * adaptive.stats.pixels_refined);
    // Refined pixels are the full sampling's, bit for bit; the others their first sample's (as
    // a render refining fewer pixels shows them).
    options.sampling.spp = 16;
    options.sampling.adaptive_contrast = 1e9f;  // no colour differs by more: objects' outlines alone
    Renderer(options).render(scene, camera, 2, first);
    EXPECT_LT(first.stats.pixels_refined, adaptive.stats.pixels_refined);
    // Refined pixels are the full sampling's (their other samples traced in packets of their
    // own, so to rounding: the same rays, shading and sum order, other packet traversals);
    // the others their first sample's, bit for bit, as a render refining fewer pixels shows.
    std::size_t kept = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (std::memcmp(&adaptive.color[p], &first.color[p], sizeof(glm::vec3)) == 0) {
            ++kept;
            continue;
        }
        const glm::vec3 d = glm::abs(adaptive.color[p] - full.color[p]);
        EXPECT_LT(std::max({d.x, d.y, d.z}), 1e-4f) << "pixel " << p;
    }
    EXPECT_GE(kept, pixels - adaptive.stats.pixels_refined);
    EXPECT_LT(mean_channel_difference(adaptive.color, full.color), 0.5 * mean_channel_difference(first.color, full.color));
}

TEST(AdaptiveAntiAliasing, RefinesBothSidesOfAnEdgeAndOtherObjects) {
    RenderedFrame frame;
    frame.width = 6;
    frame.height = 4;
    frame.color.assign(24, glm::vec3(0.2f));
    std::vector<bvh::InstanceHit> hits(24);
    for (auto& h : hits) h.object = 0;
    for (int y = 0; y < 4; ++y) frame.color[std::size_t(y * 6 + 3)] = glm::vec3(0.9f);  // a bright column x = 3
    hits[std::size_t(0)].object = 1;                                                   // another object at (0, 0)
    std::vector<std::uint8_t> refined;
    EXPECT_EQ(detail::refine_pixels(frame, hits, 0.1f, refined), std::size_t(4 * 3 + 3));
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 6; ++x) {
            const bool expected = x == 2 || x == 3 || x == 4 || (y == 0 && x <= 1) || (y == 1 && x == 0);
            EXPECT_EQ(refined[std::size_t(y * 6 + x)] != 0, expected) << x << "," << y;
        }
    }
    // Colours past 1 are clamped first: a difference the image cannot show refines nothing.
    frame.color.assign(24, glm::vec3(1.5f));
    frame.color[7] = glm::vec3(3.0f);
    for (auto& h : hits) h.object = 0;
    EXPECT_EQ(detail::refine_pixels(frame, hits, 0.1f, refined), 0u);
}

TEST(AreaLights, SoftShadowsConvergeToTheReferenceIntegralOverTheLight) {
    // A floor and a sphere over it, lit by a quad light above: the reference renders the mean
    // of 16 x 16 point lights spread over the quad; dynrt samples the quad once per pixel
    // sample. Compared on floor pixels away from the sphere's outline (where the pixel's
    // samples spread over two surfaces the reference's centre ray cannot see).
    Scene scene = load_scene("plane:8@0,-1,0,4#c0c0c0+sphere:2000@0,0,0,0.6#e04020");
    const Camera camera{{0.0f, 3.5f, 3.5f}, {0.0f, -0.6f, 0.0f}, {0.0f, 1.0f, 0.0f}, 45.0f};
    PointLight quad{{0.3f, 2.0f, 0.2f}, 0.8f};
    quad.shape = PointLight::Shape::quad;
    quad.edge_u = {1.6f, 0.0f, 0.0f};
    quad.edge_v = {0.0f, 0.0f, 1.6f};
    RenderOptions options = sampling_options();
    options.width = options.height = 64;
    options.lights = {quad};
    options.sampling.spp = 256;
    options.sampling.filter = PixelFilter::box;
    RenderedFrame soft, hard;
    Renderer(options).render(scene, camera, 0, soft);
    options.lights[0].shape = PointLight::Shape::point;
    Renderer(options).render(scene, camera, 0, hard);

    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const reference::ReferenceTracer tracer(scene, posed);
    reference::ReferenceShading shading = reference::shading_from(scene, options);
    shading.lights.clear();
    constexpr int kGrid = 16;
    for (int i = 0; i < kGrid; ++i) {
        for (int j = 0; j < kGrid; ++j) {
            const float a = (float(i) + 0.5f) / kGrid - 0.5f, b = (float(j) + 0.5f) / kGrid - 0.5f;
            shading.lights.push_back(
                PointLight{quad.position + a * quad.edge_u + b * quad.edge_v, quad.intensity / (kGrid * kGrid)});
        }
    }
    const reference::ReferenceFrame exact = reference::render_reference(scene, tracer, camera, 64, 64, shading);
    double soft_error = 0.0, hard_error = 0.0, worst = 0.0;
    int compared = 0, penumbra = 0;
    for (int y = 1; y < 63; ++y) {
        for (int x = 1; x < 63; ++x) {
            bool floor_around = true;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) floor_around &= exact.at(x + dx, y + dy).hit.object == 0;
            }
            if (!floor_around) continue;
            const glm::dvec3 want = exact.at(x, y).color;
            const std::size_t p = std::size_t(y * 64 + x);
            const double e = glm::length(glm::dvec3(soft.color[p]) - want);
            soft_error += e;
            worst = std::max(worst, e);
            hard_error += glm::length(glm::dvec3(hard.color[p]) - want);
            ++compared;
            if (std::abs(double(hard.color[p].x) - want.x) > 0.05) ++penumbra;
        }
    }
    ASSERT_GT(compared, 1000);
    EXPECT_GT(penumbra, 50);  // the point light's hard shadow misses the soft one: the test can fail
    EXPECT_LT(soft_error / compared, 0.004);
    EXPECT_LT(worst, 0.06);
    EXPECT_GT(hard_error / compared, 4.0 * soft_error / compared);
}

TEST(SamplingSettings, BadValuesAreRefusedByName) {
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    const auto refused = [&](const RenderOptions& options, const std::string& words) {
        RenderedFrame frame;
        try {
            Renderer(options).render(scene, camera, 0, frame);
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            return;
        }
        ADD_FAILURE() << "not refused: " << words;
    };
    RenderOptions options = sampling_options();
    options.sampling.spp = 0;
    refused(options, "samples per pixel 0");
    options.sampling.spp = 5000;
    refused(options, "samples per pixel 5000");
    options.sampling.spp = 4;
    options.sampling.adaptive_contrast = std::numeric_limits<float>::quiet_NaN();
    refused(options, "contrast");
    options.sampling.adaptive_contrast = 0.1f;
    options.tiles = packet::TileShare{0, 2};
    refused(options, "whole image");
    options.tiles = {};
    options.sampling.adaptive_contrast = 0.0f;
    options.adaptive_tolerance = 0.1f;
    refused(options, "one sample per pixel");
    options.adaptive_tolerance = 0.0f;

    PointLight sphere{{0.0f, 3.0f, 0.0f}, 1.0f};
    sphere.shape = PointLight::Shape::sphere;
    sphere.radius = 0.0f;
    options.lights = {PointLight{{1.0f, 3.0f, 0.0f}}, sphere};
    refused(options, "light 1: a sphere light's radius");
    options.lights[1].radius = std::numeric_limits<float>::quiet_NaN();
    refused(options, "light 1: a sphere light's radius");
    PointLight quad{{0.0f, 3.0f, 0.0f}, 1.0f};
    quad.shape = PointLight::Shape::quad;
    quad.edge_u = {1.0f, 0.0f, 0.0f};
    quad.edge_v = {2.0f, 0.0f, 0.0f};
    options.lights = {quad};
    refused(options, "light 0: a quad light's edges");
    EXPECT_THROW(parse_pixel_filter("gauss"), std::invalid_argument);
    EXPECT_EQ(parse_pixel_filter("blackman-harris"), PixelFilter::blackman_harris);
}

}  // namespace
}  // namespace dynrt
