// Tracing of a 1024x1024 primary-ray image (the engine's camera convention, default camera for
// the scene's bounds), in parallel over 16x16 tiles with oneTBB:
//   - single rays: dynrt's BVH traversal (the engine's default, the 8-wide tree; and, to
//     compare the trees, the binary tree and wide trees of 4 and 8) against Embree 3's
//     rtcIntersect1 over the very same rays;
//   - packets: dynrt's 16x16 packets on the wide and the binary tree against Embree's
//     rtcIntersect16 / rtcOccluded16 over 4x4-pixel blocks with a coherent context (its
//     tutorials' arrangement), closest hits of the camera rays and any hits of shadow rays
//     from those hits toward a light above the camera. Both sides copy the same precomputed
//     rays into their packets.
// Plus a microbenchmark of the watertight ray/triangle test alone. Items are rays (or tests).

#include "bm_scenes.h"

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/watertight_intersector.h"
#include "dynrt/bvh/wide_bvh.h"
#include "dynrt/engine/camera.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"

#if DYNRT_HAVE_EMBREE
#include "bm_embree.h"
#include "dynrt/embree/embree_rays.h"
#endif

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <cstdint>
#include <glm/geometric.hpp>
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
        const packet::PinholeRays camera(default_camera(input.bounds), kWidth, kHeight);
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
    state.counters["sah"] = bvh::sah_cost(accel, bvh::BuildConfig{}.sah_costs());
}

/// The binary tree alone (BuildConfig::wide off), so that packets trace it.
const bvh::TriangleBvh& binary_accel_for(const SceneInput& input) {
    static std::map<std::string, std::unique_ptr<bvh::TriangleBvh>> cache;
    auto& slot = cache[input.spec];
    if (!slot) {
        bvh::BuildConfig config;
        config.wide = false;
        slot = std::make_unique<bvh::TriangleBvh>(bvh::build_triangle_bvh(input.triangles, config));
    }
    return *slot;
}

/// The binary tree's traversal, whatever the engine's default.
void BM_TraceClosestBinary(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = camera_rays(input);
    const bvh::TriangleBvh& accel = binary_accel_for(input);
    std::vector<float> t(rays.size());
    for (auto _ : state) {
        for_each_pixel_by_tile(
            [&](std::size_t i) { t[i] = bvh::intersect_closest(accel, rays[i]).t; });
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
    const bvh::TriangleBvh& accel = binary_accel_for(input);
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

// ---- Packets ----------------------------------------------------------------------------


/// Shadow rays of the camera rays' closest hits (on the binary tree) toward a point light above
/// the default camera: from the hit point to the light or, `from_light`, from the light to the
/// hit point (as the renderer casts them: one origin per packet), t in [1e-4, 1 - 1e-4].
/// Pixels without a hit get an empty segment (tmin > tmax), which every tracer reports
/// unoccluded at once.
const std::vector<bvh::Ray>& shadow_rays(const SceneInput& input, bool from_light) {
    static std::map<std::pair<std::string, bool>, std::vector<bvh::Ray>> cache;
    std::vector<bvh::Ray>& rays = cache[{input.spec, from_light}];
    if (rays.empty()) {
        const std::vector<bvh::Ray>& primary = camera_rays(input);
        const bvh::TriangleBvh& accel = binary_accel_for(input);
        const Camera camera = default_camera(input.bounds);
        const glm::vec3 light = camera.eye + glm::vec3(0.0f, 0.5f * glm::length(input.bounds.extent()), 0.0f);
        rays.resize(primary.size());
        tbb::parallel_for(std::size_t{0}, primary.size(), [&](std::size_t i) {
            const bvh::Hit hit = bvh::intersect_closest(accel, primary[i]);
            bvh::Ray r;
            const glm::vec3 point = hit.is_hit() ? primary[i].org + hit.t * primary[i].dir : primary[i].org;
            r.org = from_light ? light : point;
            r.dir = from_light ? point - light : light - point;
            r.tmin = 1e-4f;
            r.tmax = hit.is_hit() ? 1.0f - 1e-4f : 0.0f;
            rays[i] = r;
        });
    }
    return rays;
}

/// Items (rays) and the fraction of hits (closest hit: t finite) or of occluded rays (shadow
/// rays: t set to 0) in `t`, one value per pixel.
void set_packet_counters(benchmark::State& state, const std::vector<float>& t, bool shadow) {
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(t.size()));
    if (shadow) {
        std::size_t occluded = 0;
        for (const float v : t) occluded += v == 0.0f ? 1 : 0;
        state.counters["occluded_fraction"] = double(occluded) / double(t.size());
    } else {
        state.counters["hit_fraction"] = hit_fraction(t);
    }
}

/// Calls `trace(x0, y0)` for every 16x16 tile, one oneTBB task per tile.
template <class Trace>
void for_each_tile(const Trace& trace) {
    constexpr int tiles_x = kWidth / kTile;
    constexpr int tiles = tiles_x * (kHeight / kTile);
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
        for (int tile = r.begin(); tile < r.end(); ++tile) trace((tile % tiles_x) * kTile, (tile / tiles_x) * kTile);
    });
}

