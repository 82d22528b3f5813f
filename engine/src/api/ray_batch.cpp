#include "ray_batch.h"

#include "dynrt/api/error.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/engine/trace_backend.h"
#include "dynrt/packet/ray_packet.h"
#include "rendering/cpu_tracer.h"

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
/// checking each (an Error names a bad one). No branch in the loop, so the compiler can
/// vectorise it.
template <typename Source>
void load_run(const Source& rays, std::size_t first, std::size_t n, packet::RayPacket& packet) {
    bool valid = true;
    for (std::size_t i = 0; i < n; ++i) {
        const Ray ray = rays[first + i];
        valid &= valid_ray(ray);
        packet.org_x[i] = ray.origin.x;
        packet.org_y[i] = ray.origin.y;
        packet.org_z[i] = ray.origin.z;
        packet.dir_x[i] = ray.direction.x;
        packet.dir_y[i] = ray.direction.y;
        packet.dir_z[i] = ray.direction.z;
        packet.tmin[i] = ray.tmin;
        packet.tmax[i] = ray.tmax;
    }
    if (!valid) {
        for (std::size_t i = 0; i < n; ++i) {
            if (!valid_ray(rays[first + i])) throw_bad_ray(rays[first + i], first + i);
        }
    }
    packet.active = packet::LaneMask{};
    for (std::size_t w = 0; w < n / 64; ++w) packet.active.words[w] = ~std::uint64_t{0};
    if (n % 64) packet.active.words[n / 64] = (std::uint64_t{1} << (n % 64)) - 1;
}

struct RunWork {
    std::size_t hits = 0, packet_rays = 0, single_rays = 0;
};

/// Runs per_run(tracer, first, packet, work) for every run of kRun rays, in parallel: the
/// packet holds the run (lane i is ray first + i), `tracer` is dynrt's over `accel`. Sums the
/// work into QueryStats.
template <typename Source, typename PerRun>
QueryStats for_each_run(const SceneAccel& accel, const Source& rays, std::size_t outputs, PerRun&& per_run) {
    if (outputs != rays.size()) {
        throw Error(Error::Code::invalid_argument,
                    "dynrt::Engine: " + std::to_string(rays.size()) + " rays but room for " +
                        std::to_string(outputs) + " results");
    }
    const Stopwatch clock;
    const detail::CpuTracer tracer(accel, TraceSettings{});
    tbb::combinable<RunWork> work;
    const std::size_t runs = (rays.size() + kRun - 1) / kRun;
    tbb::parallel_for(std::size_t(0), runs, [&](std::size_t r) {
        const std::size_t first = r * kRun, n = std::min(kRun, rays.size() - first);
        packet::RayPacket packet;
        load_run(rays, first, n, packet);
        per_run(tracer, first, packet, work.local());
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
    return for_each_run(accel, rays, hits.size(), [&](const detail::CpuTracer& tracer, std::size_t first,
                                                       const packet::RayPacket& packet, RunWork& work) {
        LaneHits lane_hits;
        const auto packed = std::size_t(tracer.closest(packet, RayCoherence::unknown, lane_hits, nullptr));
        packet.active.for_each([&](int lane) {
            const bvh::InstanceHit& hit = lane_hits[lane];
            hits[first + std::size_t(lane)] = to_api(hit, mesh_ids);
            work.hits += hit.is_hit();
        });
        work.packet_rays += packed;
        work.single_rays += std::size_t(packet.active.count()) - packed;
    });
}

template <typename Source>
QueryStats occluded_rays(const SceneAccel& accel, const Source& rays,
                         std::span<std::uint8_t> occluded) {
    return for_each_run(accel, rays, occluded.size(), [&](const detail::CpuTracer& tracer, std::size_t first,
                                                           const packet::RayPacket& packet, RunWork& work) {
        int packed = 0;
        const packet::LaneMask blocked = tracer.occluded(packet, RayCoherence::unknown, nullptr, packed);
        packet.active.for_each([&](int lane) {
            occluded[first + std::size_t(lane)] = blocked.test(lane);
        });
        work.hits += std::size_t(blocked.count());
        work.packet_rays += std::size_t(packed);
        work.single_rays += std::size_t(packet.active.count() - packed);
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
