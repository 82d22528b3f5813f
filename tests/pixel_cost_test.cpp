// The cost view (dynrt/engine/pixel_cost.h, TraceSettings::pixel_cost, `--aov cost`): each
// pixel's camera-ray work must be the single-ray tracer's work for that ray, add up to what the
// frame's counters report, show misses as cheap and a scrambled refit as dearer than a
// rebuild, respect tile shares, and be written and drawn as documented.

#include "moving_scene.h"

#include "dynrt/engine/camera.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/pixel_cost.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/packet/pinhole.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

namespace dynrt {
namespace pixel_cost_test {

RenderOptions cost_options(int width, int height) {
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.pixel_cost = true;
    return options;
}

std::uint64_t total(const std::vector<PixelCost>& costs, CostMeasure measure) {
    std::uint64_t sum = 0;
    for (const PixelCost& c : costs) sum += cost_of(c, measure);
    return sum;
}

// The camera rays alone (a light of no intensity casts no shadow rays), traced by the
// single-ray tracer with its counters on: the frame's node visits and triangle tests are the
// camera rays', which the cost pass counts again ray by ray.
TEST(PixelCost, AddsUpToTheSingleRayTracersWorkOnTheCameraRays) {
    const Scene scene = test::moving_scene();
    RenderOptions options = cost_options(96, 64);
    options.tracer = Tracer::single;
    options.count_packet_work = true;
    options.reuse.mode = PixelReuse::off;
    PointLight dark;
    dark.position = glm::vec3(0.0f, 5.0f, 0.0f);
    dark.intensity = 0.0f;
    options.lights = {dark};
    Renderer renderer(options);
    const Camera camera = default_camera(scene_bounds(scene));
    RenderedFrame frame;
    for (const int f : {0, 7}) {
        SCOPED_TRACE("frame " + std::to_string(f));
        renderer.render(scene, camera, f, frame);
        ASSERT_EQ(frame.cost.size(), std::size_t(96 * 64));
        ASSERT_EQ(frame.stats.shadow_rays, 0u);
        EXPECT_GT(frame.stats.nodes_visited, 0u);
        EXPECT_EQ(total(frame.cost, CostMeasure::nodes), frame.stats.nodes_visited);
        EXPECT_EQ(total(frame.cost, CostMeasure::triangles), frame.stats.ray_triangle_tests);
    }
}

TEST(PixelCost, IsLeftEmptyWhenNotAskedFor) {
    const Scene scene = load_scene("sphere:500");
    RenderOptions options = cost_options(32, 32);
    options.pixel_cost = false;
    Renderer renderer(options);
    RenderedFrame frame;
    frame.cost.assign(5, PixelCost{1, 1});  // a previous frame's, which must not stay
    renderer.render(scene, default_camera(scene_bounds(scene)), 0, frame);
    EXPECT_TRUE(frame.cost.empty());
}

// A ray that misses the scene's box tests no triangle; one through the middle of a sphere
// tests some; the images do not depend on the cost pass.
TEST(PixelCost, MissesAreCheapAndTheImageIsUnchanged) {
    const Scene scene = load_scene("sphere:4000");
    Camera camera;
    camera.eye = glm::vec3(0.0f, 0.0f, 6.0f);
    camera.target = glm::vec3(0.0f);
    RenderOptions options = cost_options(64, 64);
    Renderer with_cost(options);
    options.pixel_cost = false;
    Renderer without(options);
    RenderedFrame a, b;
    with_cost.render(scene, camera, 0, a);
    without.render(scene, camera, 0, b);
    EXPECT_EQ(a.color, b.color);
    EXPECT_EQ(a.cost[0].triangles, 0u);                        // the corner misses
    EXPECT_GT(a.cost[32 * 64 + 32].triangles, 0u);             // the middle hits
    EXPECT_GT(a.cost[32 * 64 + 32].nodes, a.cost[0].nodes);
}

// Pixel by pixel: a pixel whose camera ray hit a triangle tested at least that one; a pixel
// whose ray missed the whole scene's box (checked with margin in double) tested none.
TEST(PixelCost, EachPixelsCostIsItsOwnRays) {
    const Scene scene = load_scene("plane:2@-1,0.5,0,1#808080+sphere:300@0.8,-0.4,0,0.5#e04020");
    Camera camera;
    camera.eye = glm::vec3(0.3f, 0.2f, 4.0f);
    camera.target = glm::vec3(0.0f);
    const int width = 77, height = 53;
    Renderer renderer(cost_options(width, height));
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    const bvh::Aabb box = scene_bounds(scene);
    const packet::PinholeRays rays(camera, width, height);
    int hits = 0, far_misses = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
            if (frame.object[p] >= 0) {
                ++hits;
                EXPECT_GE(frame.cost[p].triangles, 1u) << x << "," << y;
                continue;
            }
            // Slab test of the scene's box grown by 5% of its size: a miss of that is a miss.
            const bvh::Ray ray = rays.ray(x, y);
            double t0 = 0.0, t1 = 1e30;
            for (int a = 0; a < 3; ++a) {
                const double pad = 0.05 * (double(box.hi[a]) - double(box.lo[a])) + 1e-3;
                const double lo = double(box.lo[a]) - pad, hi = double(box.hi[a]) + pad;
                const double o = ray.org[a], d = ray.dir[a];
                if (d == 0.0) {
                    if (o < lo || o > hi) t1 = -1.0;
                    continue;
                }
                double n = (lo - o) / d, f = (hi - o) / d;
                if (n > f) std::swap(n, f);
                t0 = std::max(t0, n);
                t1 = std::min(t1, f);
            }
            if (t0 > t1) {
                ++far_misses;
                EXPECT_EQ(frame.cost[p].triangles, 0u) << x << "," << y;
            }
        }
    }
    EXPECT_GT(hits, 200);
    EXPECT_GT(far_misses, 200);
}

