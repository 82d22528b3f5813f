#include "ray_batch.h"

#include "dynrt/api/error.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/two_level_packet.h"
#include "stopwatch.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace dynrt::api_detail {

namespace {

constexpr std::size_t kRun = packet::kPacketRays;

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The engine's ray for `ray`, or an Error naming ray `index` and what is wrong with it.
bvh::Ray checked(const Ray& ray, std::size_t index) {
    const char* problem = nullptr;
    if (!finite(ray.origin)) {
        problem = "origin is not finite";
    } else if (!finite(ray.direction)) {
        problem = "direction is not finite";
    } else if (ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) {
        problem = "direction is zero";
    } else if (!(ray.tmin >= 0.0f) || std::isinf(ray.tmin)) {
        problem = "tmin is not finite and >= 0";
    } else if (!(ray.tmax >= ray.tmin)) {
        problem = "tmax is not >= tmin";
    }
    if (problem) {
        throw Error(Error::Code::invalid_argument,
                    "dynrt::Engine: ray " + std::to_string(index) + ": " + problem);
    }
    return bvh::Ray{{ray.origin.x, ray.origin.y, ray.origin.z},
                    {ray.direction.x, ray.direction.y, ray.direction.z},
                    ray.tmin,
                    ray.tmax};
}

/// Whether rays [first, first + n) may share a packet: one direction sign per axis, and every
/// direction within kCoherentCosine of their mean.
bool coherent(std::span<const bvh::Ray> rays) {
    const auto signs = [](const glm::vec3& d) {
        return int(std::signbit(d.x)) | int(std::signbit(d.y)) << 1 | int(std::signbit(d.z)) << 2;
    };
    const int octant = signs(rays[0].dir);
    glm::vec3 sum{0.0f};
    for (const bvh::Ray& ray : rays) {
        if (signs(ray.dir) != octant) return false;
        sum += glm::normalize(ray.dir);
    }
    const glm::vec3 mean = glm::normalize(sum);
    return std::all_of(rays.begin(), rays.end(), [&](const bvh::Ray& ray) {
        return glm::dot(glm::normalize(ray.dir), mean) >= kCoherentCosine;
    });
}

struct RunWork {
    std::size_t hits = 0, packet_rays = 0, single_rays = 0;
};

/// Runs per_run(first, rays of the run as engine rays, work) over runs of kRun rays in
/// parallel, and sums the work into QueryStats.
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
        bvh::Ray run[kRun];
        for (std::size_t i = 0; i < n; ++i) run[i] = checked(rays[first + i], first + i);
        per_run(first, std::span<const bvh::Ray>(run, n), work.local());
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

void fill_packet(std::span<const bvh::Ray> run, packet::RayPacket& packet) {
    packet.clear();
    for (std::size_t i = 0; i < run.size(); ++i) packet.set_ray(int(i), run[i]);
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
    return for_each_run(rays, hits.size(), [&](std::size_t first, std::span<const bvh::Ray> run,
                                                RunWork& work) {
        if (coherent(run)) {
            packet::RayPacket packet;
            packet::InstanceHits packet_hits;
            fill_packet(run, packet);
            packet::intersect_closest(tlas, packet, packet_hits);
            for (std::size_t i = 0; i < run.size(); ++i) {
                bvh::InstanceHit hit = packet_hits.hit(int(i));
                accel.resolve(hit);
                hits[first + i] = to_api(hit);
                work.hits += hit.is_hit();
            }
            work.packet_rays += run.size();
            return;
        }
        for (std::size_t i = 0; i < run.size(); ++i) {
            bvh::InstanceHit hit = bvh::intersect_closest(tlas, run[i]);
            accel.resolve(hit);
            hits[first + i] = to_api(hit);
            work.hits += hit.is_hit();
        }
        work.single_rays += run.size();
    });
}

QueryStats occluded_batch(const SceneAccel& accel, std::span<const Ray> rays,
                          std::span<std::uint8_t> occluded) {
    const bvh::TwoLevelBvh& tlas = accel.top_level();
    return for_each_run(rays, occluded.size(), [&](std::size_t first,
                                                    std::span<const bvh::Ray> run,
                                                    RunWork& work) {
        if (coherent(run)) {
            packet::RayPacket packet;
            packet::LaneMask blocked;
            fill_packet(run, packet);
            packet::intersect_any(tlas, packet, blocked);
            for (std::size_t i = 0; i < run.size(); ++i) {
                const bool hit = blocked.test(int(i));
                occluded[first + i] = hit;
                work.hits += hit;
            }
            work.packet_rays += run.size();
            return;
        }
        for (std::size_t i = 0; i < run.size(); ++i) {
            const bool hit = bvh::intersect_any(tlas, run[i]);
            occluded[first + i] = hit;
            work.hits += hit;
        }
        work.single_rays += run.size();
    });
}

}  // namespace dynrt::api_detail