/// dynrt's 16x16 packets: closest hits of the camera rays (kShadow false) or any hits of the
/// shadow rays, on the wide tree or the binary one, with the work per ray of a counting pass.
template <bool kWide, bool kShadow>
void BM_Packet(benchmark::State& state, const std::string& spec,
               int single_ray_max = packet::PacketConfig{}.single_ray_max, bool from_light = false) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = kShadow ? shadow_rays(input, from_light) : camera_rays(input);
    const bvh::TriangleBvh& accel = kWide ? accel_for(input) : binary_accel_for(input);
    std::vector<float> t(rays.size());
    packet::PacketConfig config;  // the renderer's defaults
    config.single_ray_max = single_ray_max;
    const auto trace = [&](int x0, int y0, packet::PacketStats* stats) {
        thread_local auto packet = std::make_unique<packet::RayPacket>();
        thread_local auto hits = std::make_unique<packet::PacketHits>();
        const packet::Tile tile{x0, y0, x0 + kTile, y0 + kTile};
        packet::fill_tile(tile, [&](int x, int y) { return rays[std::size_t(y) * kWidth + std::size_t(x)]; }, *packet);
        if constexpr (kShadow) {
            for (int lane = 0; lane < packet::kPacketRays; ++lane) {
                if (packet->tmin[lane] > packet->tmax[lane]) packet->active.reset(lane);
            }
            packet::LaneMask occluded;
            packet::intersect_any(accel, *packet, occluded, config, stats);
            for (int lane = 0; lane < packet::kPacketRays; ++lane) {
                const packet::LanePixel p = packet::tile_pixel(tile, lane);
                t[std::size_t(p.y) * kWidth + std::size_t(p.x)] = occluded.test(lane) ? 0.0f : 1.0f;
            }
        } else {
            packet::intersect_closest(accel, *packet, *hits, config, stats);
            for (int lane = 0; lane < packet::kPacketRays; ++lane) {
                const packet::LanePixel p = packet::tile_pixel(tile, lane);
                t[std::size_t(p.y) * kWidth + std::size_t(p.x)] = hits->t[lane];
            }
        }
    };
    for (auto _ : state) {
        for_each_tile([&](int x0, int y0) { trace(x0, y0, nullptr); });
        benchmark::ClobberMemory();
    }
    set_packet_counters(state, t, kShadow);
    packet::PacketStats work;
    for (int y0 = 0; y0 < kHeight; y0 += kTile) {
        for (int x0 = 0; x0 < kWidth; x0 += kTile) trace(x0, y0, &work);
    }
    const double n = double(rays.size());
    state.counters["nodes_per_ray"] = double(work.nodes_visited) / n;
    state.counters["box_tests_per_ray"] = double(work.ray_box_tests) / n;
    state.counters["tris_per_ray"] = double(work.ray_triangle_tests) / n;
}
/// The switch from packet to single-ray traversal (PacketConfig::single_ray_max) swept on the
/// wide tree: the argument is the most rays, hitting a node within at most two SIMD steps,
/// that continue below it one by one (0: never switch; the default is 2).
void BM_PacketSwitchClosest(benchmark::State& state, const std::string& spec) {
    BM_Packet<true, false>(state, spec, int(state.range(0)));
}
void BM_PacketSwitchOccluded(benchmark::State& state, const std::string& spec) {
    BM_Packet<true, true>(state, spec, int(state.range(0)));
}
void BM_PacketClosestWide(benchmark::State& state, const std::string& spec) {
    BM_Packet<true, false>(state, spec);
}
void BM_PacketClosestBinary(benchmark::State& state, const std::string& spec) {
    BM_Packet<false, false>(state, spec);
}
void BM_PacketOccludedWide(benchmark::State& state, const std::string& spec) {
    BM_Packet<true, true>(state, spec);
}
void BM_PacketOccludedWideFromLight(benchmark::State& state, const std::string& spec) {
    BM_Packet<true, true>(state, spec, packet::PacketConfig{}.single_ray_max, true);
}
void BM_PacketOccludedBinary(benchmark::State& state, const std::string& spec) {
    BM_Packet<false, true>(state, spec);
}