// The soup explodes: refitted frame after frame its boxes grow over each other, and its rays
// pay for it; rebuilt every frame they do not. The view must show that difference.
TEST(PixelCost, ShowsWhatARebuildBuysOverARefit) {
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    std::uint64_t cost[2] = {0, 0};
    const UpdateMethod methods[2] = {UpdateMethod::refit, UpdateMethod::sah};
    for (int m = 0; m < 2; ++m) {
        RenderOptions options = cost_options(128, 96);
        options.method = methods[m];
        Renderer renderer(options);
        RenderedFrame frame;
        for (const int f : {0, 10, 20, 30}) renderer.render(scene, camera, f, frame);
        cost[m] = total(frame.cost, CostMeasure::triangles);
    }
    EXPECT_GT(cost[0], cost[1] + cost[1] / 4) << "refit " << cost[0] << ", rebuild " << cost[1];
}

// A tile share's pixels get the whole frame's costs; the others stay 0.
TEST(PixelCost, FollowsTheTileShare) {
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = cost_options(80, 48);
    Renderer whole(options);
    options.tiles = packet::TileShare{1, 3};
    Renderer share(options);
    RenderedFrame all, part;
    whole.render(scene, camera, 3, all);
    share.render(scene, camera, 3, part);
    ASSERT_EQ(part.cost.size(), all.cost.size());
    std::vector<bool> in_share(all.cost.size(), false);
    packet::Tiling(80, 48, options.tiles).for_each_pixel([&](std::size_t i) { in_share[i] = true; });
    std::size_t inside = 0;
    for (std::size_t i = 0; i < all.cost.size(); ++i) {
        if (in_share[i]) {
            ++inside;
            EXPECT_EQ(part.cost[i], all.cost[i]) << "pixel " << i;
        } else {
            EXPECT_EQ(part.cost[i], PixelCost{}) << "pixel " << i;
        }
    }
    EXPECT_GT(inside, 0u);
    EXPECT_LT(inside, all.cost.size());
}

