// The library API's per-step overhead (issue 7), for a simulation loop over a deforming mesh of
// about 100k triangles: each step gives new vertex positions, brings the tree up to date (a
// refit) and traces 1M closest-hit ray queries. The same step is timed through dynrt::Engine
// (dynrt/dynrt.h) and through the internals called directly: the triangles gathered from the
// positions, bvh::refit of one TriangleBvh, and the rays traced in runs of 256 with
// packet::intersect_closest (or one by one with bvh::intersect_closest, where the API traces
// them one by one too). What the API adds: checking positions and rays, copying positions
// (Ownership::copy), a top level over the one instance, choosing packets, converting hits.
//
// Each iteration is one step, alternating between two frames of a wave so that every vertex
// moves every step. Ray sets: `tiles` (1024x1024 camera rays over the mesh, 16x16 blocks in
// order, the packet tracer's best case), `rows` (the same rays row by row: runs of 256 are row
// segments) and `random` (random origins and directions above the mesh: traced one by one).

#include "dynrt/api/engine.h"
#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

/// 224 x 224 vertices: 2 * 223 * 223 = 99,458 triangles over the unit square (y up).
constexpr int kGrid = 224;
constexpr int kImage = 1024;  // 1024 x 1024 = 1,048,576 rays

struct Input {
    std::vector<std::uint32_t> indices;
    /// Two frames of the wave, x, y, z per vertex.
    std::vector<float> frames[2];
    std::vector<Ray> rays_tiles, rays_rows, rays_random;
};

std::vector<float> wave_frame(float phase) {
    std::vector<float> p;
    p.reserve(3 * kGrid * kGrid);
    for (int j = 0; j < kGrid; ++j) {
        for (int i = 0; i < kGrid; ++i) {
            const float x = float(i) / (kGrid - 1), z = float(j) / (kGrid - 1);
            p.push_back(x);
            p.push_back(0.05f * std::sin(12.0f * x + phase) * std::cos(9.0f * z - phase));
            p.push_back(z);
        }
    }
    return p;
}

Ray camera_ray(int x, int y) {
    // From above the mesh's centre, looking down over it (60 degrees across).
    const float s = std::tan(0.5236f);
    const float u = (2.0f * (float(x) + 0.5f) / kImage - 1.0f) * s;
    const float v = (2.0f * (float(y) + 0.5f) / kImage - 1.0f) * s;
    return Ray{{0.5f, 1.2f, 0.5f}, {u, -1.0f, v}, 0.0f, 100.0f};
}

const Input& input() {
    static const Input in = [] {
        Input out;
        for (int j = 0; j + 1 < kGrid; ++j) {
            for (int i = 0; i + 1 < kGrid; ++i) {
                const std::uint32_t a = std::uint32_t(j * kGrid + i), b = a + 1,
                                    c = a + kGrid, d = c + 1;
                out.indices.insert(out.indices.end(), {a, c, b, b, c, d});
            }
        }
        out.frames[0] = wave_frame(0.0f);
        out.frames[1] = wave_frame(1.0f);
        for (int ty = 0; ty < kImage; ty += 16) {
            for (int tx = 0; tx < kImage; tx += 16) {
                for (int y = ty; y < ty + 16; ++y) {
                    for (int x = tx; x < tx + 16; ++x) out.rays_tiles.push_back(camera_ray(x, y));
                }
            }
        }
        for (int y = 0; y < kImage; ++y) {
            for (int x = 0; x < kImage; ++x) out.rays_rows.push_back(camera_ray(x, y));
        }
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f), any(-1.0f, 1.0f);
        for (int k = 0; k < kImage * kImage; ++k) {
            out.rays_random.push_back(Ray{{unit(rng), 0.3f + unit(rng), unit(rng)},
                                          {any(rng), -0.2f - unit(rng), any(rng)}, 0.0f, 100.0f});
        }
        return out;
    }();
    return in;
}

const std::vector<Ray>& rays_of(int set) {
    const Input& in = input();
    return set == 0 ? in.rays_tiles : set == 1 ? in.rays_rows : in.rays_random;
}

const char* const kSetNames[] = {"tiles", "rows", "random"};

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

void report(benchmark::State& state, double update_ms, double trace_ms, std::size_t rays,
            std::size_t hits, std::size_t packet_rays) {
    const double steps = double(state.iterations());
    state.counters["update_ms"] = update_ms / steps;
    state.counters["trace_ms"] = trace_ms / steps;
    state.counters["hit_fraction"] = double(hits) / (double(rays) * steps);
    state.counters["packet_fraction"] = double(packet_rays) / (double(rays) * steps);
    state.counters["rays_per_s"] =
        benchmark::Counter(double(rays) * steps, benchmark::Counter::kIsRate);
}

