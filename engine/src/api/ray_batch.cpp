#include "ray_batch.h"

#include "dynrt/api/error.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/two_level_packet.h"
#include "stopwatch.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
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

/// Loads rays [first, first + n) into lanes 0..n-1 of `packet` (the others inactive), checking
/// each (an Error names a bad one), and returns whether they are coherent: every direction
/// within kCoherentCosine of the run's middle ray's, with its sign on every axis. One pass and
/// no square root: cos(d, r) >= c is tested as (d.r)^2 >= c^2 |d|^2 |r|^2 with d.r > 0.
bool load_run(std::span<const Ray> rays, std::size_t first, std::size_t n,
              packet::RayPacket& packet) {
    const Vec3& r = rays[first + n / 2].direction;
    const float rr = r.x * r.x + r.y * r.y + r.z * r.z;
    const float c2 = kCoherentCosine * kCoherentCosine;
    bool coherent = true;
    for (std::size_t i = 0; i < n; ++i) {
        const Ray& ray = rays[first + i];
        const Vec3& o = ray.origin;
        const Vec3& d = ray.direction;
        const bool valid = finite(o) & finite(d) &
                           ((d.x != 0.0f) | (d.y != 0.0f) | (d.z != 0.0f)) &
                           (ray.tmin >= 0.0f) &
                           (ray.tmin < std::numeric_limits<float>::infinity()) &
                           (ray.tmax >= ray.tmin);
        if (!valid) throw_bad_ray(ray, first + i);
        packet.org_x[i] = o.x;
        packet.org_y[i] = o.y;
        packet.org_z[i] = o.z;
        packet.dir_x[i] = d.x;
        packet.dir_y[i] = d.y;
        packet.dir_z[i] = d.z;
        packet.tmin[i] = ray.tmin;
        packet.tmax[i] = ray.tmax;
        const float dr = d.x * r.x + d.y * r.y + d.z * r.z;
        const float dd = d.x * d.x + d.y * d.y + d.z * d.z;
        const bool same_signs = (std::signbit(d.x) == std::signbit(r.x)) &
                                (std::signbit(d.y) == std::signbit(r.y)) &
                                (std::signbit(d.z) == std::signbit(r.z));
        coherent &= same_signs & (dr > 0.0f) & (dr * dr >= c2 * dd * rr);
    }
    packet.active = packet::LaneMask{};
    for (std::size_t w = 0; w < n / 64; ++w) packet.active.words[w] = ~std::uint64_t{0};
    if (n % 64) packet.active.words[n / 64] = (std::uint64_t{1} << (n % 64)) - 1;
    return coherent;
}

struct RunWork {
    std::size_t hits = 0, packet_rays = 0, single_rays = 0;
};

/// Runs per_run(first, n, the run's packet, whether it is coherent, work) over the runs of kRun
/// rays in parallel, and sums the work into QueryStats.
template <typename PerRun>
QueryStats for_each_run(std::span<const Ray> rays, std::size_t outputs, PerRun&& per_run) {
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
        const bool coherent = load_run(rays, first, n, packet);
        per_run(first, n, packet, coherent, work.local());
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

RayHit to_api(const bvh::InstanceHit& hit) {
    RayHit out;
    if (!hit.is_hit()) return out;
    out.t = hit.hit.t;
    out.mesh = MeshId{hit.object};
    out.primitive = hit.hit.prim;
    out.u = hit.hit.u;
    out.v = hit.hit.v;
    return out;
}

}  // namespace

QueryStats intersect_batch(const SceneAccel& accel, std::span<const Ray> rays,
                           std::span<RayHit> hits) {
    const bvh::TwoLevelBvh& tlas = accel.top_level();
    return for_each_run(rays, hits.size(), [&](std::size_t first, std::size_t n,
                                                const packet::RayPacket& packet, bool coherent,
                                                RunWork& work) {
        const auto store = [&](std::size_t i, bvh::InstanceHit hit) {
            accel.resolve(hit);
            hits[first + i] = to_api(hit);
            work.hits += hit.is_hit();
        };
        if (coherent) {
            packet::InstanceHits packet_hits;
            packet::intersect_closest(tlas, packet, packet_hits);
            for (std::size_t i = 0; i < n; ++i) store(i, packet_hits.hit(int(i)));
            work.packet_rays += n;
        } else {
            for (std::size_t i = 0; i < n; ++i) {
                store(i, bvh::intersect_closest(tlas, packet.ray(int(i))));
            }
            work.single_rays += n;
        }
    });
}

QueryStats occluded_batch(const SceneAccel& accel, std::span<const Ray> rays,
                          std::span<std::uint8_t> occluded) {
    const bvh::TwoLevelBvh& tlas = accel.top_level();
    return for_each_run(rays, occluded.size(), [&](std::size_t first, std::size_t n,
                                                    const packet::RayPacket& packet,
                                                    bool coherent, RunWork& work) {
        if (coherent) {
            packet::LaneMask blocked;
            packet::intersect_any(tlas, packet, blocked);
            for (std::size_t i = 0; i < n; ++i) {
                occluded[first + i] = blocked.test(int(i));
                work.hits += blocked.test(int(i));
            }
            work.packet_rays += n;
        } else {
            for (std::size_t i = 0; i < n; ++i) {
                const bool hit = bvh::intersect_any(tlas, packet.ray(int(i)));
                occluded[first + i] = hit;
                work.hits += hit;
            }
            work.single_rays += n;
        }
    });
}

}  // namespace dynrt::api_detail
