#pragma once
// dynrt's own tracer behind the trace seam (trace_backend.h): the 16x16 packet tracer
// (dynrt/packet/two_level_packet.h) and the single-ray tracer (dynrt/bvh/two_level_bvh.h) over
// a SceneAccel's two-level tree. Both give the same hits bit for bit, so which one traces a
// batch changes only the time; that choice is made here and nowhere else (as_packet).

#include "dynrt/engine/renderer.h"
#include "dynrt/engine/trace_backend.h"
#include "update/scene_accel.h"

namespace dynrt::detail {

class CpuTracer final : public TraceBackend {
public:
    /// Traces through `accel`'s trees as they are at each call, with `options`' tracer, packet
    /// settings and secondary.min_packet_rays; borrows `accel`.
    CpuTracer(const SceneAccel& accel, const TraceSettings& options)
        : accel_(accel), single_rays_(options.tracer == Tracer::single), packet_(options.packet),
          min_scattered_(options.secondary.min_packet_rays) {}

    int closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                TraceWork* work) const override;
    packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence,
                              TraceWork* work) const override;

    /// The one rule for packet versus single rays: whether `count` rays of `coherence` are
    /// traced as one packet. Never under Tracer::single. A tile's rays: more than
    /// kFewTileRays, since a packet's traversal costs mostly per node, not per ray (a
    /// handful of a tile's pixels, re-traced by reuse or adaptive sampling, cost less one by
    /// one). Scattered rays: at least SecondaryRays::min_packet_rays of them, and for closest
    /// hits those of one direction octant (a planar mirror's or a glass pane's stay as
    /// coherent as camera rays; what a curved surface scatters does not).
    bool as_packet(int count, RayCoherence coherence) const;

    static constexpr int kFewTileRays = 32;

private:
    const SceneAccel& accel_;
    bool single_rays_;
    packet::PacketConfig packet_;
    int min_scattered_;

    /// Closest hits of `lanes` of `rays`, resolved: packed into the first lanes of one packet,
    /// or one by one.
    void closest_group(const packet::RayPacket& rays, const packet::LaneMask& lanes, bool as_packet,
                       HitTarget hits, TraceWork* work) const;
};

}  // namespace dynrt::detail
