#include "frame_tracer.h"

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/packet/two_level_packet.h"
#include "adaptive_tile.h"
#include "dynrt/engine/shadow_ray_offset.h"
#include "dynrt/engine/stopwatch.h"
#include "tile_shading.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <algorithm>
#include <functional>
#include <optional>
#include <vector>

namespace dynrt {

namespace {

using detail::ShadowOrigin;
using detail::shade_lanes;
using detail::TileShading;
using detail::TileShadowOrigins;

template <typename PerPixel>
void for_each_pixel_in_tiles(const packet::Tiling& tiling, int width, PerPixel&& per_pixel) {
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        const packet::Tile tile = tiling.tile(i);
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) per_pixel(x, y, std::size_t(y) * width + x);
        }
    });
}


template <typename PerTile>
void for_each_tile(const packet::Tiling& tiling, PerTile&& per_tile) {
    tbb::parallel_for(0, tiling.count(), [&](int i) { per_tile(tiling.tile(i)); });
}



/// The adaptive path (RenderOptions::adaptive_tolerance > 0): each tile traced, shadowed and
/// shaded by trace_tile_adaptive in one task; the stage times split the loop's wall time in
/// proportion to the workers' time in each stage, as the exact packet path does for its
/// shadow and shading stages.
void trace_adaptive(const detail::AdaptiveFrame& frame, const packet::Tiling& tiling,
                    std::vector<bvh::InstanceHit>& hits, bool count, RenderedFrame& out) {
    TraceStats& stats = out.stats;  // the trace stage fills its part only
    tbb::combinable<detail::AdaptiveTileWork> work;
    tbb::combinable<packet::PacketStats> packet_work;
    const Stopwatch clock;
    for_each_tile(tiling, [&](const packet::Tile& tile) {
        detail::trace_tile_adaptive(frame, tile, hits, out, work.local(),
                                    count ? &packet_work.local() : nullptr);
    });
    const double wall_ms = clock.elapsed_ms();
    const detail::AdaptiveTileWork sum = work.combine([](detail::AdaptiveTileWork a,
                                                         const detail::AdaptiveTileWork& b) {
        a.primary_ms += b.primary_ms;
        a.shadow_ms += b.shadow_ms;
        a.shade_ms += b.shade_ms;
        a.primary_rays += b.primary_rays;
        a.shadow_rays += b.shadow_rays;
        a.interpolated += b.interpolated;
        return a;
    });
    const double thread_total = sum.primary_ms + sum.shadow_ms + sum.shade_ms;
    const double scale = thread_total > 0.0 ? wall_ms / thread_total : 0.0;
    stats.primary_ms = sum.primary_ms * scale;
    stats.shadow_ms = sum.shadow_ms * scale;
    stats.shade_ms = wall_ms - stats.primary_ms - stats.shadow_ms;
    stats.primary_rays = sum.primary_rays;
    stats.shadow_rays = sum.shadow_rays;
    stats.interpolated_pixels = sum.interpolated;
    if (count) {
        const packet::PacketStats total = packet_work.combine(
            [](packet::PacketStats a, const packet::PacketStats& b) { return a += b; });
        stats.ray_triangle_tests = total.ray_triangle_tests;
        stats.ray_triangle_culled = total.culled_active_bounds + total.culled_beam_planes +
                                    total.culled_triangle_edges + total.culled_near_far;
    }
}


}  // namespace

