#include "rendering/cpu_tracer.h"

#include "dynrt/packet/two_level_packet.h"

#include <glm/vec3.hpp>

#include <bit>
#include <vector>

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
    // The occluder cache's questions and answers.
    std::vector<packet::InstanceTriangle> guesses;
    alignas(64) std::uint32_t occluder_instance[kPacketRays];
    alignas(64) std::uint32_t occluder_prim[kPacketRays];
};

Scratch& thread_scratch() {
    thread_local Scratch scratch;
    return scratch;
}

/// Whether every active lane of `rays` starts at the same point (bit for bit), which is then
/// `origin`: a light's shadow rays.
bool one_origin(const RayPacket& rays, glm::vec3& origin) {
    int first = -1;
    for (int w = 0; w < kPacketRays / 64 && first < 0; ++w) {
        if (rays.active.words[w] != 0) first = w * 64 + std::countr_zero(rays.active.words[w]);
    }
    if (first < 0) return false;
    const auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
    const std::uint32_t x = bits(rays.org_x[first]), y = bits(rays.org_y[first]), z = bits(rays.org_z[first]);
    bool same = true;
    // Every lane, inactive ones passing: branch-free, so it vectorises.
    for (int lane = 0; lane < kPacketRays; ++lane) {
        const bool inactive = ((rays.active.words[lane >> 6] >> (lane & 63)) & 1u) == 0;
        same &= inactive | ((bits(rays.org_x[lane]) == x) & (bits(rays.org_y[lane]) == y) &
                            (bits(rays.org_z[lane]) == z));
    }
    origin = glm::vec3(rays.org_x[first], rays.org_y[first], rays.org_z[first]);
    return same;
}

/// `lanes` of `rays` by the octant of their directions.
void split_by_octant(const RayPacket& rays, const LaneMask& lanes, LaneMask (&octant)[8]) {
    lanes.for_each([&](int lane) {
        const int o = int(rays.dir_x[lane] < 0.0f) | int(rays.dir_y[lane] < 0.0f) << 1 |
                      int(rays.dir_z[lane] < 0.0f) << 2;
        octant[o].set(lane);
    });
}

/// The `k`-th lane of `lanes` (0-based, in lane order); precondition: k < lanes.count().
int nth_lane(const LaneMask& lanes, int k) {
    int w = 0;
    for (; k >= std::popcount(lanes.words[w]); ++w) k -= std::popcount(lanes.words[w]);
    std::uint64_t bits = lanes.words[w];
    for (; k > 0; --k) bits &= bits - 1;
    return w * 64 + std::countr_zero(bits);
}

/// One past the last lane of `lanes` (0 when empty).
int lane_end(const LaneMask& lanes) {
    for (int w = kPacketRays / 64 - 1; w >= 0; --w) {
        if (lanes.words[w] != 0) return w * 64 + 64 - std::countl_zero(lanes.words[w]);
    }
    return 0;
}

/// Whether every direction of `group` lies within `cosine` of the direction of its middle lane
/// (in lane order), and, with `same_octant`, in that direction's octant. No square root:
/// cos(d, r) >= c is tested as (d.r)^2 >= c^2 |d|^2 |r|^2 with d.r > 0. A group of the first
/// lanes (a caller's run) is tested in one branch-free pass, which the compiler vectorises.
template <bool same_octant>
bool within_cone(const RayPacket& rays, const LaneMask& group, float cosine) {
    const int middle = nth_lane(group, group.count() / 2);
    const float rx = rays.dir_x[middle], ry = rays.dir_y[middle], rz = rays.dir_z[middle];
    const float c2rr = cosine * cosine * (rx * rx + ry * ry + rz * rz);
    const bool nx = rx < 0.0f, ny = ry < 0.0f, nz = rz < 0.0f;
    const auto close = [&](int lane) {
        const float dx = rays.dir_x[lane], dy = rays.dir_y[lane], dz = rays.dir_z[lane];
        const float dr = dx * rx + dy * ry + dz * rz;
        bool near = (dr > 0.0f) & (dr * dr >= c2rr * (dx * dx + dy * dy + dz * dz));
        if constexpr (same_octant) near &= ((dx < 0.0f) == nx) & ((dy < 0.0f) == ny) & ((dz < 0.0f) == nz);
        return near;
    };
    const int end = lane_end(group);
    bool coherent = true;
    if (group.count() == end) {
        // Lanes 0 to end - 1, a caller's run: no mask to read.
        for (int lane = 0; lane < end; ++lane) coherent &= close(lane);
        return coherent;
    }
    group.for_each([&](int lane) { coherent &= close(lane); });
    return coherent;
}

}  // namespace

bool CpuTracer::as_packet(const RayPacket& rays, const LaneMask& group, RayCoherence coherence) const {
    if (single_rays_) return false;
    const int count = group.count();
    switch (coherence) {
        case RayCoherence::tile: return count > kFewTileRays;
        case RayCoherence::scattered: return count >= min_scattered_;
        case RayCoherence::unknown:
            return count >= kPacketRaysMin && within_cone<false>(rays, group, kCoherentCosine);
    }
    return false;
}

bool CpuTracer::one_coherent_group(const RayPacket& rays) const {
    return !single_rays_ && rays.active.count() >= kPacketRaysMin &&
           within_cone<true>(rays, rays.active, kCoherentCosine);
}