TEST(PixelCost, ScaleIsARoundNumberAboveMostPixels) {
    std::vector<PixelCost> costs(100);
    for (std::size_t i = 0; i < costs.size(); ++i) costs[i] = PixelCost{std::uint32_t(i), std::uint32_t(3 * i)};
    costs[99].nodes = 100000;  // one extreme pixel does not set the scale
    EXPECT_EQ(cost_scale(costs, CostMeasure::nodes), 100u);    // 99th percentile 98 -> 100
    EXPECT_EQ(cost_scale(costs, CostMeasure::triangles), 500u);  // 294 -> 500
    EXPECT_EQ(cost_scale({}, CostMeasure::nodes), 1u);
    EXPECT_EQ(cost_scale(std::vector<PixelCost>(4), CostMeasure::nodes), 1u);
    EXPECT_EQ(cost_scale(std::vector<PixelCost>(4, PixelCost{13, 0}), CostMeasure::nodes), 20u);
}

TEST(PixelCost, HeatMapRunsFromBlackToWhiteGettingBrighter) {
    std::vector<PixelCost> costs;
    for (std::uint32_t n = 0; n <= 60; ++n) costs.push_back(PixelCost{n, 0});
    const std::vector<std::uint8_t> rgb = cost_heat_rgb8(costs, CostMeasure::nodes, 50);
    ASSERT_EQ(rgb.size(), costs.size() * 3);
    EXPECT_EQ(rgb[0] + rgb[1] + rgb[2], 0);
    int last = -1;
    for (std::size_t i = 0; i < costs.size(); ++i) {
        const int brightness = rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2];
        EXPECT_GE(brightness, last) << "cost " << i;
        last = brightness;
        if (i >= 50) {
            EXPECT_EQ(brightness, 3 * 255) << "cost " << i;  // at and above the scale
        }
    }
    EXPECT_LT(rgb[3 * 25] + rgb[3 * 25 + 1] + rgb[3 * 25 + 2], 3 * 255);
    EXPECT_THROW(cost_heat_rgb8(costs, CostMeasure::nodes, 0), std::invalid_argument);
}

// `--aov cost`: two float channels named nodes and triangles, the counts exactly.
TEST(PixelCost, AovWritesBothCountsAsNamedChannels) {
    const Scene scene = load_scene("sphere:800");
    Renderer renderer(cost_options(40, 24));
    RenderedFrame frame;
    renderer.render(scene, default_camera(scene_bounds(scene)), 0, frame);
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "dynrt_pixel_cost_test";
    std::filesystem::create_directories(dir);
    const std::filesystem::path image = dir / "frame.png";
    write_aov(image, Aov::cost, frame);
    const std::filesystem::path path = aov_path(image, Aov::cost);
    EXPECT_EQ(path.filename(), "frame.cost.exr");
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    ASSERT_EQ(spec.nchannels, 2);
    EXPECT_EQ(spec.channelnames[0], "nodes");
    EXPECT_EQ(spec.channelnames[1], "triangles");
    std::vector<float> data(std::size_t(40 * 24 * 2));
    ASSERT_TRUE(in->read_image(0, 0, 0, 2, OIIO::TypeDesc::FLOAT, data.data()));
    for (std::size_t i = 0; i < frame.cost.size(); ++i) {
        ASSERT_EQ(data[2 * i], float(frame.cost[i].nodes)) << "pixel " << i;
        ASSERT_EQ(data[2 * i + 1], float(frame.cost[i].triangles)) << "pixel " << i;
    }
    EXPECT_GT(total(frame.cost, CostMeasure::triangles), 0u);
    frame.cost.clear();
    EXPECT_THROW(write_aov(image, Aov::cost, frame), std::invalid_argument);
    EXPECT_EQ(parse_aov_list("depth,cost"), (std::vector<Aov>{Aov::depth, Aov::cost}));
    EXPECT_STREQ(aov_name(Aov::cost), "cost");
    std::filesystem::remove_all(dir);
}

}  // namespace pixel_cost_test
}  // namespace dynrt
