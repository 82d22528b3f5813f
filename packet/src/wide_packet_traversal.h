#pragma once
// Packet traversal of the wide tree (wide_packet_traversal.cpp), called by the packet tracer's
// entry points when the TriangleBvh carries one.

#include "packet_work.h"

#include "dynrt/bvh/wide_bvh.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"

#include <span>

namespace dynrt::packet::detail {

/// Closest hits of the prepared packet `w` (made from `packet`) through `wide`, left in w's
/// tfar, hit_u, hit_v and hit_prim.
template <int W>
void wide_closest(const bvh::WideBvh& wide, const RayPacket& packet, Work& w,
                  const PacketConfig& config, PacketStats* stats);

/// Any hits of the prepared packet `w`: the occluded lanes are set in `occluded` (cleared by
/// the caller), each with its blocking primitive in w.hit_prim where known; `first` is tested
/// before the traversal (OccluderSearch::test_first).
template <int W>
void wide_any(const bvh::WideBvh& wide, const RayPacket& packet, Work& w,
              const PacketConfig& config, PacketStats* stats, LaneMask& occluded,
              std::span<const PrimTriangle> first = {});

}  // namespace dynrt::packet::detail
