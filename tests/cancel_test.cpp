// Stopping a frame part way (Renderer::cancel, FramePipeline::cancel): a trace asked to stop
// from another thread returns with FrameStats::cancelled, and the next frame, which may not
// reuse anything of the incomplete one, is exactly a fresh renderer's. A cancel between frames
// changes nothing.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace dynrt {
namespace {

RenderedFrame fresh_render(const Scene& scene, const RenderOptions& options, const Camera& camera) {
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    return frame;
}

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
    EXPECT_EQ(next.color, fresh_render(scene, options, b).color);
    renderer.render(scene, a, 0, next);
    EXPECT_EQ(next.color, fresh_render(scene, options, a).color);
    EXPECT_FALSE(fresh_render(scene, options, b).stats.cancelled);
}

}  // namespace
}  // namespace dynrt
