#include "ray_batch.h"

#include "dynrt/api/error.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/two_level_packet.h"
#include "dynrt/engine/stopwatch.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace dynrt::api_detail {

namespace {

constexpr std::size_t kRun = packet::kPacketRays;

bool finite(const Vec3& v) {
    return std::isfinite(v.x) & std::isfinite(v.y) & std::isfinite(v.z);
}

/// The API's contract for a ray (dynrt::Ray), without branches.
bool valid_ray(const Ray& ray) {
    const Vec3& d = ray.direction;
    return finite(ray.origin) & finite(d) & ((d.x != 0.0f) | (d.y != 0.0f) | (d.z != 0.0f)) &
           (ray.tmin >= 0.0f) & (ray.tmin < std::numeric_limits<float>::infinity()) &
           (ray.tmax >= ray.tmin);
}

[[noreturn]] void throw_bad_ray(const Ray& ray, std::size_t index) {
    const char* problem = "tmax is not >= tmin";
    if (!finite(ray.origin)) {
        problem = "origin is not finite";
    } else if (!finite(ray.direction)) {
        problem = "direction is not finite";
    } else if (ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) {
        problem = "direction is zero";
    } else if (!(ray.tmin >= 0.0f) || std::isinf(ray.tmin)) {
        problem = "tmin is not finite and >= 0";
    }
    throw Error(Error::Code::invalid_argument,
                "dynrt::Engine: ray " + std::to_string(index) + ": " + problem);
}

/// Where a batch's rays come from: an array of dynrt::Ray or separate arrays (RayArrays). Both
/// hand out ray i as a dynrt::Ray value, which the compiler keeps in registers.
struct RayStructs {
    std::span<const Ray> rays;
    std::size_t size() const { return rays.size(); }
    Ray operator[](std::size_t i) const { return rays[i]; }
};

struct RayColumns {
    const RayArrays& arrays;
    std::size_t size() const { return arrays.size(); }
    Ray operator[](std::size_t i) const {
        const float* o = arrays.origins.data() + 3 * i;
        const float* d = arrays.directions.data() + 3 * i;
        return Ray{{o[0], o[1], o[2]}, {d[0], d[1], d[2]},
                   arrays.tmin.empty() ? arrays.tmin_all : arrays.tmin[i],
                   arrays.tmax.empty() ? arrays.tmax_all : arrays.tmax[i]};
    }
};

/// RayArrays whose sizes agree, or an Error saying which does not.
void check_sizes(const RayArrays& a) {
    const auto fail = [](const std::string& what) {
        throw Error(Error::Code::invalid_argument, "dynrt::Engine: ray arrays: " + what);
    };
    if (a.origins.size() % 3 != 0) {
        fail(std::to_string(a.origins.size()) + " origin floats, not 3 per ray");
    }
    const std::size_t n = a.size();
    if (a.directions.size() != a.origins.size()) {
        fail(std::to_string(n) + " origins but " + std::to_string(a.directions.size()) +
             " direction floats (3 per ray)");
    }
    if (!a.tmin.empty() && a.tmin.size() != n) {
        fail(std::to_string(n) + " rays but " + std::to_string(a.tmin.size()) + " tmin values");
    }
    if (!a.tmax.empty() && a.tmax.size() != n) {
        fail(std::to_string(n) + " rays but " + std::to_string(a.tmax.size()) + " tmax values");
    }
}

/// Loads rays [first, first + n) into lanes 0..n-1 of `packet` (the others inactive),
/// checking each (an Error names a bad one). Returns whether the whole run is one coherent
/// group (see group_run), the common case of a batch in a coherent order, decided in the same
/// pass: every direction with the signs of the run's middle ray's and within kCoherentCosine
/// of it. No branch in the loop, so the compiler can vectorise it.
template <typename Source>
bool load_run(const Source& rays, std::size_t first, std::size_t n, packet::RayPacket& packet) {
    const Vec3 r = rays[first + n / 2].direction;
    const float c2rr = kCoherentCosine * kCoherentCosine * (r.x * r.x + r.y * r.y + r.z * r.z);
    bool valid = true, coherent = true;
    for (std::size_t i = 0; i < n; ++i) {
        const Ray ray = rays[first + i];
        const Vec3& o = ray.origin;
        const Vec3& d = ray.direction;
        valid &= valid_ray(ray);
        packet.org_x[i] = o.x;
        packet.org_y[i] = o.y;
        packet.org_z[i] = o.z;
        packet.dir_x[i] = d.x;
        packet.dir_y[i] = d.y;
        packet.dir_z[i] = d.z;
        packet.tmin[i] = ray.tmin;
        packet.tmax[i] = ray.tmax;
        const float dr = d.x * r.x + d.y * r.y + d.z * r.z;
        const bool same_signs = (std::signbit(d.x) == std::signbit(r.x)) &
                                (std::signbit(d.y) == std::signbit(r.y)) &
                                (std::signbit(d.z) == std::signbit(r.z));
        coherent &= same_signs & (dr > 0.0f) & (dr * dr >= c2rr * (d.x * d.x + d.y * d.y + d.z * d.z));
    }
    if (!valid) {
        for (std::size_t i = 0; i < n; ++i) {
            if (!valid_ray(rays[first + i])) throw_bad_ray(rays[first + i], first + i);
        }
    }
    packet.active = packet::LaneMask{};
    for (std::size_t w = 0; w < n / 64; ++w) packet.active.words[w] = ~std::uint64_t{0};
    if (n % 64) packet.active.words[n / 64] = (std::uint64_t{1} << (n % 64)) - 1;
    return coherent && int(n) >= kPacketRaysMin;
}

/// A set of a run's rays traced together: as a packet (the lanes of `lanes`) or one by one.
struct RayGroup {
    packet::LaneMask lanes;
    bool packet = false;
};

/// Splits the loaded run into groups by the signs of the directions (at most 8), and marks a
/// group as a packet when it has at least kPacketRaysMin rays, all within kCoherentCosine of
/// the direction of its middle ray. A batch in a coherent order gives one group; a lidar sweep
/// crossing the horizon gives two coherent ones. No square root: cos(d, r) >= c is tested as
/// (d.r)^2 >= c^2 |d|^2 |r|^2 with d.r > 0. Returns the number of groups written to `groups`.
int group_run(const packet::RayPacket& packet, std::size_t n, RayGroup (&groups)[8]) {
    // Lanes sorted by octant (a counting sort), so each group reads only its own lanes.
    std::uint8_t octant_of[packet::kPacketRays];
    int count[8] = {};
    for (std::size_t i = 0; i < n; ++i) {
        const int octant = int(std::signbit(packet.dir_x[i])) |
                           int(std::signbit(packet.dir_y[i])) << 1 |
                           int(std::signbit(packet.dir_z[i])) << 2;
        octant_of[i] = std::uint8_t(octant);
        ++count[octant];
    }
    int start[9] = {};
    for (int octant = 0; octant < 8; ++octant) start[octant + 1] = start[octant] + count[octant];
    std::uint16_t order[packet::kPacketRays];
    int next[8];
    std::copy(start, start + 8, next);
    for (std::size_t i = 0; i < n; ++i) order[next[octant_of[i]]++] = std::uint16_t(i);

    int written = 0;
    for (int octant = 0; octant < 8; ++octant) {
        if (count[octant] == 0) continue;
        RayGroup& group = groups[written++];
        group = RayGroup{};
        const std::span<const std::uint16_t> lanes(order + start[octant], std::size_t(count[octant]));
        for (const std::uint16_t lane : lanes) group.lanes.set(lane);
        if (count[octant] < kPacketRaysMin) continue;
        // The group's middle ray is its reference direction.
        const int middle = lanes[lanes.size() / 2];
        const float rx = packet.dir_x[middle], ry = packet.dir_y[middle], rz = packet.dir_z[middle];
        const float c2rr = kCoherentCosine * kCoherentCosine * (rx * rx + ry * ry + rz * rz);
        bool coherent = true;
        for (const std::uint16_t lane : lanes) {
            const float dx = packet.dir_x[lane], dy = packet.dir_y[lane], dz = packet.dir_z[lane];
            const float dr = dx * rx + dy * ry + dz * rz;
            coherent &= (dr > 0.0f) & (dr * dr >= c2rr * (dx * dx + dy * dy + dz * dz));
        }
        group.packet = coherent;
    }
    return written;
}

struct RunWork {
    std::size_t hits = 0, packet_rays = 0, single_rays = 0;
};

/// Runs per_group(first, packet, as_packet, work) for every group of every run of kRun rays,
/// in parallel: the packet holds the run (lane i is ray first + i) with the group's lanes
/// active. Sums the work into QueryStats.
template <typename Source, typename PerGroup>
QueryStats for_each_group(const Source& rays, std::size_t outputs, PerGroup&& per_group) {
    if (outputs != rays.size()) {
        throw Error(Error::Code::invalid_argument,
                    "dynrt::Engine: " + std::to_string(rays.size()) + " rays but room for " +
                        std::to_string(outputs) + " results");
    }
    const Stopwatch clock;
    tbb::combinable<RunWork> work;
    const std::size_t runs = (rays.size() + kRun - 1) / kRun;
    tbb::parallel_for(std::size_t(0), runs, [&](std::size_t r) {
        const std::size_t first = r * kRun, n = std::min(kRun, rays.size() - first);
        packet::RayPacket packet;
        RayGroup groups[8];
        int count = 1;
        if (load_run(rays, first, n, packet)) {
            groups[0] = RayGroup{packet.active, true};
        } else {
            count = group_run(packet, n, groups);
        }
        for (int g = 0; g < count; ++g) {
            packet.active = groups[g].lanes;
            per_group(first, packet, groups[g].packet, work.local());
        }
    });
    const RunWork sum = work.combine([](RunWork a, const RunWork& b) {
        return RunWork{a.hits + b.hits, a.packet_rays + b.packet_rays,
                       a.single_rays + b.single_rays};
    });
    QueryStats stats;
    stats.rays = rays.size();
    stats.hits = sum.hits;
    stats.packet_rays = sum.packet_rays;
    stats.single_rays = sum.single_rays;
    stats.ms = clock.elapsed_ms();
    stats.mrays_per_s = stats.ms > 0.0 ? double(stats.rays) / (stats.ms * 1e3) : 0.0;
    return stats;
}

RayHit to_api(const bvh::InstanceHit& hit, std::span<const std::uint32_t> mesh_ids) {
    RayHit out;
    if (!hit.is_hit()) return out;
    out.t = hit.hit.t;
    out.mesh = MeshId{mesh_ids.empty() ? hit.object : mesh_ids[hit.object]};
    out.primitive = hit.hit.prim;
    out.u = hit.hit.u;
    out.v = hit.hit.v;
    return out;
}


template <typename Source>
QueryStats intersect_rays(const SceneAccel& accel, const Source& rays, std::span<RayHit> hits,
                          std::span<const std::uint32_t> mesh_ids) {
    const bvh::TwoLevelBvh& tlas = accel.top_level();
    return for_each_group(rays, hits.size(), [&](std::size_t first,
                                                  const packet::RayPacket& packet,
                                                  bool as_packet, RunWork& work) {
        const auto store = [&](int lane, bvh::InstanceHit hit) {
            accel.resolve(hit);
            hits[first + std::size_t(lane)] = to_api(hit, mesh_ids);
            work.hits += hit.is_hit();
        };
        const std::size_t n = std::size_t(packet.active.count());
        if (as_packet) {
            packet::InstanceHits packet_hits;
            packet::intersect_closest(tlas, packet, packet_hits);
            packet.active.for_each([&](int lane) { store(lane, packet_hits.hit(lane)); });
            work.packet_rays += n;
        } else {
            packet.active.for_each([&](int lane) {
                store(lane, bvh::intersect_closest(tlas, packet.ray(lane)));
            });
            work.single_rays += n;
        }
    });
}

template <typename Source>
QueryStats occluded_rays(const SceneAccel& accel, const Source& rays,
                         std::span<std::uint8_t> occluded) {
    const bvh::TwoLevelBvh& tlas = accel.top_level();
    return for_each_group(rays, occluded.size(), [&](std::size_t first,
                                                      const packet::RayPacket& packet,
                                                      bool as_packet, RunWork& work) {
        const std::size_t n = std::size_t(packet.active.count());
        if (as_packet) {
            packet::LaneMask blocked;
            packet::intersect_any(tlas, packet, blocked);
            packet.active.for_each([&](int lane) {
                occluded[first + std::size_t(lane)] = blocked.test(lane);
                work.hits += blocked.test(lane);
            });
            work.packet_rays += n;
        } else {
            packet.active.for_each([&](int lane) {
                const bool hit = bvh::intersect_any(tlas, packet.ray(lane));
                occluded[first + std::size_t(lane)] = hit;
                work.hits += hit;
            });
            work.single_rays += n;
        }
    });
}

}  // namespace

QueryStats intersect_batch(const SceneAccel& accel, std::span<const Ray> rays,
                           std::span<RayHit> hits, std::span<const std::uint32_t> mesh_ids) {
    return intersect_rays(accel, RayStructs{rays}, hits, mesh_ids);
}

QueryStats intersect_batch(const SceneAccel& accel, const RayArrays& rays,
                           std::span<RayHit> hits, std::span<const std::uint32_t> mesh_ids) {
    check_sizes(rays);
    return intersect_rays(accel, RayColumns{rays}, hits, mesh_ids);
}

QueryStats occluded_batch(const SceneAccel& accel, std::span<const Ray> rays,
                          std::span<std::uint8_t> occluded) {
    return occluded_rays(accel, RayStructs{rays}, occluded);
}

QueryStats occluded_batch(const SceneAccel& accel, const RayArrays& rays,
                          std::span<std::uint8_t> occluded) {
    check_sizes(rays);
    return occluded_rays(accel, RayColumns{rays}, occluded);
}

}  // namespace dynrt::api_detail
