#pragma once
// dynrt's own tracer behind the trace seam (trace_backend.h): the 16x16 packet tracer
// (dynrt/packet/two_level_packet.h) and the single-ray tracer (dynrt/bvh/two_level_bvh.h) over
// a SceneAccel's two-level tree. Both give the same hits bit for bit, so which one traces a
// batch changes only the time; that choice is made here and nowhere else (as_packet).

#include "dynrt/engine/renderer.h"
#include "dynrt/engine/trace_backend.h"
#include "rendering/occluder_cache.h"
#include "update/scene_accel.h"

#include <memory>

namespace dynrt::detail {

class CpuTracer final : public TraceBackend {
public:
    /// Traces through `accel`'s trees as they are at each call, with `options`' tracer, packet
    /// settings and secondary.min_packet_rays; borrows `accel`.
    CpuTracer(const SceneAccel& accel, const TraceSettings& options)
        : accel_(accel), single_rays_(options.tracer == Tracer::single), packet_(options.packet),
          min_scattered_(options.secondary.min_packet_rays),
          cache_(options.occluder_cache && !single_rays_ ? std::make_unique<OccluderCache>() : nullptr) {}

    int closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                TraceWork* work) const override;
    packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence,
                              TraceWork* work) const override;

    /// occluded(), also saying how many of the rays were traced as packets (the library API
    /// reports it).
    packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence, TraceWork* work,
                              int& packet_rays) const;

    /// The one rule for packet versus single rays: whether the rays of `group` (lanes of
    /// `rays`, of `coherence`) are traced as one packet. Never under Tracer::single.
    ///   tile       more than kFewTileRays, since a packet's traversal costs mostly per node,
    ///              not per ray (a handful of a tile's pixels, re-traced by reuse or adaptive
    ///              sampling, cost less one by one);
    ///   scattered  at least SecondaryRays::min_packet_rays of them, and for closest hits those
    ///              of one direction octant (a planar mirror's or a glass pane's stay as
    ///              coherent as camera rays; what a curved surface scatters does not);
    ///   unknown    at least kPacketRaysMin of one octant, every direction within
    ///              kCoherentCosine of the group's middle ray's (a caller's rays may be in any
    ///              order; packets pay while their rays visit mostly the same nodes).
    bool as_packet(const packet::RayPacket& rays, const packet::LaneMask& group, RayCoherence coherence) const;

    /// Whether rays of unknown coherence are all one group that as_packet sends as a packet
    /// (one octant, within the cone): the common case of a caller's batch in a coherent order,
    /// recognised in one pass before any split.
    bool one_coherent_group(const packet::RayPacket& rays) const;

    static constexpr int kFewTileRays = 32;
    /// About 25 degrees, and 16 rays: measured on the library API's queries (benchmarks/bm_api.cpp).
    static constexpr float kCoherentCosine = 0.9f;
    static constexpr int kPacketRaysMin = 16;

    /// Shadow rays traced in packets with the occluder cache, and those its triangles answered
    /// (0 and 0 without it).
    std::size_t cached_shadow_rays() const { return cache_ ? cache_->traced() : 0; }
    std::size_t cache_answered_shadow_rays() const { return cache_ ? cache_->answered() : 0; }

private:
    const SceneAccel& accel_;
    bool single_rays_;
    packet::PacketConfig packet_;
    int min_scattered_;
    /// TraceSettings::occluder_cache: for packets whose rays leave one point (a light).
    std::unique_ptr<OccluderCache> cache_;

    /// The one place a batch is cut into the groups traced together, each as one packet or
    /// ray by ray (as_packet): calls trace(group, as_packet, traced_in_place) per group and
    /// returns how many rays went as packets. Closest hits of scattered rays are split by
    /// direction octant; their shadow rays, sorted toward one light, are not.
    template <class TraceGroup>
    int for_each_group(const packet::RayPacket& rays, RayCoherence coherence, bool closest_hits,
                       TraceGroup&& trace) const;
    /// Whether a packet of `lanes` of `rays` is traced in their own lanes rather than packed
    /// into the first ones: a tile's rays (the packet's beam spans the tile), and a caller's
    /// batch when the group is all of it. Lane by lane the hits are the same either way
    /// (packet_traversal.h); packing drops the empty chunks of a sparse group.
    static bool in_place(const packet::RayPacket& rays, const packet::LaneMask& lanes, RayCoherence coherence);
    /// Closest hits of `lanes` of `rays`, resolved: as one packet (in place, or packed into
    /// the first lanes of one), or one by one.
    void closest_group(const packet::RayPacket& rays, const packet::LaneMask& lanes, bool as_packet,
                       bool traced_in_place, HitTarget hits, TraceWork* work) const;
    /// Which of `lanes` of `rays` are blocked, traced as closest_group traces them.
    packet::LaneMask occluded_group(const packet::RayPacket& rays, const packet::LaneMask& lanes,
                                    bool as_packet, bool traced_in_place, TraceWork* work) const;
    /// Which active lanes of `rays` are blocked, as one packet: through the occluder cache when
    /// the rays all leave one point.
    packet::LaneMask occluded_packet(const packet::RayPacket& rays, TraceWork* work) const;
};

}  // namespace dynrt::detail