void trace_frame(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                 TraceScratch& scratch, RenderedFrame& out) {
    const std::span<const PointLight> lights = in.lights;
    const int width = options.width, height = options.height;
    const packet::PinholeRays rays(camera, width, height);
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    // The tiles this trace renders: every one, or a process's share of them.
    const packet::Tiling tiling(width, height, options.tiles);
    TraceStats& stats = out.stats;  // the trace stage fills its part only
    const bvh::TwoLevelBvh& accel = in.accel.top_level();
    // The shading kernel's view of the lights (bookkeeping, outside the stage clocks).
    scratch.shading_lights.clear();
    for (const PointLight& light : lights) {
        scratch.shading_lights.push_back(packet::ShadingLight{light.position, light.intensity});
    }
    Stopwatch clock;
    const auto finish = [&] {
        const auto mrays_per_s = [](std::size_t rays_traced, double ms) {
            return ms > 0.0 ? double(rays_traced) / (ms * 1e3) : 0.0;
        };
        stats.primary_mrays_per_s = mrays_per_s(stats.primary_rays, stats.primary_ms);
        stats.shadow_mrays_per_s = mrays_per_s(stats.shadow_rays, stats.shadow_ms);
    };
    stats.secondary_ms = 0.0;
    stats.reflection_rays = stats.refraction_rays = 0;
    stats.reflection_mrays_per_s = stats.refraction_mrays_per_s = 0.0;
    stats.secondary_shadow_rays = stats.secondary_packet_rays = stats.secondary_single_rays = 0;
    stats.secondary_rays_per_depth.clear();
    stats.secondary_packet_rays_per_depth.clear();
    const TileShading shading{in.materials, scratch.shading_lights, options.ambient,
                              options.background, options.packet.lanes, in.textures};
    out.width = width;
    out.height = height;
    out.color.resize(pixels);
    const std::size_t hit_pixels = options.hit_buffers ? pixels : 0;
    out.depth.resize(hit_pixels);
    out.object.resize(hit_pixels);
    out.prim.resize(hit_pixels);
    out.normal.resize(hit_pixels);

    if (options.adaptive_tolerance > 0.0f) {
        scratch.hits.resize(pixels);
        const detail::AdaptiveFrame frame{in.accel, rays, lights, shading,
                                          in.object_material, options.packet,
                                          options.adaptive_tolerance, width};
        trace_adaptive(frame, tiling, scratch.hits, options.count_packet_work, out);
        finish();
        return;
    }

    // ---- Primary rays, one 16x16 tile per task ----
    scratch.hits.resize(pixels);
    const bool count = options.count_packet_work;
    tbb::combinable<packet::PacketStats> work;
    tbb::combinable<bvh::TraversalStats> single_work;
    if (options.tracer == Tracer::packet) {
        const packet::PinholeRays& pinhole = rays;
        for_each_tile(tiling, [&](const packet::Tile& tile) {
            packet::RayPacket packet_rays;
            packet::InstanceHits packet_hits;
            pinhole.fill_tile(tile, packet_rays);
            packet::intersect_closest(accel, packet_rays, packet_hits, options.packet,
                                      count ? &work.local() : nullptr);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    bvh::InstanceHit& hit = scratch.hits[std::size_t(y) * width + x];
                    hit = packet_hits.hit(packet::tile_lane(tile, x, y));
                    in.accel.resolve(hit);
                }
            }
        });
    } else {
        // The camera rays of a tile are made in SIMD, as for packets (the very same rays as
        // rays.ray(x, y), bit for bit), then traced one by one: making each ray on its own (a
        // normalisation per pixel) cost a third as much as tracing it on sphere:1000000.
        const packet::PinholeRays& pinhole = rays;
        for_each_tile(tiling, [&](const packet::Tile& tile) {
            packet::RayPacket camera_rays;
            pinhole.fill_tile(tile, camera_rays);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const bvh::Ray ray = camera_rays.ray(packet::tile_lane(tile, x, y));
                    bvh::InstanceHit& hit = scratch.hits[std::size_t(y) * width + x];
                    hit = count ? bvh::intersect_closest(accel, ray, single_work.local())
                                : bvh::intersect_closest(accel, ray);
                    in.accel.resolve(hit);
                }
            }
        });
    }
    stats.primary_ms = clock.lap_ms();
    stats.primary_rays = options.tiles.whole() ? pixels : tiling.pixel_count();

    // ---- Shadow rays (one per hit and light on the lit side), then shading ----
    const packet::PinholeRays& pinhole = rays;
    // ---- ... and the reflection and refraction rays of each tile after its shading ----
    const bool secondary = detail::any_secondary(in.scene_materials, options.secondary);
    std::optional<detail::SecondaryFrame> secondary_frame;
    if (secondary) {
        const detail::SecondaryTracing tracing{in.accel, options.secondary, options.packet,
                                               options.tracer == Tracer::single, count};
        secondary_frame.emplace(detail::SecondaryFrame{tracing, lights, shading,
                                                       in.scene_materials, in.object_material,
                                                       options.secondary_log});
    }
    tbb::combinable<detail::SecondaryWork> secondary_work;
    tbb::combinable<double> single_shade_ms([] { return 0.0; });
    double single_shadow_ms = 0.0;
    // The shadow and shading loop's wall time is split between shadow_ms, shade_ms and
    // secondary_ms in proportion to the workers' time in each (secondary work times itself).
    double secondary_scale = 0.0;
    const auto split_stages = [&](double wall_ms, double shadow_thread_ms, double shade_thread_ms) {
        double secondary_thread_ms = 0.0;
        if (secondary) {
            secondary_work.combine_each([&](const detail::SecondaryWork& w) {
                secondary_thread_ms += w.thread_ms();
            });
        }
        const double thread_total = shadow_thread_ms + shade_thread_ms + secondary_thread_ms;
        const double scale = thread_total > 0.0 ? wall_ms / thread_total : 0.0;
        stats.shadow_ms = thread_total > 0.0 ? shadow_thread_ms * scale : wall_ms;
        stats.shade_ms = wall_ms - stats.shadow_ms;  // secondary_ms is taken out of it below
        secondary_scale = scale;
    };
    tbb::combinable<std::size_t> shadow_rays([] { return std::size_t(0); });
    if (options.tracer == Tracer::packet) {
        // One shadow packet per tile and light (the tile's hit points toward the light), then
        // the tile is shaded in the same task, on the normals and hit points the shadow rays
        // were made from while they are still in cache. Both stages thus share one parallel
        // loop and one wall-clock interval: each task times its shadow part (origins and
        // shadow packets) and its shading part (kernel and output writes) on its own thread,
        // and the interval is split between shadow_ms and shade_ms in proportion to the two
        // summed thread times, i.e. by the share of the workers' time each stage took.
        struct StageThreadMs {
            double shadow = 0.0, shade = 0.0;
        };
        // Reflection and refraction rays, traced in the same task after the tile's shading
        // (secondary_rays.h): their thread time is split out of the stage's wall time by the
        // same proportion.
        tbb::combinable<StageThreadMs> thread_ms;
        tbb::combinable<std::vector<packet::LaneMask>> visible_buffers;
        tbb::parallel_for(0, tiling.count(), [&](int i) {
            Stopwatch task_clock;
            const packet::Tile tile = tiling.tile(i);
            packet::RayPacket packet_rays;
            pinhole.fill_tile(tile, packet_rays);  // the camera rays, for the facing normals
            TileShadowOrigins origins;
            origins.compute(in.accel, scratch.hits, width, tile, packet_rays, in.object_material);
            std::vector<packet::LaneMask>& visible = visible_buffers.local();
            visible.assign(lights.size(), packet::LaneMask{});
            std::size_t traced = 0;
            for (std::size_t l = 0; l < lights.size() && origins.surface.hit.any(); ++l) {
                origins.rays_to(lights[l], packet_rays);
                if (!packet_rays.active.any()) continue;
                traced += std::size_t(packet_rays.active.count());
                packet::LaneMask occluded;
                packet::intersect_any(accel, packet_rays, occluded, options.packet,
                                      count ? &work.local() : nullptr);
                visible[l] = packet_rays.active & ~occluded;
            }
            shadow_rays.local() += traced;
            StageThreadMs& ms = thread_ms.local();
            ms.shadow += task_clock.lap_ms();
            packet::ShadedColors colors;
            shade_lanes(shading, origins, visible, colors);
            if (secondary) {
                ms.shade += task_clock.lap_ms();
                detail::add_secondary(*secondary_frame, origins, colors, secondary_work.local());
                task_clock.lap_ms();  // the secondary work times itself
            }
            detail::write_tile(shading, tile, origins, scratch.hits, colors, out);
            ms.shade += task_clock.lap_ms();
        });
        const double wall_ms = clock.lap_ms();
        const StageThreadMs sum = thread_ms.combine([](StageThreadMs a, const StageThreadMs& b) {
            return StageThreadMs{a.shadow + b.shadow, a.shade + b.shade};
        });
        split_stages(wall_ms, sum.shadow, sum.shade);
    } else {
        scratch.visible.assign(pixels * lights.size(), 0);
        for_each_pixel_in_tiles(tiling, width, [&](int x, int y, std::size_t p) {
            const bvh::InstanceHit& hit = scratch.hits[p];
            if (!hit.is_hit()) return;
            const ShadowOrigin origin(in.accel.world_triangle(hit.object, hit.hit.prim), hit.hit,
                                      rays.ray(x, y).dir);
            std::size_t traced = 0;
            for (std::size_t l = 0; l < lights.size(); ++l) {
                if (!origin.faces(lights[l])) continue;
                ++traced;
                const bvh::Ray shadow = origin.ray_to(lights[l]);
                scratch.visible[p * lights.size() + l] =
                    !(count ? bvh::intersect_any(accel, shadow, single_work.local())
                            : bvh::intersect_any(accel, shadow));
            }
            shadow_rays.local() += traced;
        });
        stats.shadow_ms = clock.lap_ms();
        single_shadow_ms = stats.shadow_ms;
        // The same shading kernel as the packet tracer, so both render the same bits; the
        // normals and hit points are recomputed per tile (as the shadow stage computed them).
        tbb::combinable<std::vector<packet::LaneMask>> visible_buffers;
        tbb::parallel_for(0, tiling.count(), [&](int i) {
            const packet::Tile tile = tiling.tile(i);
            packet::RayPacket camera_rays;
            pinhole.fill_tile(tile, camera_rays);
            TileShadowOrigins origins;
            origins.compute(in.accel, scratch.hits, width, tile, camera_rays, in.object_material);
            std::vector<packet::LaneMask>& visible = visible_buffers.local();
            visible.assign(lights.size(), packet::LaneMask{});
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const std::size_t p = std::size_t(y) * width + x;
                    const int lane = packet::tile_lane(tile, x, y);
                    for (std::size_t l = 0; l < lights.size(); ++l) {
                        if (scratch.visible[p * lights.size() + l]) visible[l].set(lane);
                    }
                }
            }
            packet::ShadedColors colors;
            Stopwatch task_clock;
            shade_lanes(shading, origins, visible, colors);
            if (secondary) {
                single_shade_ms.local() += task_clock.lap_ms();
                detail::add_secondary(*secondary_frame, origins, colors, secondary_work.local());
                task_clock.lap_ms();  // the secondary work times itself
            }
            detail::write_tile(shading, tile, origins, scratch.hits, colors, out);
            single_shade_ms.local() += task_clock.lap_ms();
        });
        const double wall_ms = clock.lap_ms();
        split_stages(wall_ms, 0.0, single_shade_ms.combine(std::plus<>()));
        stats.shadow_ms = single_shadow_ms;
    }
    if (secondary) {
        stats.secondary_rays_per_depth.clear();
    stats.secondary_packet_rays_per_depth.clear();
        detail::report_secondary(secondary_work.combine([](detail::SecondaryWork a,
                                                           const detail::SecondaryWork& b) {
                                     return a += b;
                                 }),
                                 secondary_scale, stats);
        stats.shade_ms = std::max(0.0, stats.shade_ms - stats.secondary_ms);
    }
    stats.shadow_rays = shadow_rays.combine(std::plus<>());
    if (count) {
        const packet::PacketStats total =
            work.combine([](packet::PacketStats a, const packet::PacketStats& b) { return a += b; });
        stats.ray_triangle_tests = total.ray_triangle_tests;
        stats.ray_triangle_culled = total.culled_active_bounds + total.culled_beam_planes +
                                    total.culled_triangle_edges + total.culled_near_far;
        stats.nodes_visited = total.nodes_visited;
        if (options.tracer == Tracer::single) {
            const bvh::TraversalStats single = single_work.combine(
                [](bvh::TraversalStats a, const bvh::TraversalStats& b) {
                    a.nodes_visited += b.nodes_visited;
                    a.triangles_tested += b.triangles_tested;
                    return a;
                });
            stats.ray_triangle_tests = single.triangles_tested;
            stats.nodes_visited = single.nodes_visited;
        }
    }
    finish();
}

}  // namespace dynrt
