// The error of a frame against the exact reference on sampled pixels (tests/reference/
// frame_error.h): the sample is stratified and reproducible, a frame agrees with its own
// scene's reference, and each kind of corruption is counted where it belongs.

#include "dynrt/reference/frame_error.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

namespace dynrt::reference {
namespace {

TEST(StratifiedPixels, OnePixelInsideEveryBlockEdgesIncluded) {
    const std::vector<PixelCoord> pixels = stratified_pixels(20, 13, 8);
    ASSERT_EQ(pixels.size(), 3u * 2u);  // blocks cut at x = 16..19 and y = 8..12 count too
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        const int bx = int(i % 3), by = int(i / 3);
        EXPECT_GE(pixels[i].x, bx * 8);
        EXPECT_LT(pixels[i].x, std::min(20, bx * 8 + 8));
        EXPECT_GE(pixels[i].y, by * 8);
        EXPECT_LT(pixels[i].y, std::min(13, by * 8 + 8));
    }
}

TEST(StratifiedPixels, BlockOneIsEveryPixelAndTheSeedFixesTheChoice) {
    const std::vector<PixelCoord> all = stratified_pixels(5, 3, 1);
    ASSERT_EQ(all.size(), 15u);
    for (std::size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(all[i].x, int(i % 5));
        EXPECT_EQ(all[i].y, int(i / 5));
    }
    const auto as_set = [](const std::vector<PixelCoord>& p) {
        std::set<std::pair<int, int>> s;
        for (const PixelCoord& c : p) s.insert({c.x, c.y});
        return s;
    };
    EXPECT_EQ(as_set(stratified_pixels(64, 64, 8)), as_set(stratified_pixels(64, 64, 8)));
    EXPECT_NE(as_set(stratified_pixels(64, 64, 8, 1)), as_set(stratified_pixels(64, 64, 8, 2)));
    // Not a regular grid: the offsets within the blocks vary.
    std::set<std::pair<int, int>> offsets;
    for (const PixelCoord& c : stratified_pixels(64, 64, 8)) offsets.insert({c.x % 8, c.y % 8});
    EXPECT_GT(offsets.size(), 10u);
    EXPECT_THROW(stratified_pixels(0, 4, 1), std::invalid_argument);
    EXPECT_THROW(stratified_pixels(4, 4, 0), std::invalid_argument);
}

/// A small scene rendered by dynrt and its reference at every pixel.
struct Rendered {
    RenderedFrame frame;
    std::vector<PixelCoord> pixels;
    std::vector<ReferencePixel> reference;
};

Rendered render_both(int width, int height) {
    const Scene scene = load_scene("plane:2@0,-1,0,3+sphere:500");
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = width;
    options.height = height;
    Rendered out;
    Renderer(options).render(scene, camera, 0, out.frame);
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const ReferenceTracer tracer(scene, posed);
    out.pixels = stratified_pixels(width, height, 1);
    out.reference = render_reference_pixels(scene, tracer, camera, width, height, out.pixels,
                                            shading_from(scene, options));
    return out;
}

TEST(RenderReferencePixels, MatchesTheFullReferenceAtThoseShuffledPixels) {
    const Scene scene = load_scene("sphere:300");
    const Camera camera = default_camera(scene_bounds(scene));
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const ReferenceTracer tracer(scene, posed);
    const ReferenceShading shading = shading_from(scene, RenderOptions{});
    const ReferenceFrame full = render_reference(scene, tracer, camera, 24, 16, shading);
    const std::vector<PixelCoord> pixels = {{23, 15}, {0, 0}, {12, 8}, {5, 11}, {12, 8}};
    const std::vector<ReferencePixel> some =
        render_reference_pixels(scene, tracer, camera, 24, 16, pixels, shading);
    ASSERT_EQ(some.size(), pixels.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        const ReferencePixel& want = full.at(pixels[i].x, pixels[i].y);
        EXPECT_EQ(some[i].hit.object, want.hit.object) << i;
        EXPECT_EQ(some[i].hit.prim, want.hit.prim) << i;
        EXPECT_EQ(some[i].color, want.color) << i;
    }
    const std::vector<PixelCoord> outside = {{24, 0}};
    EXPECT_THROW(render_reference_pixels(scene, tracer, camera, 24, 16, outside, shading),
                 std::out_of_range);
}

TEST(FrameError, AFrameAgreesWithItsOwnSceneReference) {
    const Rendered r = render_both(48, 40);
    const FrameError e = frame_error(r.frame, r.pixels, r.reference);
    EXPECT_EQ(e.samples, 48 * 40);
    EXPECT_EQ(e.determined_differs, 0);
    EXPECT_EQ(e.hit_differs, e.ambiguous_differs);
    EXPECT_LT(e.ambiguous_differs, e.samples / 50);
    // Float against double shading: tiny colour differences (~1e-7), none on the scale of a
    // wrong hit or shadow (~0.1). The bounds leave room for a light the reference calls
    // ambiguous at a shadow's edge.
    EXPECT_LT(e.rmse, 1e-2);
    EXPECT_GT(e.psnr_db, 40.0);
}

TEST(FrameError, ACorruptedObjectPrimitiveOrColourIsCounted) {
    const Rendered clean = render_both(48, 40);
    const FrameError base = frame_error(clean.frame, clean.pixels, clean.reference);
    // Two determined hits (ambiguity kNone) on the sphere (object 1).
    std::vector<std::size_t> picks;
    for (std::size_t k = 0; k < clean.pixels.size() && picks.size() < 2; ++k) {
        const ReferencePixel& ref = clean.reference[k];
        if (ref.hit.object == 1 && ref.hit.ambiguity == Ambiguity::kNone) picks.push_back(k);
    }
    ASSERT_EQ(picks.size(), 2u);
    const auto index = [&](std::size_t k) {
        return std::size_t(clean.pixels[k].y) * 48 + std::size_t(clean.pixels[k].x);
    };

    Rendered bad = clean;
    bad.frame.object[index(picks[0])] = 0;  // the plane instead of the sphere
    bad.frame.prim[index(picks[1])] += 1;   // the neighbouring triangle
    const FrameError e = frame_error(bad.frame, bad.pixels, bad.reference);
    EXPECT_EQ(e.hit_differs, base.hit_differs + 2);
    EXPECT_EQ(e.determined_differs, 2);
    EXPECT_EQ(e.ambiguous_differs, base.ambiguous_differs);
    EXPECT_EQ(e.rmse, base.rmse);  // hits changed, colours did not

    Rendered dark = clean;
    dark.frame.color[index(picks[0])] += glm::vec3(0.5f, 0.0f, 0.0f);
    const FrameError c = frame_error(dark.frame, dark.pixels, dark.reference);
    EXPECT_EQ(c.determined_differs, 0);
    // One channel of one sample off by 0.5: mse grows by about 0.25 / (3 samples).
    EXPECT_NEAR(c.mse, base.mse + 0.25 / (3.0 * c.samples), 1e-6);
    EXPECT_LT(c.psnr_db, base.psnr_db - 10.0);
}

TEST(FrameError, IdenticalColoursGiveInfinitePsnr) {
    RenderedFrame frame;
    frame.width = 2;
    frame.height = 1;
    frame.color = {glm::vec3(0.25f), glm::vec3(0.5f, 0.125f, 1.0f)};
    frame.object = {-1, 3};
    frame.prim = {-1, 7};
    std::vector<ReferencePixel> ref(2);
    ref[0].color = glm::dvec3(0.25);
    ref[1].color = glm::dvec3(0.5, 0.125, 1.0);
    ref[1].hit.object = 3;
    ref[1].hit.prim = 8;  // only the primitive differs, and the reference allows it
    ref[1].hit.ambiguity = Ambiguity::kPrimitive;
    const std::vector<PixelCoord> pixels = {{0, 0}, {1, 0}};
    const FrameError e = frame_error(frame, pixels, ref);
    EXPECT_EQ(e.mse, 0.0);
    EXPECT_TRUE(std::isinf(e.psnr_db));
    EXPECT_EQ(format_psnr(e.psnr_db), "inf");
    EXPECT_EQ(format_psnr(48.26), "48.3");
    EXPECT_EQ(e.hit_differs, 1);
    EXPECT_EQ(e.determined_differs, 0);
    EXPECT_EQ(e.ambiguous_differs, 1);
    EXPECT_EQ(e.ambiguous_samples, 1);

    frame.object.clear();  // no hit buffers
    EXPECT_THROW(frame_error(frame, pixels, ref), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt::reference
