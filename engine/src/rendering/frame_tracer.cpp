#include "frame_tracer.h"

#include "dynrt/engine/stopwatch.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "rendering/adaptive_tile.h"
#include "rendering/stage_work.h"
#include "rendering/tile_pass.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace dynrt {

namespace {

using detail::StageWork;

/// The adaptive path (RenderOptions::adaptive_tolerance > 0): each tile sampled, traced,
/// shadowed and shaded by trace_tile_adaptive in one task.
void trace_adaptive(const detail::AdaptiveFrame& frame, const packet::Tiling& tiling,
                    detail::FrameProgress* progress, RenderedFrame& out) {
    tbb::combinable<StageWork> work;
    const Stopwatch clock;
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        detail::trace_tile_adaptive(frame, i, tiling.tile(i), out, work.local());
        if (progress != nullptr) progress->tile_done();
    });
    const double wall_ms = clock.elapsed_ms();
    const StageWork sum = work.combine([](StageWork a, const StageWork& b) { return a += b; });
    detail::report_stages(sum, wall_ms, out.stats);
    out.stats.interpolated_pixels = sum.interpolated;
    if (frame.pass.count) sum.trace.report(out.stats);
}

}  // namespace

FrameSecondary::FrameSecondary(const TraceInputs& in, const TraceSettings& options,
                               const detail::TileShading& shading, TraceScratch& scratch,
                               const detail::SamplePass& sample) {
    if (!detail::any_secondary(in.scene_materials, options.secondary)) return;
    const detail::SecondaryTracing tracing{in.accel, in.tracer, options.secondary, options.count_packet_work};
    frame_.emplace(detail::SecondaryFrame{tracing, in.lights, shading, in.scene_materials,
                                          in.object_material, options.secondary_log, sample});
    stage_.emplace(*frame_, scratch.secondary);
}

void size_image(const TraceSettings& options, RenderedFrame& out) {
    const std::size_t pixels = std::size_t(options.width) * std::size_t(options.height);
    out.width = options.width;
    out.height = options.height;
    out.color.resize(pixels);
    const std::size_t hit_pixels = options.hit_buffers ? pixels : 0;
    out.depth.resize(hit_pixels);
    out.object.resize(hit_pixels);
    out.prim.resize(hit_pixels);
    out.normal.resize(hit_pixels);
}

void size_frame(const TraceSettings& options, TraceScratch& scratch, RenderedFrame& out) {
    size_image(options, out);
    scratch.hits.resize(std::size_t(options.width) * std::size_t(options.height));
}

detail::TileShading frame_shading(const TraceInputs& in, const TraceSettings& options,
                                  TraceScratch& scratch) {
    scratch.shading_lights.clear();
    for (const PointLight& light : in.lights) {
        scratch.shading_lights.push_back(detail::shading_light(light));
    }
    // Shadow rays pass through transmissive objects (tile_tracing.h, through_glass), a term of
    // Whitted's model: with secondary rays off (max_depth 0) every surface blocks light.
    scratch.glass.clear();
    const bool any_glass = std::any_of(in.scene_materials.begin(), in.scene_materials.end(),
                                       [](const Material& m) { return m.transmittance != glm::vec3(0.0f); });
    if (any_glass && options.secondary.max_depth > 0) {
        for (const std::int32_t m : in.object_material) {
            scratch.glass.push_back(std::size_t(m) < in.scene_materials.size()
                                        ? in.scene_materials[std::size_t(m)].transmittance
                                        : glm::vec3(0.0f));
        }
    }
    detail::TileShading shading{in.materials, scratch.shading_lights, options.ambient,
                                options.background, options.packet.lanes, in.textures};
    shading.glass = scratch.glass;
    shading.environment = options.environment.get();
    return shading;
}

void trace_frame(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                 TraceScratch& scratch, RenderedFrame& out, const detail::SamplePass& sample) {
    const int width = options.width, height = options.height;
    // The image's camera: a pass over a list of samples has a frame of its own shape.
    const packet::PinholeRays rays(camera, sample.samples ? sample.image_width : width,
                                   sample.samples ? sample.image_height : height);
    // The tiles this trace renders: every one, or a process's share of them.
    const packet::Tiling tiling(width, height, options.tiles);
    TraceStats& stats = out.stats;  // the trace stage fills its part only
    stats.secondary_ms = 0.0;
    stats.reflection_rays = stats.refraction_rays = 0;
    stats.reflection_mrays_per_s = stats.refraction_mrays_per_s = stats.secondary_shadow_mrays_per_s = 0.0;
    stats.secondary_shadow_rays = stats.secondary_packet_rays = stats.secondary_single_rays = 0;
    stats.secondary_rays_per_depth.clear();
    stats.secondary_packet_rays_per_depth.clear();
    stats.secondary_mrays_per_s_per_depth.clear();
    const detail::TileShading shading = frame_shading(in, options, scratch);
    size_frame(options, scratch, out);
    const bool count = options.count_packet_work;

    if (options.adaptive_tolerance > 0.0f) {
        // Counted per tile here, whether it was interpolated or traced.
        TraceInputs uncounted = in;
        uncounted.progress = nullptr;
        const detail::TilePass pass{uncounted, rays, shading, nullptr, scratch.hits, width, count, sample};
        trace_adaptive(detail::AdaptiveFrame{pass, options.adaptive_tolerance}, tiling, in.progress, out);
        return;
    }

    FrameSecondary secondary(in, options, shading, scratch, sample);
    const detail::TilePass pass{in, rays, shading, secondary.stage(), scratch.hits, width, count, sample};
    tbb::combinable<StageWork> work;
    const Stopwatch clock;
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        const packet::Tile tile = tiling.tile(i);
        if (sample.pixels != nullptr) {
            detail::SomePixels some{pass, *sample.pixels, tile};
            detail::trace_tile(pass, i, tile, some, work.local(), out);
        } else {
            detail::EveryRay every{pass};
            detail::trace_tile(pass, i, tile, every, work.local(), out);
        }
    });
    const StageWork sum = work.combine([](StageWork a, const StageWork& b) { return a += b; });
    detail::report_stages(sum, clock.elapsed_ms(), stats);
    if (secondary.stage()) secondary.stage()->trace(out, stats);
    if (count) sum.trace.report(stats);
}

}  // namespace dynrt
