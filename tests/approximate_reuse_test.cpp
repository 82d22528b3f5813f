// The approximate pixel reuse modes (PixelReuse::render_cache and frameless;
// engine/src/rendering/approximate_reuse.h) against full renders of the same frames: with the
// whole image as budget they are the full render; with less, a still scene converges to it in
// as many frames as the budget needs to cover the image; pixels that show a moving object are
// always exact under the render cache; and a small camera move keeps the error bounded.

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bench/image_metrics.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace dynrt {
namespace {

const std::string kPlane = "plane:8@0,-1,0,4#808080";
const std::string kBall = "sphere:600@-0.8,-0.4,0.3,0.6#e04020";
const std::string kOther = "sphere:300@1.2,-0.5,-0.6,0.5#2050e0";

/// The largest difference of any colour channel between two frames.
float max_colour_difference(const RenderedFrame& a, const RenderedFrame& b) {
    EXPECT_EQ(a.color.size(), b.color.size());
    float worst = 0.0f;
    for (std::size_t p = 0; p < a.color.size() && p < b.color.size(); ++p) {
        const glm::vec3 d = glm::abs(a.color[p] - b.color[p]);
        worst = std::max({worst, d.x, d.y, d.z});
    }
    return worst;
}

double psnr(const RenderedFrame& test, const RenderedFrame& reference) {
    return psnr_db(display_image(test), display_image(reference));
}

RenderOptions small_options(const std::string& reuse) {
    RenderOptions options;
    options.width = 96;  // edge tiles and 8x8 blocks clipped on one axis
    options.height = 80;
    options.reuse = parse_reuse(reuse);
    options.method = UpdateMethod::threshold;
    return options;
}

/// A camera circling the scene's centre by `step` small steps.
Camera orbiting(const Camera& start, int step) {
    Camera c = start;
    const glm::vec3 arm = start.eye - start.target;
    const float angle = 0.004f * float(step);
    c.eye = start.target + glm::vec3(arm.x * std::cos(angle) - arm.z * std::sin(angle), arm.y,
                                     arm.x * std::sin(angle) + arm.z * std::cos(angle));
    return c;
}

TEST(ApproximateReuse, WholeImageBudgetIsTheFullRender) {
    Scene scene = load_scene(kPlane + "+" + kBall + "+" + kOther);
    anim::add_procedural_motions(scene, std::vector<std::string>{"rigid:" + kBall, "wave:" + kOther});
    const Camera start = default_camera(scene_bounds(scene));
    for (const std::string mode : {"cache:1", "frameless:1"}) {
        SCOPED_TRACE(mode);
        Renderer approximate(small_options(mode));
        Renderer full(small_options("off"));
        RenderedFrame a, b;
        for (int f = 0; f < 6; ++f) {
            SCOPED_TRACE("frame " + std::to_string(f));
            const Camera camera = orbiting(start, f / 2);  // still, then moved, in turn
            approximate.render(scene, camera, f, a);
            full.render(scene, camera, f, b);
            EXPECT_EQ(a.stats.reuse_mode, mode.substr(0, mode.find(':')));
            EXPECT_EQ(a.stats.pixels_traced, a.color.size());
            EXPECT_EQ(a.stats.pixels_filled, 0u);
            EXPECT_EQ(max_colour_difference(a, b), 0.0f);
            EXPECT_EQ(a.object, b.object);
            EXPECT_EQ(a.prim, b.prim);
            EXPECT_EQ(a.depth, b.depth);
        }
    }
}

// A still camera over a still scene: a budget of a quarter of the image reaches every pixel
// within four frames (untraced pixels rank first as holes, then by age), after which the frame
// is the full render; before that its error shrinks.
TEST(ApproximateReuse, StillSceneConvergesToTheFullRender) {
    const Scene scene = load_scene(kPlane + "+" + kBall + "+" + kOther);
    const Camera camera = default_camera(scene_bounds(scene));
    for (const std::string mode : {"cache:0.25", "frameless:0.25"}) {
        SCOPED_TRACE(mode);
        Renderer approximate(small_options(mode));
        Renderer full(small_options("off"));
        RenderedFrame a, b;
        full.render(scene, camera, 0, b);
        double last_psnr = 0.0;
        for (int f = 0; f < 6; ++f) {
            SCOPED_TRACE("frame " + std::to_string(f));
            approximate.render(scene, camera, f, a);
            // Blocks at the budget's rank are drawn at random (by a hash of block and frame),
            // so the count is about a quarter.
            EXPECT_LE(a.stats.pixels_traced, a.color.size() * 2 / 5);
            EXPECT_GE(a.stats.pixels_traced, a.color.size() / 6);
            if (f < 3) {
                EXPECT_GT(max_colour_difference(a, b), 0.0f);  // not every pixel traced yet
                const double p = psnr(a, b);
                EXPECT_GT(p, last_psnr);
                last_psnr = p;
            } else {
                EXPECT_EQ(max_colour_difference(a, b), 0.0f);
                EXPECT_EQ(a.stats.pixels_filled, 0u);
            }
        }
    }
}

// The render cache never shows a moving object stale: every pixel where the full render sees
// the moving ball is exact, whatever the budget, while the camera moves too; and the error of
// the whole frame stays bounded under a small camera move. The camera holds still for the
// first frames, while the budget fills the cache.
TEST(ApproximateReuse, RenderCacheKeepsMovingObjectsExactAndErrorBounded) {
    Scene scene = load_scene(kPlane + "+" + kBall + "+" + kOther);
    anim::add_procedural_motions(scene, std::vector<std::string>{"rigid:" + kBall});
    const Camera start = default_camera(scene_bounds(scene));
    Renderer approximate(small_options("cache:0.25"));
    Renderer full(small_options("off"));
    RenderedFrame a, b;
    double worst_psnr = 1e9;
    std::size_t ball_pixels = 0, traced = 0;
    constexpr int kStill = 5, kFrames = 14;
    for (int f = 0; f < kFrames; ++f) {
        SCOPED_TRACE("frame " + std::to_string(f));
        const Camera camera = orbiting(start, std::max(0, f - kStill));
        approximate.render(scene, camera, f, a);
        full.render(scene, camera, f, b);
        for (std::size_t p = 0; p < b.color.size(); ++p) {
            if (b.object[p] != 1) continue;  // the ball is object 1
            ++ball_pixels;
            ASSERT_EQ(a.object[p], 1) << "pixel " << p;
            ASSERT_EQ(a.color[p], b.color[p]) << "pixel " << p;
        }
        if (f > kStill) {
            worst_psnr = std::min(worst_psnr, psnr(a, b));
            EXPECT_NE(a.stats.reuse_reason.find("camera moved: reprojected"), std::string::npos)
                << a.stats.reuse_reason;
            EXPECT_GT(a.stats.pixels_reused, a.color.size() / 2);
            traced += a.stats.pixels_traced;
        }
    }
    EXPECT_GT(ball_pixels, 500u);
    // Well under a full trace per moving frame.
    EXPECT_LT(traced, a.color.size() * (kFrames - kStill - 1) / 2);
    std::printf("render cache, worst PSNR %.2f dB\n", worst_psnr);
    EXPECT_GT(worst_psnr, 30.0);
}

// Frameless rendering keeps samples in place when the camera moves, so its error grows with
// the move; the render cache, which reprojects them, is nearer the full render on the same
// budget.
TEST(ApproximateReuse, ReprojectionBeatsKeepingSamplesInPlace) {
    const Scene scene = load_scene(kPlane + "+" + kBall + "+" + kOther);
    const Camera start = default_camera(scene_bounds(scene));
    Renderer cache(small_options("cache:0.25"));
    Renderer frameless(small_options("frameless:0.25"));
    Renderer full(small_options("off"));
    RenderedFrame c, fl, b;
    double cache_psnr = 0.0, frameless_psnr = 0.0;
    for (int f = 0; f < 8; ++f) {
        const Camera camera = orbiting(start, 8 * std::max(0, f - 4));
        cache.render(scene, camera, f, c);
        frameless.render(scene, camera, f, fl);
        full.render(scene, camera, f, b);
        if (f < 5) continue;  // still until frame 4
        cache_psnr += psnr(c, b);
        frameless_psnr += psnr(fl, b);
    }
    std::printf("mean PSNR over 3 moving frames: render cache %.2f dB, frameless %.2f dB\n",
                cache_psnr / 3.0, frameless_psnr / 3.0);
    EXPECT_GT(cache_psnr, frameless_psnr + 3 * 1.5);  // 1.5 dB better per frame on average
}

TEST(ApproximateReuse, BudgetInMillisecondsTracesPartOfTheImage) {
    const Scene scene = load_scene(kPlane + "+" + kBall + "+" + kOther);
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options = small_options("frameless:0.001ms");
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);  // no measured cost yet: the whole image
    EXPECT_EQ(frame.stats.pixels_traced, frame.color.size());
    renderer.render(scene, camera, 1, frame);  // a microsecond: one block at the least
    EXPECT_GE(frame.stats.pixels_traced, 1u);
    EXPECT_LT(frame.stats.pixels_traced, frame.color.size() / 4);
}

}  // namespace
}  // namespace dynrt
