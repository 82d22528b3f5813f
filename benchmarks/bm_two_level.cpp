// Overhead of the two-level BVH on a static scene: packet primary rays of a 1024x1024 image
// (default camera for the bounds, packet::PinholeRays tiles) through the scene's TriangleBvh
// directly, through a TwoLevelBvh holding that tree as its one identity instance (what the
// renderer traces once every object is an instance), and as one transformed instance with the
// identity matrix (every packet copied and transformed lane by lane). oneTBB over tiles. Items
// are rays; the ratio of the first two is the cost of the top level for static scenes.

#include "bm_scenes.h"

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/camera.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/two_level_packet.h"

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

namespace dynrt::bench {
namespace {

constexpr int kWidth = 1024;
constexpr int kHeight = 1024;

enum class Mode { triangle_bvh, identity_instance, transformed_instance };

struct Setup {
    bvh::TriangleBvh accel;
    bvh::TwoLevelBvh identity_tlas, transformed_tlas;
    std::unique_ptr<packet::PinholeRays> pinhole;
};

const Setup& setup_for(const std::string& spec) {
    static std::map<std::string, std::unique_ptr<Setup>> cache;
    auto& slot = cache[spec];
    if (slot) return *slot;
    const SceneInput& input = scene_input(spec);
    slot = std::make_unique<Setup>();
    slot->accel = bvh::build_triangle_bvh(input.triangles, bvh::BuildConfig{});
    bvh::Instance instance;
    instance.blas = &slot->accel;
    bvh::build_top_level(slot->identity_tlas, {instance});
    instance.identity = false;
    bvh::build_top_level(slot->transformed_tlas, {instance});
    const Camera camera = default_camera(input.bounds);
    slot->pinhole = std::make_unique<packet::PinholeRays>(camera, kWidth, kHeight);
    return *slot;
}

void BM_PacketPrimary(benchmark::State& state, const std::string& spec, Mode mode) {
    const Setup& s = setup_for(spec);
    const packet::Tiling tiling(kWidth, kHeight);
    std::atomic<std::int64_t> hits{0};
    for (auto _ : state) {
        hits = 0;
        tbb::parallel_for(tbb::blocked_range<int>(0, tiling.count(), 8), [&](const tbb::blocked_range<int>& r) {
            auto rays = std::make_unique<packet::RayPacket>();
            auto plain = std::make_unique<packet::PacketHits>();
            auto inst = std::make_unique<packet::InstanceHits>();
            std::int64_t local = 0;
            for (int i = r.begin(); i < r.end(); ++i) {
                s.pinhole->fill_tile(tiling.tile(i), *rays);
                const packet::PacketHits* h = plain.get();
                if (mode == Mode::triangle_bvh) {
                    packet::intersect_closest(s.accel, *rays, *plain);
                } else {
                    packet::intersect_closest(mode == Mode::identity_instance ? s.identity_tlas : s.transformed_tlas,
                                              *rays, *inst);
                    h = &inst->hits;
                }
                for (int lane = 0; lane < packet::kPacketRays; ++lane) local += h->prim[lane] != bvh::kInvalidId;
            }
            hits += local;
        });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kWidth) * kHeight);
    state.counters["hit_fraction"] = static_cast<double>(hits.load()) / (double(kWidth) * kHeight);
}

#define DYNRT_TWO_LEVEL_BENCHMARK(name, mode)                                       \
    BENCHMARK_CAPTURE(BM_PacketPrimary, name, std::string("sphere:1000000"), mode) \
        ->MinWarmUpTime(0.3)                                                        \
        ->Unit(benchmark::kMillisecond)                                             \
        ->UseRealTime()

DYNRT_TWO_LEVEL_BENCHMARK(sphere_1M_triangle_bvh, Mode::triangle_bvh);
DYNRT_TWO_LEVEL_BENCHMARK(sphere_1M_identity_instance, Mode::identity_instance);
DYNRT_TWO_LEVEL_BENCHMARK(sphere_1M_transformed_identity_matrix, Mode::transformed_instance);

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
