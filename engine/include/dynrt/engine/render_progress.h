#pragma once
// How far the frame being traced has come (Renderer::progress, the library API's
// Engine::render_progress), readable from another thread while a render runs: a window's
// progress bar, a job's status line, the decision to cancel a render (Renderer::cancel).

#include <algorithm>
#include <cstddef>

namespace dynrt {

/// A frame's tile passes: each 16x16 tile of the image (or of the trace's tile share), once
/// per sample pass (TraceSettings::sampling.spp), counts as done once its camera rays, shadow
/// rays and shading are. Reflections and refractions are traced after the tiles as one stage
/// of their own (ARCHITECTURE.md), so a frame with them stays at 100% while they run. With
/// adaptive anti-aliasing (PixelSampling::adaptive_contrast) the first pass's tiles are the
/// total until the pixels to refine are known; then their samples' tiles are added to it.
struct RenderProgress {
    /// A trace is running (false before the first and between frames; the counts are then
    /// the last frame's).
    bool tracing = false;
    std::size_t tiles_done = 0;
    std::size_t tiles_total = 0;

    /// tiles_done / tiles_total in [0, 1]; 0 before anything was traced.
    double fraction() const {
        return tiles_total == 0 ? 0.0 : std::min(1.0, double(tiles_done) / double(tiles_total));
    }
};

}  // namespace dynrt
