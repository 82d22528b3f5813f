#include "rendering/cpu_tracer.h"

#include "dynrt/packet/two_level_packet.h"

namespace dynrt::detail {

namespace {

using packet::kPacketRays;
using packet::LaneMask;
using packet::RayPacket;

/// Copies the rays of `lanes` into the first lanes of `dense`, in lane order, and returns how
/// many. The packet tracer works on the range from the first to the last active lane, so rays
/// scattered over a tile's 256 lanes are traced packed: lane by lane the results are the same
/// (packet_traversal.h), only the empty chunks go.
int pack(const RayPacket& rays, const LaneMask& lanes, RayPacket& dense, int (&lane_of)[kPacketRays]) {
    dense.clear();
    int n = 0;
    lanes.for_each([&](int lane) {
        dense.org_x[n] = rays.org_x[lane];
        dense.org_y[n] = rays.org_y[lane];
        dense.org_z[n] = rays.org_z[lane];
        dense.dir_x[n] = rays.dir_x[lane];
        dense.dir_y[n] = rays.dir_y[lane];
        dense.dir_z[n] = rays.dir_z[lane];
        dense.tmin[n] = rays.tmin[lane];
        dense.tmax[n] = rays.tmax[lane];
        dense.active.set(n);
        lane_of[n++] = lane;
    });
    return n;
}

/// A thread's packets for packing and hits (each several KiB: kept off the stack, which the
/// packet tracer already uses 24 KiB of).
struct Scratch {
    RayPacket dense;
    packet::InstanceHits hits;
    int lane_of[kPacketRays];
};

Scratch& thread_scratch() {
    thread_local Scratch scratch;
    return scratch;
}

}  // namespace

bool CpuTracer::as_packet(int count, RayCoherence coherence) const {
    if (single_rays_) return false;
    return coherence == RayCoherence::tile ? count > kFewTileRays : count >= min_scattered_;
}

void CpuTracer::closest_group(const RayPacket& rays, const LaneMask& lanes, bool packed,
                              HitTarget hits, TraceWork* work) const {
    const bvh::TwoLevelBvh& tlas = accel_.top_level();
    if (!packed) {
        lanes.for_each([&](int lane) {
            bvh::InstanceHit hit = work ? bvh::intersect_closest(tlas, rays.ray(lane), work->single)
                                        : bvh::intersect_closest(tlas, rays.ray(lane));
            accel_.resolve(hit);
            hits[lane] = hit;
        });
        return;
    }
    Scratch& s = thread_scratch();
    const int n = pack(rays, lanes, s.dense, s.lane_of);
    packet::intersect_closest(tlas, s.dense, s.hits, packet_, work ? &work->packet : nullptr);
    for (int k = 0; k < n; ++k) {
        bvh::InstanceHit hit = s.hits.hit(k);
        accel_.resolve(hit);
        hits[s.lane_of[k]] = hit;
    }
}

int CpuTracer::closest(const RayPacket& rays, RayCoherence coherence, HitTarget hits,
                       TraceWork* work) const {
    int packet_rays = 0;
    if (coherence == RayCoherence::tile) {
        // A tile's rays, traced in their pixels' lanes: the packet's beam spans the tile.
        const int count = rays.active.count();
        if (as_packet(count, coherence)) {
            Scratch& s = thread_scratch();
            packet::intersect_closest(accel_.top_level(), rays, s.hits, packet_,
                                      work ? &work->packet : nullptr);
            rays.active.for_each([&](int lane) {
                bvh::InstanceHit hit = s.hits.hit(lane);
                accel_.resolve(hit);
                hits[lane] = hit;
            });
            packet_rays = count;
        } else {
            closest_group(rays, rays.active, false, hits, work);
        }
    } else {
        // Scattered rays, by direction octant.
        LaneMask octant[8];
        rays.active.for_each([&](int lane) {
            const int o = int(rays.dir_x[lane] < 0.0f) | int(rays.dir_y[lane] < 0.0f) << 1 |
                          int(rays.dir_z[lane] < 0.0f) << 2;
            octant[o].set(lane);
        });
        for (const LaneMask& group : octant) {
            const int count = group.count();
            if (count == 0) continue;
            const bool packed = as_packet(count, coherence);
            closest_group(rays, group, packed, hits, work);
            if (packed) packet_rays += count;
        }
    }
    return packet_rays;
}

LaneMask CpuTracer::occluded(const RayPacket& rays, RayCoherence coherence, TraceWork* work) const {
    const bvh::TwoLevelBvh& tlas = accel_.top_level();
    LaneMask blocked;
    if (!as_packet(rays.active.count(), coherence)) {
        rays.active.for_each([&](int lane) {
            const bool hit = work ? bvh::intersect_any(tlas, rays.ray(lane), work->single)
                                  : bvh::intersect_any(tlas, rays.ray(lane));
            if (hit) blocked.set(lane);
        });
        return blocked;
    }
    if (coherence == RayCoherence::tile) {
        packet::intersect_any(tlas, rays, blocked, packet_, work ? &work->packet : nullptr);
        return blocked;
    }
    Scratch& s = thread_scratch();
    const int n = pack(rays, rays.active, s.dense, s.lane_of);
    LaneMask dense_blocked;
    packet::intersect_any(tlas, s.dense, dense_blocked, packet_, work ? &work->packet : nullptr);
    for (int k = 0; k < n; ++k) {
        if (dense_blocked.test(k)) blocked.set(s.lane_of[k]);
    }
    return blocked;
}

}  // namespace dynrt::detail