bool CpuTracer::in_place(const RayPacket& rays, const LaneMask& lanes, RayCoherence coherence) {
    return coherence == RayCoherence::tile || (coherence == RayCoherence::unknown && lanes == rays.active);
}

void CpuTracer::closest_group(const RayPacket& rays, const LaneMask& lanes, bool packed, bool traced_in_place,
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
    if (traced_in_place) {
        packet::intersect_closest(tlas, rays, s.hits, packet_, work ? &work->packet : nullptr);
        lanes.for_each([&](int lane) {
            bvh::InstanceHit hit = s.hits.hit(lane);
            accel_.resolve(hit);
            hits[lane] = hit;
        });
        return;
    }
    const int n = pack(rays, lanes, s.dense, s.lane_of);
    packet::intersect_closest(tlas, s.dense, s.hits, packet_, work ? &work->packet : nullptr);
    for (int k = 0; k < n; ++k) {
        bvh::InstanceHit hit = s.hits.hit(k);
        accel_.resolve(hit);
        hits[s.lane_of[k]] = hit;
    }
}

template <class TraceGroup>
int CpuTracer::for_each_group(const RayPacket& rays, RayCoherence coherence, bool closest_hits,
                              TraceGroup&& trace) const {
    // One group: a tile's rays (the packet's beam spans the tile), a sorted stream's shadow
    // rays toward one light, or a caller's run that is one coherent group as a whole.
    const bool whole = coherence == RayCoherence::tile ||
                       (coherence == RayCoherence::scattered && !closest_hits) ||
                       (coherence == RayCoherence::unknown && one_coherent_group(rays));
    if (whole) {
        // one_coherent_group has already said as_packet's yes for a caller's run.
        const bool packed = coherence == RayCoherence::unknown || as_packet(rays, rays.active, coherence);
        trace(rays.active, packed, in_place(rays, rays.active, coherence));
        return packed ? rays.active.count() : 0;
    }
    // Scattered rays' closest hits, and a caller's other runs, by direction octant.
    int packet_rays = 0;
    LaneMask octant[8];
    split_by_octant(rays, rays.active, octant);
    for (const LaneMask& group : octant) {
        if (!group.any()) continue;
        const bool packed = as_packet(rays, group, coherence);
        trace(group, packed, in_place(rays, group, coherence));
        if (packed) packet_rays += group.count();
    }
    return packet_rays;
}

int CpuTracer::closest(const RayPacket& rays, RayCoherence coherence, HitTarget hits,
                       TraceWork* work) const {
    return for_each_group(rays, coherence, true, [&](const LaneMask& group, bool packed, bool traced_in_place) {
        closest_group(rays, group, packed, traced_in_place, hits, work);
    });
}

LaneMask CpuTracer::occluded(const RayPacket& rays, RayCoherence coherence, TraceWork* work) const {
    int packet_rays = 0;
    return occluded(rays, coherence, work, packet_rays);
}

LaneMask CpuTracer::occluded(const RayPacket& rays, RayCoherence coherence, TraceWork* work,
                             int& packet_rays) const {
    LaneMask blocked;
    packet_rays = for_each_group(rays, coherence, false, [&](const LaneMask& group, bool packed, bool traced_in_place) {
        blocked |= occluded_group(rays, group, packed, traced_in_place, work);
    });
    return blocked;
}

LaneMask CpuTracer::occluded_group(const RayPacket& rays, const LaneMask& lanes, bool packed,
                                   bool traced_in_place, TraceWork* work) const {
    const bvh::TwoLevelBvh& tlas = accel_.top_level();
    LaneMask blocked;
    if (!packed) {
        lanes.for_each([&](int lane) {
            const bool hit = work ? bvh::intersect_any(tlas, rays.ray(lane), work->single)
                                  : bvh::intersect_any(tlas, rays.ray(lane));
            if (hit) blocked.set(lane);
        });
        return blocked;
    }
    if (traced_in_place) return occluded_packet(rays, work);
    Scratch& s = thread_scratch();
    const int n = pack(rays, lanes, s.dense, s.lane_of);
    const LaneMask dense_blocked = occluded_packet(s.dense, work);
    for (int k = 0; k < n; ++k) {
        if (dense_blocked.test(k)) blocked.set(s.lane_of[k]);
    }
    return blocked;
}

LaneMask CpuTracer::occluded_packet(const RayPacket& rays, TraceWork* work) const {
    const bvh::TwoLevelBvh& tlas = accel_.top_level();
    packet::PacketStats* stats = work ? &work->packet : nullptr;
    LaneMask blocked;
    glm::vec3 origin;
    OccluderCache::Light* light = cache_ && one_origin(rays, origin) ? cache_->light_at(origin) : nullptr;
    if (light == nullptr) {
        packet::intersect_any(tlas, rays, blocked, packet_, stats);
        return blocked;
    }
    Scratch& s = thread_scratch();
    cache_->guesses(*light, rays, accel_, s.guesses);
    packet::InstanceOccluderSearch search{s.guesses, s.occluder_instance, s.occluder_prim, {}};
    packet::intersect_any(tlas, rays, blocked, packet_, stats, &search);
    cache_->learn(*light, rays, blocked & ~search.blocked_first, s.occluder_instance, s.occluder_prim);
    cache_->count(std::size_t(rays.active.count()), std::size_t(search.blocked_first.count()));
    return blocked;
}

}  // namespace dynrt::detail
