#pragma once
// The counters behind RenderProgress (dynrt/engine/render_progress.h): written by the trace's
// tile tasks, read by any thread.

#include "dynrt/engine/render_progress.h"

#include <atomic>
#include <cstddef>

namespace dynrt::detail {

class FrameProgress {
public:
    /// A trace of `tiles_total` tile passes begins.
    void start(std::size_t tiles_total) {
        done_.store(0, std::memory_order_relaxed);
        total_.store(tiles_total, std::memory_order_relaxed);
        tracing_.store(true, std::memory_order_release);
    }
    /// A pass whose tiles were not known at start() (adaptive anti-aliasing's refinement).
    void add_tiles(std::size_t tiles) { total_.fetch_add(tiles, std::memory_order_relaxed); }
    /// One tile pass finished (called concurrently by the tile tasks).
    void tile_done() { done_.fetch_add(1, std::memory_order_relaxed); }
    /// The trace ended (whole, or stopped part way).
    void finish() { tracing_.store(false, std::memory_order_release); }
    RenderProgress now() const {
        RenderProgress p;
        p.tracing = tracing_.load(std::memory_order_acquire);
        p.tiles_total = total_.load(std::memory_order_relaxed);
        p.tiles_done = std::min(done_.load(std::memory_order_relaxed), p.tiles_total);
        return p;
    }

private:
    std::atomic<std::size_t> done_{0}, total_{0};
    std::atomic<bool> tracing_{false};
};

}  // namespace dynrt::detail
