#pragma once
// Tracing some lanes of a tile's packet with either tracer, for the paths that re-trace part of
// a frame (exact_reuse.h, approximate_reuse.h): the packet tracer traces the chosen lanes as
// one packet, the single-ray tracer one by one; both give the same hits bit for bit.

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/two_level_packet.h"
#include "update/scene_accel.h"

#include <vector>

namespace dynrt::detail {

/// The counters of a trace that counts its work (TraceSettings::count_packet_work), or none.
struct LaneWork {
    packet::PacketStats* packet = nullptr;
    bvh::TraversalStats* single = nullptr;
};

/// Closest hits of `rays`' lanes in `lanes` (pixels of `tile`), resolved to object and
/// triangle, into hits[y * width + x]; other pixels' hits are left alone. `rays.active` is
/// restored.
inline void trace_primary_lanes(const SceneAccel& scene, const TraceSettings& options,
                                const packet::Tile& tile, int width, packet::RayPacket& rays,
                                const packet::LaneMask& lanes, std::vector<bvh::InstanceHit>& hits,
                                LaneWork work) {
    const bvh::TwoLevelBvh& accel = scene.top_level();
    const packet::LaneMask active = rays.active;
    rays.active = lanes;
    packet::InstanceHits packet_hits;
    if (options.tracer == Tracer::packet) {
        packet::intersect_closest(accel, rays, packet_hits, options.packet, work.packet);
    }
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        if (!lanes.test(lane)) continue;
        const packet::LanePixel px = packet::tile_pixel(tile, lane);
        bvh::InstanceHit& hit = hits[std::size_t(px.y) * width + px.x];
        if (options.tracer == Tracer::packet) {
            hit = packet_hits.hit(lane);
        } else {
            const bvh::Ray ray = rays.ray(lane);
            hit = work.single ? bvh::intersect_closest(accel, ray, *work.single)
                              : bvh::intersect_closest(accel, ray);
        }
        scene.resolve(hit);
    }
    rays.active = active;
}

/// Which of `shadow`'s lanes in `lanes` are occluded; `shadow.active` becomes `lanes`.
inline packet::LaneMask trace_shadow_lanes(const SceneAccel& scene, const TraceSettings& options,
                                           packet::RayPacket& shadow, const packet::LaneMask& lanes,
                                           LaneWork work) {
    const bvh::TwoLevelBvh& accel = scene.top_level();
    packet::LaneMask occluded;
    shadow.active = lanes;
    if (options.tracer == Tracer::packet) {
        packet::intersect_any(accel, shadow, occluded, options.packet, work.packet);
        return occluded;
    }
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        if (!lanes.test(lane)) continue;
        const bvh::Ray ray = shadow.ray(lane);
        const bool blocked = work.single ? bvh::intersect_any(accel, ray, *work.single)
                                         : bvh::intersect_any(accel, ray);
        if (blocked) occluded.set(lane);
    }
    return occluded;
}

}  // namespace dynrt::detail
