#pragma once
// Packet traversal of a two-level BVH (dynrt/bvh/two_level_bvh.h): the small top level is
// traversed once per packet with per-lane conservative box tests, and each instance reached is
// traced with the packet tracer (packet_traversal.h) on a packet of the lanes that reach it,
// in the instance's object space. Results are exactly those of bvh::intersect_closest /
// bvh::intersect_any on the TwoLevelBvh, lane by lane and bit for bit.

#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"

#include <cstdint>
#include <span>

namespace dynrt::packet {

/// Closest hits of a packet across instances, one lane per ray.
struct alignas(64) InstanceHits {
    /// Per lane, as bvh::InstanceHit::hit: a default bvh::Hit on a miss or an inactive lane.
    PacketHits hits;
    /// Per lane, bvh::Instance::object of the hit; bvh::kInvalidId on a miss or inactive lane.
    alignas(64) std::uint32_t object[kPacketRays];

    bvh::InstanceHit hit(int lane) const { return bvh::InstanceHit{hits.hit(lane), object[lane]}; }
};

/// Closest hit of every active lane of `packet` within [tmin, tmax] across the instances of
/// `tlas`, written to `hits`; lane by lane identical to bvh::intersect_closest(tlas, ray) (t, u,
/// v, prim and object bit for bit, ties included). `config` applies to the instances' packet
/// traces, and `stats`, if not null, receives their counters (one packet per instance reached:
/// `packets` counts bottom-level traces). Thread-safe on a shared `tlas`; `stats` must not be
/// shared between threads. Uses about 24 KiB of stack (a bottom-level packet and its hits).
void intersect_closest(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, InstanceHits& hits,
                       const PacketConfig& config = {}, PacketStats* stats = nullptr);

/// A triangle of instance `instance` (index into tlas.instances), as its tree stores it.
struct InstanceTriangle {
    std::uint32_t instance;
    PrimTriangle tri;
};

/// OccluderSearch across instances.
struct InstanceOccluderSearch {
    /// Triangles to test every ray against first, each in its instance's object space with
    /// the ray carried there as the traversal carries it; exactly triangles of the instances'
    /// trees (OccluderSearch::test_first), so the answer is the same, only sooner.
    std::span<const InstanceTriangle> test_first;
    /// If not null, kPacketRays entries each: per occluded lane, the instance and primitive
    /// found blocking it, or kInvalidId in both where the trace does not say.
    std::uint32_t* occluder_instance = nullptr;
    std::uint32_t* occluder_prim = nullptr;
    /// Set to the lanes that test_first's triangles blocked.
    LaneMask blocked_first;
};

/// For every active lane of `packet`, whether any instance is hit within [tmin, tmax] (shadow
/// rays): `occluded` gets exactly the active lanes for which bvh::intersect_any(tlas, ray) is
/// true. Thread-safety, `config` and `stats` as above. With `search`, the instances of its
/// triangles are traced first, each testing its triangles before its tree, and the occluders
/// found are reported.
void intersect_any(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, LaneMask& occluded,
                   const PacketConfig& config = {}, PacketStats* stats = nullptr,
                   InstanceOccluderSearch* search = nullptr);

}  // namespace dynrt::packet
