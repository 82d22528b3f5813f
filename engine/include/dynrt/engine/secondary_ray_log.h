#pragma once
// The reflection and refraction rays one frame traced, packet by packet as the renderer formed
// them, for benchmarks that replay the same rays through another tracer (`dynrt bench --vs
// embree` gives them to Embree's rtcIntersect16 and rtcIntersect1). Set
// TraceSettings::secondary_log to fill one; the trace appends to it from every worker thread.

#include "dynrt/bvh/ray.h"
#include "dynrt/packet/ray_packet.h"

#include <cstddef>
#include <mutex>
#include <vector>

namespace dynrt {

/// One packet of rays of one kind and depth as the renderer traced them: a frame's rays of
/// that depth sorted by kind, direction octant and origin, up to 256 of them in lanes 0, 1, ...
struct SecondaryRayPacket {
    bool refraction = false;
    int depth = 1;  ///< 1: spawned at a camera ray's hit
    packet::LaneMask lanes;
    std::vector<bvh::Ray> rays;  ///< one per lane of `lanes`, in lane order
};

struct SecondaryRayLog {
    std::vector<SecondaryRayPacket> packets;

    /// Appends a copy of `rays`' active lanes (thread-safe).
    void add(const packet::RayPacket& rays, bool refraction, int depth) {
        SecondaryRayPacket p;
        p.refraction = refraction;
        p.depth = depth;
        p.lanes = rays.active;
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            if (rays.active.test(lane)) p.rays.push_back(rays.ray(lane));
        }
        const std::lock_guard<std::mutex> lock(mutex_);
        packets.push_back(std::move(p));
    }

    /// Rays in all packets.
    std::size_t ray_count() const {
        std::size_t n = 0;
        for (const SecondaryRayPacket& p : packets) n += p.rays.size();
        return n;
    }

private:
    std::mutex mutex_;
};

}  // namespace dynrt
