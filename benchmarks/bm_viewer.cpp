// What `dynrt view`'s model adds to a frame, without a window (issue 42: the viewer's overhead
// over `dynrt render` of the same frames at most 5%): the bundled scene at 640x480, the camera
// orbiting one degree per frame (every frame traced in full, as while a user drags), rendered
// by ViewerSession::render plus the bytes the window draws (display_bytes), against
// Renderer::render of the same cameras plus the bytes `dynrt render` encodes for its PNG
// (display_rgb8). Interleave the two with --benchmark_repetitions and compare medians; the
// window's own drawing is measured by benchmarks/viewer_loop.sh.

#include "viewer_session.h"

#include "dynrt/engine/image_output.h"
#include "dynrt/engine/renderer.h"

#include <benchmark/benchmark.h>

namespace {

using dynrt::viewer::ViewArgs;
using dynrt::viewer::ViewerSession;

ViewArgs bundled_scene() {
    ViewArgs args;
    args.scene = DYNRT_BUNDLED_SCENE;
    args.res = "640x480";
    return args;
}

void BM_ViewerSessionFrame(benchmark::State& state) {
    ViewerSession session(bundled_scene());
    session.render();
    for (auto _ : state) {
        session.camera().orbit(1.0f, 0.0f);
        session.render();
        benchmark::DoNotOptimize(session.display_bytes());
    }
}

void BM_RendererFrame(benchmark::State& state) {
    ViewerSession session(bundled_scene());  // the same scene, options and first camera
    dynrt::Renderer renderer(session.options());
    dynrt::RenderedFrame frame;
    renderer.render(session.scene(), session.camera().camera(), 0, frame);
    for (auto _ : state) {
        session.camera().orbit(1.0f, 0.0f);
        renderer.render(session.scene(), session.camera().camera(), 0, frame);
        benchmark::DoNotOptimize(dynrt::display_rgb8(frame, session.display()));
    }
}

BENCHMARK(BM_ViewerSessionFrame)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_RendererFrame)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
