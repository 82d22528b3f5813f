// Single-ray closest-hit tracing of a 1024x1024 primary-ray image (the engine's camera
// convention, default camera for the scene's bounds), in parallel over 16x16 tiles with oneTBB:
// dynrt's BVH traversal (the engine's default, the 8-wide tree; and, to compare the trees, the
// binary tree and wide trees of 4 and 8) against Embree 3's rtcIntersect1 over the very same
// rays. Plus a microbenchmark of the watertight ray/triangle test alone. Items are rays (or
// tests).

#include "bm_scenes.h"

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/watertight_intersector.h"
#include "dynrt/bvh/wide_bvh.h"
#include "dynrt/engine/camera.h"

#if DYNRT_HAVE_EMBREE
#include "bm_embree.h"
#include "dynrt/embree/embree_rays.h"
#endif

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

constexpr int kWidth = 1024;
constexpr int kHeight = 1024;
constexpr int kTile = 16;

/// The image's primary rays in row-major order, computed once per scene (not timed).
const std::vector<bvh::Ray>& camera_rays(const SceneInput& input) {
    static std::map<std::string, std::vector<bvh::Ray>> cache;
    std::vector<bvh::Ray>& rays = cache[input.spec];
    if (rays.empty()) {
        const CameraRays camera(default_camera(input.bounds), kWidth, kHeight);
        rays.reserve(static_cast<std::size_t>(kWidth) * kHeight);
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) rays.push_back(camera.ray(x, y));
        }
    }
    return rays;
}

const bvh::TriangleBvh& accel_for(const SceneInput& input) {
    static std::map<std::string, std::unique_ptr<bvh::TriangleBvh>> cache;
    auto& slot = cache[input.spec];
    if (!slot) {
        slot = std::make_unique<bvh::TriangleBvh>(
            bvh::build_triangle_bvh(input.triangles, bvh::BuildConfig{}));
    }
    return *slot;
}

/// Calls `trace(i)` for every pixel index, one oneTBB task per 16x16 tile.
template <class Trace>
void for_each_pixel_by_tile(const Trace& trace) {
    constexpr int tiles_x = kWidth / kTile;
    constexpr int tiles = tiles_x * (kHeight / kTile);
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
        for (int tile = r.begin(); tile < r.end(); ++tile) {
            const int x0 = (tile % tiles_x) * kTile;
            const int y0 = (tile / tiles_x) * kTile;
            for (int y = y0; y < y0 + kTile; ++y) {
                for (int x = x0; x < x0 + kTile; ++x) trace(static_cast<std::size_t>(y) * kWidth + x);
            }
        }
    });
}

double hit_fraction(const std::vector<float>& t) {
    std::size_t hits = 0;
    for (const float v : t) hits += v < std::numeric_limits<float>::infinity() ? 1 : 0;
    return static_cast<double>(hits) / static_cast<double>(t.size());
}