/// One step through the API: set_positions, update, intersect.
void BM_StepApi(benchmark::State& state) {
    const Input& in = input();
    const std::vector<Ray>& rays = rays_of(int(state.range(0)));
    const Ownership ownership = state.range(1) ? Ownership::borrow : Ownership::copy;
    std::vector<float> borrowed = in.frames[0];
    Engine engine;
    MeshDesc desc;
    desc.name = "wave";
    desc.positions = ownership == Ownership::borrow ? std::span<const float>(borrowed)
                                                    : std::span<const float>(in.frames[0]);
    desc.indices = in.indices;
    desc.motion = Motion::deformable;
    desc.ownership = ownership;
    const MeshId mesh = engine.add_mesh(desc);
    engine.update();
    std::vector<RayHit> hits(rays.size());
    double update_ms = 0.0, trace_ms = 0.0;
    std::size_t hit_count = 0, packet_rays = 0, step = 0;
    for (auto _ : state) {
        const std::vector<float>& frame = in.frames[++step % 2];
        auto start = std::chrono::steady_clock::now();
        if (ownership == Ownership::borrow) {
            // The simulation writes its own buffer (not timed: it is the caller's work).
            state.PauseTiming();
            std::copy(frame.begin(), frame.end(), borrowed.begin());
            state.ResumeTiming();
            start = std::chrono::steady_clock::now();
            engine.set_positions(mesh, borrowed);
        } else {
            engine.set_positions(mesh, frame);
        }
        const FrameStats stats = engine.update();
        benchmark::DoNotOptimize(stats.refit_ms);
        update_ms += ms_since(start);
        start = std::chrono::steady_clock::now();
        const QueryStats query = engine.intersect(rays, hits);
        trace_ms += ms_since(start);
        hit_count += query.hits;
        packet_rays += query.packet_rays;
        benchmark::ClobberMemory();
    }
    report(state, update_ms, trace_ms, rays.size(), hit_count, packet_rays);
}

/// The same step on the internals: gather triangles, refit, trace runs of 256.
void BM_StepInternals(benchmark::State& state) {
    const Input& in = input();
    const std::vector<Ray>& api_rays = rays_of(int(state.range(0)));
    const bool packets = state.range(0) != 2;  // as the API decides for these sets
    std::vector<bvh::Ray> rays(api_rays.size());
    for (std::size_t k = 0; k < rays.size(); ++k) {
        const Ray& r = api_rays[k];
        rays[k] = bvh::Ray{{r.origin.x, r.origin.y, r.origin.z},
                           {r.direction.x, r.direction.y, r.direction.z}, r.tmin, r.tmax};
    }
    const std::size_t triangle_count = in.indices.size() / 3;
    std::vector<bvh::Triangle> triangles(triangle_count);
    const auto gather = [&](const std::vector<float>& p) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangle_count, 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t t = range.begin(); t < range.end(); ++t) {
                                  glm::vec3 v[3];
                                  for (int k = 0; k < 3; ++k) {
                                      const std::size_t i = in.indices[3 * t + k];
                                      v[k] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
                                  }
                                  triangles[t] = bvh::Triangle{v[0], v[1], v[2]};
                              }
                          });
    };
    gather(in.frames[0]);
    const bvh::BuildConfig config;
    bvh::TriangleBvh tree = bvh::build_triangle_bvh(triangles, config);
    std::vector<bvh::Hit> hits(rays.size());
    double update_ms = 0.0, trace_ms = 0.0;
    std::size_t hit_count = 0, step = 0;
    for (auto _ : state) {
        auto start = std::chrono::steady_clock::now();
        gather(in.frames[++step % 2]);
        const bvh::RefitResult refit = bvh::refit(tree, triangles, config.sah_costs());
        benchmark::DoNotOptimize(refit.sah_cost);
        update_ms += ms_since(start);
        start = std::chrono::steady_clock::now();
        const std::size_t runs = (rays.size() + 255) / 256;
        tbb::parallel_for(std::size_t(0), runs, [&](std::size_t r) {
            const std::size_t first = r * 256, n = std::min<std::size_t>(256, rays.size() - first);
            if (!packets) {
                for (std::size_t i = first; i < first + n; ++i) {
                    hits[i] = bvh::intersect_closest(tree, rays[i]);
                }
                return;
            }
            packet::RayPacket packet;
            packet::PacketHits packet_hits;
            packet.clear();
            for (std::size_t i = 0; i < n; ++i) packet.set_ray(int(i), rays[first + i]);
            packet::intersect_closest(tree, packet, packet_hits);
            for (std::size_t i = 0; i < n; ++i) hits[first + i] = packet_hits.hit(int(i));
        });
        trace_ms += ms_since(start);
        hit_count += std::size_t(std::count_if(hits.begin(), hits.end(),
                                               [](const bvh::Hit& h) { return h.is_hit(); }));
        benchmark::ClobberMemory();
    }
    report(state, update_ms, trace_ms, rays.size(), hit_count,
           packets ? rays.size() * std::size_t(state.iterations()) : 0);
}

void ray_sets(benchmark::internal::Benchmark* b, bool ownership) {
    b->Unit(benchmark::kMillisecond)->UseRealTime()->MinWarmUpTime(0.5);
    for (int set = 0; set < 3; ++set) {
        if (ownership) {
            b->Args({set, 0})->Args({set, 1});
        } else {
            b->Args({set});
        }
    }
    b->ArgNames(ownership ? std::vector<std::string>{"rays", "borrow"}
                          : std::vector<std::string>{"rays"});
}

BENCHMARK(BM_StepApi)->Apply([](benchmark::internal::Benchmark* b) { ray_sets(b, true); });
BENCHMARK(BM_StepInternals)->Apply([](benchmark::internal::Benchmark* b) { ray_sets(b, false); });

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
