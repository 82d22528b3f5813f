#pragma once
// What a frame's tile loop did, per thread, and how it becomes the report's stage times: the
// stages of a tile (camera rays, shadow rays, shading, secondary rays) run one after another in
// one task, so each task times its stages on its own thread, and the loop's wall time is split
// between the stages in proportion to the workers' summed time in each.

#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/trace_backend.h"

#include <algorithm>
#include <cstddef>

namespace dynrt::detail {

/// One thread's time and rays per stage over the tiles it ran.
struct StageWork {
    double primary_ms = 0.0, shadow_ms = 0.0, shade_ms = 0.0;
    std::size_t primary_rays = 0, shadow_rays = 0;
    /// Shadow rays not cast (tile_shading.h's ShadowCounts).
    std::size_t shadow_back_side = 0, shadow_shading_side = 0, shadow_dark_light = 0;
    /// Pixels interpolated rather than traced (adaptive sampling).
    std::size_t interpolated = 0;
    /// Pixels whose shadow rays or secondary rays alone were traced again (exact reuse).
    std::size_t shadows_only = 0;
    /// Traversal counters, when the trace counts them.
    TraceWork trace;

    /// Adds a batch's shadow rays, cast and not.
    template <class Counts>
    void add_shadows(const Counts& c) {
        shadow_rays += c.cast;
        add_skipped_shadows(c);
    }
    /// Adds a batch's shadow rays not cast.
    template <class Counts>
    void add_skipped_shadows(const Counts& c) {
        shadow_back_side += c.back_side;
        shadow_shading_side += c.shading_side;
        shadow_dark_light += c.dark_light;
    }

    StageWork& operator+=(const StageWork& o) {
        primary_ms += o.primary_ms;
        shadow_ms += o.shadow_ms;
        shade_ms += o.shade_ms;
        primary_rays += o.primary_rays;
        shadow_rays += o.shadow_rays;
        shadow_back_side += o.shadow_back_side;
        shadow_shading_side += o.shadow_shading_side;
        shadow_dark_light += o.shadow_dark_light;
        interpolated += o.interpolated;
        shadows_only += o.shadows_only;
        trace += o.trace;
        return *this;
    }
};

inline double mrays_per_s(std::size_t rays, double ms) { return ms > 0.0 ? double(rays) / (ms * 1e3) : 0.0; }

/// Sets stats' primary, shadow and shade times, rays and rates from the threads' summed work
/// `sum` over a tile loop that took `wall_ms`: each stage gets the share of `wall_ms` its
/// thread time is of the total, and shade_ms what the others leave.
inline void report_stages(const StageWork& sum, double wall_ms, TraceStats& stats) {
    const double thread_total = sum.primary_ms + sum.shadow_ms + sum.shade_ms;
    const double scale = thread_total > 0.0 ? wall_ms / thread_total : 0.0;
    stats.primary_ms = sum.primary_ms * scale;
    stats.shadow_ms = sum.shadow_ms * scale;
    stats.shade_ms = std::max(0.0, wall_ms - stats.primary_ms - stats.shadow_ms);
    stats.primary_rays = sum.primary_rays;
    stats.shadow_rays = sum.shadow_rays;
    stats.shadow_rays_back_side = sum.shadow_back_side;
    stats.shadow_rays_shading_side = sum.shadow_shading_side;
    stats.shadow_rays_dark_light = sum.shadow_dark_light;
    stats.primary_mrays_per_s = mrays_per_s(stats.primary_rays, stats.primary_ms);
    stats.shadow_mrays_per_s = mrays_per_s(stats.shadow_rays, stats.shadow_ms);
}

}  // namespace dynrt::detail