void BM_TraceClosestDynrt(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = camera_rays(input);
    const bvh::TriangleBvh& accel = accel_for(input);
    std::vector<float> t(rays.size());
    for (auto _ : state) {
        for_each_pixel_by_tile([&](std::size_t i) { t[i] = bvh::intersect_closest(accel, rays[i]).t; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
    state.counters["hit_fraction"] = hit_fraction(t);
    // Work per ray, from a separate counting pass.
    bvh::TraversalStats work;
    for (const bvh::Ray& ray : rays) bvh::intersect_closest(accel, ray, work);
    state.counters["nodes_per_ray"] = static_cast<double>(work.nodes_visited) / rays.size();
    state.counters["tris_per_ray"] = static_cast<double>(work.triangles_tested) / rays.size();
    state.counters["sah"] = bvh::sah_cost(accel.bvh, bvh::BuildConfig{}.sah_costs());
}

/// The binary tree's traversal, whatever the engine's default.
void BM_TraceClosestBinary(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = camera_rays(input);
    const bvh::TriangleBvh& accel = accel_for(input);
    std::vector<float> t(rays.size());
    for (auto _ : state) {
        for_each_pixel_by_tile(
            [&](std::size_t i) { t[i] = bvh::intersect_closest_binary(accel, rays[i]).t; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
    state.counters["hit_fraction"] = hit_fraction(t);
}

/// A wide tree of N children per node collapsed from the same binary tree, with its work per
/// ray and its bytes per triangle (nodes and blocks).
template <int N>
void BM_TraceClosestWide(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = camera_rays(input);
    const bvh::TriangleBvh& accel = accel_for(input);
    static std::map<std::string, std::unique_ptr<bvh::WideBvhOf<N>>> cache;
    auto& wide = cache[spec];
    if (!wide) {
        wide = std::make_unique<bvh::WideBvhOf<N>>(bvh::collapse_to_wide<N>(accel.bvh, accel.tris));
    }
    std::vector<float> t(rays.size());
    for (auto _ : state) {
        for_each_pixel_by_tile([&](std::size_t i) { t[i] = bvh::intersect_closest(*wide, rays[i]).t; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
    state.counters["hit_fraction"] = hit_fraction(t);
    bvh::WideTraversalStats work;
    for (const bvh::Ray& ray : rays) bvh::intersect_closest(*wide, ray, work);
    state.counters["nodes_per_ray"] = static_cast<double>(work.nodes_visited) / rays.size();
    state.counters["leaves_per_ray"] = static_cast<double>(work.leaves_visited) / rays.size();
    state.counters["tris_per_ray"] = static_cast<double>(work.triangles_tested) / rays.size();
    state.counters["bytes_per_tri"] =
        static_cast<double>(wide->bytes()) / static_cast<double>(input.triangles.size());
}
void BM_TraceClosestWide4(benchmark::State& state, const std::string& spec) {
    BM_TraceClosestWide<4>(state, spec);
}
void BM_TraceClosestWide8(benchmark::State& state, const std::string& spec) {
    BM_TraceClosestWide<8>(state, spec);
}

#if DYNRT_HAVE_EMBREE
void BM_TraceClosestEmbree(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = camera_rays(input);
    static std::map<std::string, RTCScene> scenes;
    RTCScene& scene = scenes[spec];
    if (scene == nullptr) {
        scene = make_embree_scene(input);
        rtcCommitScene(scene);
    }
    std::vector<float> t(rays.size());
    for (auto _ : state) {
        for_each_pixel_by_tile([&](std::size_t i) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            RTCRayHit rh = embree::to_rtc_ray_hit(rays[i]);
            rtcIntersect1(scene, &context, &rh);
            t[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar
                                                            : std::numeric_limits<float>::infinity();
        });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
    state.counters["hit_fraction"] = hit_fraction(t);
}
#endif

/// intersect_watertight alone: 64 rays against 1024 random triangles, about a third of the
/// tests hit. Items are ray/triangle tests.
void BM_WatertightIntersect(benchmark::State& state) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<bvh::Triangle> tris(1024);
    for (bvh::Triangle& tri : tris) {
        const glm::vec3 c(u(rng), u(rng), u(rng));
        tri = {c + 0.8f * glm::vec3(u(rng), u(rng), u(rng)), c + 0.8f * glm::vec3(u(rng), u(rng), u(rng)),
               c + 0.8f * glm::vec3(u(rng), u(rng), u(rng))};
    }
    std::vector<bvh::WatertightRay> rays;
    for (int i = 0; i < 64; ++i) {
        bvh::Ray r;
        r.org = glm::vec3(u(rng), u(rng), 5.0f);
        r.dir = glm::vec3(0.2f * u(rng), 0.2f * u(rng), -1.0f);
        rays.emplace_back(r);
    }
    std::int64_t hits = 0;
    for (auto _ : state) {
        for (const bvh::WatertightRay& ray : rays) {
            for (const bvh::Triangle& tri : tris) {
                bvh::Hit hit;
                hits += bvh::intersect_watertight(ray, tri, 0.0f, 100.0f, hit) ? 1 : 0;
                benchmark::DoNotOptimize(hit);
            }
        }
    }
    const std::int64_t tests = static_cast<std::int64_t>(rays.size() * tris.size());
    state.SetItemsProcessed(state.iterations() * tests);
    state.counters["hit_fraction"] =
        static_cast<double>(hits) / static_cast<double>(state.iterations() * tests);
}

#define DYNRT_TRACE_BENCHMARK(fn, name, spec)      \
    BENCHMARK_CAPTURE(fn, name, std::string(spec)) \
        ->MinWarmUpTime(0.3)                       \
        ->Unit(benchmark::kMillisecond)            \
        ->UseRealTime()

DYNRT_TRACE_BENCHMARK(BM_TraceClosestDynrt, sphere_1M, "sphere:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestDynrt, soup_1M, "soup:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestBinary, sphere_1M, "sphere:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestBinary, soup_1M, "soup:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestWide4, sphere_1M, "sphere:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestWide4, soup_1M, "soup:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestWide8, sphere_1M, "sphere:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestWide8, soup_1M, "soup:1000000");
#if DYNRT_HAVE_EMBREE
DYNRT_TRACE_BENCHMARK(BM_TraceClosestEmbree, sphere_1M, "sphere:1000000");
DYNRT_TRACE_BENCHMARK(BM_TraceClosestEmbree, soup_1M, "soup:1000000");
#endif
BENCHMARK(BM_WatertightIntersect);

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