#if DYNRT_HAVE_EMBREE
/// Embree's rtcIntersect16 (kShadow false) or rtcOccluded16 over the tile's 4x4-pixel blocks,
/// coherent context, denormals flushed as Embree asks, HIGH build quality (its best trace).
template <bool kShadow>
void BM_PacketEmbree16(benchmark::State& state, const std::string& spec, bool from_light = false) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Ray>& rays = kShadow ? shadow_rays(input, from_light) : camera_rays(input);
    static std::map<std::string, RTCScene> scenes;
    RTCScene& scene = scenes[spec];
    if (scene == nullptr) {
        embree::EmbreeFloatMode mode;
        scene = make_embree_scene(input, false, nullptr, RTC_BUILD_QUALITY_HIGH);
        rtcCommitScene(scene);
    }
    std::vector<float> t(rays.size());
    for (auto _ : state) {
        for_each_tile([&](int x0, int y0) {
            embree::EmbreeFloatMode mode;
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            alignas(64) int valid[16];
            for (int by = y0; by < y0 + kTile; by += 4) {
                for (int bx = x0; bx < x0 + kTile; bx += 4) {
                    alignas(64) RTCRayHit16 rh;
                    for (int k = 0; k < 16; ++k) {
                        const bvh::Ray& r = rays[std::size_t(by + k / 4) * kWidth + std::size_t(bx + k % 4)];
                        embree::set_rtc_ray_hit16(rh, k, r, 0);
                        valid[k] = r.tmin <= r.tmax ? -1 : 0;
                    }
                    if constexpr (kShadow) {
                        rtcOccluded16(valid, scene, &context, &rh.ray);
                    } else {
                        rtcIntersect16(valid, scene, &context, &rh);
                    }
                    for (int k = 0; k < 16; ++k) {
                        const std::size_t i = std::size_t(by + k / 4) * kWidth + std::size_t(bx + k % 4);
                        if constexpr (kShadow) {
                            t[i] = valid[k] != 0 && rh.ray.tfar[k] < 0.0f ? 0.0f : 1.0f;
                        } else {
                            t[i] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID
                                       ? rh.ray.tfar[k]
                                       : std::numeric_limits<float>::infinity();
                        }
                    }
                }
            }
        });
        benchmark::ClobberMemory();
    }
    set_packet_counters(state, t, kShadow);
}
void BM_PacketClosestEmbree16(benchmark::State& state, const std::string& spec) {
    BM_PacketEmbree16<false>(state, spec);
}
void BM_PacketOccludedEmbree16(benchmark::State& state, const std::string& spec) {
    BM_PacketEmbree16<true>(state, spec);
}
void BM_PacketOccludedEmbree16FromLight(benchmark::State& state, const std::string& spec) {
    BM_PacketEmbree16<true>(state, spec, true);
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

// Every tracing benchmark on both 1M-triangle scenes.
#define DYNRT_TRACE_BOTH_SCENES(fn)                          \
    DYNRT_TRACE_BENCHMARK(fn, sphere_1M, "sphere:1000000"); \
    DYNRT_TRACE_BENCHMARK(fn, soup_1M, "soup:1000000")

DYNRT_TRACE_BOTH_SCENES(BM_TraceClosestDynrt);
DYNRT_TRACE_BOTH_SCENES(BM_TraceClosestBinary);
DYNRT_TRACE_BOTH_SCENES(BM_TraceClosestWide4);
DYNRT_TRACE_BOTH_SCENES(BM_TraceClosestWide8);
DYNRT_TRACE_BOTH_SCENES(BM_PacketClosestWide);
DYNRT_TRACE_BOTH_SCENES(BM_PacketClosestBinary);
DYNRT_TRACE_BOTH_SCENES(BM_PacketOccludedWide);
DYNRT_TRACE_BOTH_SCENES(BM_PacketOccludedWideFromLight);
DYNRT_TRACE_BOTH_SCENES(BM_PacketOccludedBinary);
#define DYNRT_SWITCH_BENCHMARK(fn, name, spec) \
    DYNRT_TRACE_BENCHMARK(fn, name, spec)->Arg(0)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Arg(16)
DYNRT_SWITCH_BENCHMARK(BM_PacketSwitchClosest, sphere_1M, "sphere:1000000");
DYNRT_SWITCH_BENCHMARK(BM_PacketSwitchClosest, soup_1M, "soup:1000000");
DYNRT_SWITCH_BENCHMARK(BM_PacketSwitchOccluded, sphere_1M, "sphere:1000000");
DYNRT_SWITCH_BENCHMARK(BM_PacketSwitchOccluded, soup_1M, "soup:1000000");
#if DYNRT_HAVE_EMBREE
DYNRT_TRACE_BOTH_SCENES(BM_TraceClosestEmbree);
DYNRT_TRACE_BOTH_SCENES(BM_PacketClosestEmbree16);
DYNRT_TRACE_BOTH_SCENES(BM_PacketOccludedEmbree16);
DYNRT_TRACE_BOTH_SCENES(BM_PacketOccludedEmbree16FromLight);
#endif
BENCHMARK(BM_WatertightIntersect);

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
