// Refit (Wald, Boulos and Shirley 2007) of the triangle BVH of the scenes after every
// vertex moved, against Embree 3's refit (RTC_BUILD_QUALITY_REFIT geometries in a dynamic
// scene). The tree is built once over frame 0; the iterations refit it to a waved copy of the
// scene and back, alternately, so every refit moves every vertex. Items are triangles.

#include "bm_scenes.h"

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"

#if DYNRT_HAVE_EMBREE
#include "bm_embree.h"
#endif

#include <benchmark/benchmark.h>
#include <oneapi/tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

/// A wave across the scene: each vertex rises by up to 2% of the scene's size, by a sine of
/// its x. A pure function of the position, so shared vertices stay shared.
struct Wave {
    bvh::Aabb bounds;

    glm::vec3 operator()(const glm::vec3& p) const {
        const glm::vec3 e = bounds.extent();
        const float phase = 6.2831853f * 3.0f * (p.x - bounds.lo.x) / e.x;
        return p + glm::vec3(0.0f, 0.02f * e.y * std::sin(phase), 0.0f);
    }
};

/// The scene's second frame, waved, in both of bm_scenes.h's forms.
struct WavedScene {
    std::vector<bvh::Triangle> triangles;
    std::vector<std::vector<float>> positions;
};

const WavedScene& waved(const SceneInput& input) {
    static std::map<std::string, std::unique_ptr<WavedScene>> cache;
    auto& slot = cache[input.spec];
    if (slot) return *slot;
    const Wave wave{input.bounds};
    auto out = std::make_unique<WavedScene>();
    for (const bvh::Triangle& t : input.triangles) {
        out->triangles.push_back({wave(t.v0), wave(t.v1), wave(t.v2)});
    }
    out->positions = input.positions;
    for (std::vector<float>& p : out->positions) {
        for (std::size_t v = 0; v + 2 < p.size(); v += 3) {  // the last float is padding
            const glm::vec3 q = wave(glm::vec3(p[v], p[v + 1], p[v + 2]));
            p[v] = q.x;
            p[v + 1] = q.y;
            p[v + 2] = q.z;
        }
    }
    slot = std::move(out);
    return *slot;
}

/// The triangles' corners, three a triangle in order: a soup's vertices, read in place
/// (bvh::TriangleSource::soup) as the engine reads a moving soup's.
std::vector<glm::vec3> corners_of(const std::vector<bvh::Triangle>& tris) {
    std::vector<glm::vec3> corners;
    corners.reserve(3 * tris.size());
    for (const bvh::Triangle& t : tris) corners.insert(corners.end(), {t.v0, t.v1, t.v2});
    return corners;
}

/// `refit` of a TriangleBvh: of its wide tree (blocks and node boxes), or with `wide` false of
/// its binary tree (leaf-order triangle copies and node boxes). `threads` 0 runs
/// on the default arena (the whole machine), otherwise in an arena of that many threads. With
/// `soup`, the triangles are read as a soup's corners rather than as triangles (the same bytes
/// in the same order, so the difference is the reading code's).
void BM_RefitTriangleBvh(benchmark::State& state, const std::string& spec, int threads,
                         bool wide = true, bool soup = false) {
    const SceneInput& input = scene_input(spec);
    const std::vector<bvh::Triangle>* frames[2] = {&waved(input).triangles, &input.triangles};
    std::vector<glm::vec3> corners[2];
    bvh::TriangleSource sources[2] = {*frames[0], *frames[1]};
    if (soup) {
        for (int f = 0; f < 2; ++f) {
            corners[f] = corners_of(*frames[f]);
            sources[f] = bvh::TriangleSource::soup(corners[f]);
        }
    }
    bvh::BuildConfig config;
    config.wide = wide;
    bvh::TriangleBvh accel = bvh::build_triangle_bvh(input.triangles, config);
    const double built_sah = bvh::sah_cost(accel, config.sah_costs());
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    std::size_t frame = 0;
    double waved_sah = 0.0;
    for (auto _ : state) {
        const bvh::RefitResult result =
            arena.execute([&] { return bvh::refit(accel, sources[frame], config.sah_costs()); });
        if (frame == 0) waved_sah = result.sah_cost;
        frame ^= 1;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.triangles.size()));
    state.counters["sah_built"] = built_sah;
    state.counters["sah_waved"] = waved_sah;
}

/// `refit` of a plain Bvh from per-primitive boxes (the top level over objects will use it).
void BM_RefitBvhFromBoxes(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    std::vector<bvh::Aabb> boxes[2];
    std::vector<glm::vec3> centers;
    for (const bvh::Triangle& t : input.triangles) {
        boxes[1].push_back(t.bounds());
        centers.push_back(boxes[1].back().center());
    }
    for (const bvh::Triangle& t : waved(input).triangles) boxes[0].push_back(t.bounds());
    const bvh::BuildConfig config;
    bvh::Bvh tree = bvh::build_binned_sah(boxes[1], centers, config);
    std::size_t frame = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(bvh::refit(tree, boxes[frame], config.sah_costs()));
        frame ^= 1;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(boxes[1].size()));
}

#if DYNRT_HAVE_EMBREE
/// Embree's refit: the vertices are copied into the shared buffer and marked updated
/// (untimed), then rtcCommitScene (timed) refits.
void BM_RefitEmbree(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    const std::vector<std::vector<float>>* frames[2] = {&waved(input).positions, &input.positions};
    std::vector<std::vector<float>> shared = input.positions;
    RTCScene scene = make_embree_scene(input, true, &shared);
    rtcCommitScene(scene);
    std::size_t frame = 0;
    for (auto _ : state) {
        for (std::size_t o = 0; o < shared.size(); ++o) {
            shared[o] = (*frames[frame])[o];  // same size: no reallocation
            RTCGeometry geometry = rtcGetGeometry(scene, static_cast<unsigned>(o));
            rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
            rtcCommitGeometry(geometry);
        }
        const auto start = std::chrono::steady_clock::now();
        rtcCommitScene(scene);
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        frame ^= 1;
    }
    rtcReleaseScene(scene);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.triangles.size()));
}
#endif

// Wall-clock time: the refits run on several threads. Embree's figure is timed by hand around
// rtcCommitScene alone.
#define DYNRT_REFIT_BENCHMARK(fn, name, ...)   \
    BENCHMARK_CAPTURE(fn, name, __VA_ARGS__)   \
        ->MinWarmUpTime(0.5)                   \
        ->Unit(benchmark::kMillisecond)

const std::string kSphere = "sphere:1000000";
const std::string kSoup = "soup:1000000";

DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, sphere_1M, kSphere, 0)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, soup_1M, kSoup, 0)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, soup_1M_in_place, kSoup, 0, true, true)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, sphere_1M_binary_only, kSphere, 0, false)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, soup_1M_binary_only, kSoup, 0, false)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, sphere_1M_1thread, kSphere, 1)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitTriangleBvh, soup_1M_1thread, kSoup, 1)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitBvhFromBoxes, sphere_1M, kSphere)->UseRealTime();
DYNRT_REFIT_BENCHMARK(BM_RefitBvhFromBoxes, soup_1M, kSoup)->UseRealTime();
#if DYNRT_HAVE_EMBREE
DYNRT_REFIT_BENCHMARK(BM_RefitEmbree, sphere_1M, kSphere)->UseManualTime();
DYNRT_REFIT_BENCHMARK(BM_RefitEmbree, soup_1M, kSoup)->UseManualTime();
#endif

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
