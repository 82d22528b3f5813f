// Stopping a frame part way (Renderer::cancel, FramePipeline::cancel): a trace asked to stop
// from another thread returns with FrameStats::cancelled, and the next frame, which may not
// reuse anything of the incomplete one, is exactly a fresh renderer's. A cancel between frames
// changes nothing. Progress (Renderer::progress) counts each tile pass of a frame once, in
// every mode.

#include "moving_scene.h"

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include "reference_shot.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <vector>
#include <thread>

namespace dynrt {
namespace {

using test::renderer_shot;

TEST(Cancel, AStoppedTraceReturnsAndTheNextFrameIsWhole) {
    const Scene scene = load_scene("sphere:100000+plane:4@0,-1,0,4#808080");
    RenderOptions options;
    options.width = 320;
    options.height = 240;
    options.sampling.spp = 4;
    options.reuse.mode = PixelReuse::exact;
    Camera a = default_camera(scene_bounds(scene));
    Camera b = a;
    b.eye.x += 0.5f;
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, a, 0, frame);
    renderer.cancel();  // between frames: nothing happens
    // Frame b, stopped from this thread as soon as its trace runs (cancel does nothing
    // during the update, so it is asked again until the frame returns).
    std::atomic<bool> finished{false};
    RenderedFrame stopped;
    std::thread render([&] {
        renderer.render(scene, b, 0, stopped);
        finished = true;
    });
    while (!finished) {
        renderer.cancel();
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    render.join();
    EXPECT_TRUE(stopped.stats.cancelled);
    // The next frames are whole: b, then a, each a fresh renderer's, bit for bit.
    RenderedFrame next;
    renderer.render(scene, b, 0, next);
    EXPECT_FALSE(next.stats.cancelled);
    EXPECT_EQ(next.color, renderer_shot(scene, b, options).color);
    renderer.render(scene, a, 0, next);
    EXPECT_EQ(next.color, renderer_shot(scene, a, options).color);
    EXPECT_FALSE(renderer_shot(scene, b, options).stats.cancelled);
}

// After a whole frame, every tile of the trace's share was counted once per sample pass: no
// mode skips the count or counts a tile twice.
TEST(Progress, EveryModeCountsEachTilePassOnce) {
    const Scene scene = test::moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    struct Mode {
        const char* name;
        std::function<void(RenderOptions&)> set;
    };
    const std::vector<Mode> modes = {
        {"reuse off", [](RenderOptions& o) { o.reuse.mode = PixelReuse::off; }},
        {"exact reuse", [](RenderOptions&) {}},
        {"render cache", [](RenderOptions& o) { o.reuse.mode = PixelReuse::render_cache; }},
        {"frameless", [](RenderOptions& o) { o.reuse.mode = PixelReuse::frameless; }},
        {"adaptive sampling", [](RenderOptions& o) { o.adaptive_tolerance = 0.05f; }},
        {"4 spp", [](RenderOptions& o) { o.sampling.spp = 4; o.reuse.mode = PixelReuse::off; }},
        {"4 spp exact reuse", [](RenderOptions& o) { o.sampling.spp = 4; }},
        {"4 spp adaptive aa", [](RenderOptions& o) { o.sampling.spp = 4; o.sampling.adaptive_contrast = 0.05f; }},
        {"tile share", [](RenderOptions& o) { o.tiles = packet::TileShare{1, 3}; }},
        {"single rays", [](RenderOptions& o) { o.tracer = Tracer::single; }},
    };
    for (const Mode& mode : modes) {
        SCOPED_TRACE(mode.name);
        RenderOptions options;
        options.width = 72;
        options.height = 40;
        mode.set(options);
        Renderer renderer(options);
        EXPECT_EQ(renderer.progress().tiles_total, 0u);
        const std::size_t tiles = std::size_t(packet::Tiling(72, 40, options.tiles).count());
        std::size_t passes = tiles * std::size_t(options.sampling.spp);
        RenderedFrame frame;
        for (const int f : {0, 1, 2}) {
            renderer.render(scene, camera, f, frame);
            if (options.sampling.adaptive_contrast > 0.0f) {
                // One pass over the tiles, then the refined pixels' other samples, 256 to a
                // tile pass.
                const std::size_t samples = frame.stats.pixels_refined * std::size_t(options.sampling.spp - 1);
                passes = tiles + (samples + 255) / 256;
                EXPECT_GT(frame.stats.pixels_refined, 0u) << "nothing refined: the case tests nothing";
            }
            const RenderProgress p = renderer.progress();
            EXPECT_FALSE(p.tracing) << "frame " << f;
            EXPECT_EQ(p.tiles_total, passes) << "frame " << f;
            EXPECT_EQ(p.tiles_done, passes) << "frame " << f;
        }
    }
}

}  // namespace
}  // namespace dynrt
