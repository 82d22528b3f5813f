#pragma once
// Packet traversal of a triangle BVH: 256 rays share one stack and one sequence of traversal
// decisions (ranged traversal: Wald, Boulos and Shirley 2007, "Ray Tracing Deformable Scenes
// Using Dynamic Bounding Volume Hierarchies"; Overbeck, Ramamoorthi and Mark 2008, "Large Ray
// Packets for Real-Time Whitted Ray Tracing"), with the leaf-level vertex culling of Reshetov
// 2007, "Faster Ray Packets - Triangle Intersection through Vertex Culling". The packet
// traces the TriangleBvh's wide tree when it has one (all N children of a node decided in one
// SIMD pass by an early hit and an early miss; packet/src/wide_packet_traversal.cpp), else its
// binary tree (packet/src/packet_traversal.cpp).
//
// Results are exactly those of the single-ray tracer (bvh::intersect_closest and
// bvh::intersect_any), lane by lane and bit for bit: the per-lane box and triangle tests are the
// same arithmetic, and every packet-level shortcut is conservative with respect to that very
// arithmetic (see packet/src/packet_traversal.cpp for the arguments).

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/packet/packet_config.h"
#include "dynrt/packet/ray_packet.h"

#include <cstdint>
#include <span>

namespace dynrt::packet {

/// A triangle of a tree as the tree stores it, with its primitive index.
struct PrimTriangle {
    bvh::Triangle triangle;
    std::uint32_t prim;
};

/// What an any-hit trace may be told and may tell beyond its mask (an occluder cache's
/// questions: dynrt/engine's rendering/occluder_cache.h).
struct OccluderSearch {
    /// Triangles of the tree to test every ray against before traversing it, as a leaf of
    /// their own. They must be exactly triangles of the tree (the same coordinates and
    /// primitive index): a lane one of them blocks is then one the traversal would find
    /// occluded, so the answer is the same, only sooner.
    std::span<const PrimTriangle> test_first;
    /// If not null, kPacketRays entries, all written: per occluded lane the primitive found
    /// blocking it, kInvalidId where the trace does not say (a ray finished one by one) and on
    /// every other lane.
    std::uint32_t* occluder = nullptr;
    /// Set to the lanes that test_first's triangles blocked.
    LaneMask blocked_first;
};

/// Closest hit of every active lane of `packet` within [tmin, tmax], written to `hits`;
/// inactive lanes get a miss. Lane by lane identical to bvh::intersect_closest(accel, ray)
/// (t, u, v and prim bit for bit, ties included). Works for any rays; rays sharing an origin
/// and close in direction are fastest. Thread-safe on a shared tree; `stats`, if not null,
/// receives this trace's counters (added, not assigned) and must not be shared between threads.
void intersect_closest(const bvh::TriangleBvh& accel, const RayPacket& packet, PacketHits& hits,
                       const PacketConfig& config = {}, PacketStats* stats = nullptr);

/// For every active lane of `packet`, whether any triangle is hit within [tmin, tmax]
/// (shadow rays): `occluded` gets exactly the active lanes for which bvh::intersect_any is
/// true. Rays stop being traced once occluded. Thread-safety and `stats` as above.
/// With `search`, also tests its triangles first and reports the occluders found.
void intersect_any(const bvh::TriangleBvh& accel, const RayPacket& packet, LaneMask& occluded,
                   const PacketConfig& config = {}, PacketStats* stats = nullptr,
                   OccluderSearch* search = nullptr);

}  // namespace dynrt::packet
