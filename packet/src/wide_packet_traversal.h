#pragma once
// Packet traversal of the wide tree (wide_packet_traversal.cpp), called by the packet tracer's
// entry points when the TriangleBvh carries one.

#include "packet_work.h"

#include "dynrt/bvh/wide_bvh.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"

namespace dynrt::packet::detail {

/// Closest hits of the prepared packet `w` (made from `packet`) through `wide`, left in w's
/// tfar, hit_u, hit_v and hit_prim.
template <int W>
void wide_closest(const bvh::WideBvh& wide, const RayPacket& packet, Work& w,
                  const PacketConfig& config, PacketStats* stats);

/// Any hits of the prepared packet `w`: the occluded lanes are set in `occluded` (cleared by
/// the caller).
template <int W>
void wide_any(const bvh::WideBvh& wide, const RayPacket& packet, Work& w,
              const PacketConfig& config, PacketStats* stats, LaneMask& occluded);

}  // namespace dynrt::packet::detail
