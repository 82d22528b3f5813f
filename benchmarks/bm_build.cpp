// Build throughput of dynrt's binned SAH triangle BVH (Wald 2007) against Embree 3 at
// RTC_BUILD_QUALITY_MEDIUM, and of dynrt's Morton builder (morton_builder.h) against Embree's
// at RTC_BUILD_QUALITY_LOW (its Morton builder, what it rebuilds dynamic scenes with), on the
// procedural scenes of the issues, both on their default thread count (the whole machine).
// Items are triangles; counters give the tree's quality.

#include "bm_scenes.h"

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/wide_bvh.h"

#if DYNRT_HAVE_EMBREE
#include "bm_embree.h"
#endif

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The shape of `tree`, a Bvh or a TriangleBvh (then of the tree it holds, the wide one by
/// default: its SAH is on the wide scale, not comparable with a binary tree's).
template <class Tree>
void report_tree(benchmark::State& state, const Tree& tree, const bvh::BuildConfig& config) {
    const bvh::BvhStats stats = bvh::compute_stats(tree);
    state.counters["sah"] = bvh::sah_cost(tree, config.sah_costs());
    state.counters["nodes"] = static_cast<double>(stats.nodes);
    state.counters["leaves"] = static_cast<double>(stats.leaves);
    state.counters["leaf_mean"] = stats.leaf_prims_mean;
    state.counters["depth"] = stats.depth;
}

/// Times build_triangle_bvh with `config`, each build into fresh storage (the previous tree
/// is freed outside the timed region) or, with `recycled`, into the previous iteration's tree,
/// as the engine rebuilds an object every frame: the same work on storage already faulted in.
/// The triangles are the scene's gathered ones, or `from` when given.
void time_builds(benchmark::State& state, const std::string& spec, const bvh::BuildConfig& config,
                 bool recycled, const bvh::TriangleSource* from = nullptr) {
    const SceneInput& input = scene_input(spec);
    const bvh::TriangleSource gathered(input.triangles);
    const bvh::TriangleSource& source = from != nullptr ? *from : gathered;
    bvh::TriangleBvh accel;
    for (auto _ : state) {
        const Clock::time_point start = Clock::now();
        if (recycled) {
            accel = bvh::build_triangle_bvh(source, config, std::move(accel));
            state.SetIterationTime(seconds_since(start));
        } else {
            bvh::TriangleBvh built = bvh::build_triangle_bvh(source, config);
            state.SetIterationTime(seconds_since(start));
            accel = std::move(built);
        }
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(source.size()));
    report_tree(state, accel, config);
    state.counters["bytes_per_tri"] =
        static_cast<double>(accel.wide.bytes() + accel.bvh.nodes.size() * sizeof(bvh::BvhNode) +
                            accel.bvh.prim_ids.size() * 4 + accel.tris.size() * sizeof(bvh::Triangle)) /
        static_cast<double>(source.size());
}

bvh::BuildConfig config_of(bvh::BuildMethod method, bool wide = true) {
    bvh::BuildConfig config;
    config.method = method;
    config.wide = wide;
    return config;
}

/// build_triangle_bvh: degenerate filtering, references, tree, triangles in leaf order; the
/// complete traceable structure, like Embree's commit.
void BM_BuildTriangleBvh(benchmark::State& state, const std::string& spec) {
    time_builds(state, spec, config_of(bvh::BuildMethod::binned_sah), false);
}

/// The same from the scene's vertices through their index triples, as the engine builds its
/// static objects' tree (bvh::TriangleSource over indexed meshes): no gathered copy of the
/// triangles, at the price of reading each triangle's corners through its indices.
void BM_BuildTriangleBvhIndexed(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    std::vector<std::vector<glm::vec3>> positions(input.positions.size());
    std::vector<std::vector<glm::uvec3>> triangles(input.indices.size());
    std::vector<bvh::TriangleSource::IndexedMesh> meshes;
    for (std::size_t k = 0; k < positions.size(); ++k) {
        const std::vector<float>& xyzw = input.positions[k];  // x, y, z per vertex, then one float of padding
        for (std::size_t v = 0; v + 3 < xyzw.size(); v += 3) positions[k].emplace_back(xyzw[v], xyzw[v + 1], xyzw[v + 2]);
        const std::vector<std::uint32_t>& ids = input.indices[k];
        for (std::size_t t = 0; t + 2 < ids.size(); t += 3) triangles[k].emplace_back(ids[t], ids[t + 1], ids[t + 2]);
        meshes.push_back(bvh::TriangleSource::IndexedMesh{positions[k], triangles[k]});
    }
    const bvh::TriangleSource source(meshes);
    time_builds(state, spec, config_of(bvh::BuildMethod::binned_sah), false, &source);
}

/// The same into the previous iteration's tree.
void BM_BuildTriangleBvhRecycled(benchmark::State& state, const std::string& spec) {
    time_builds(state, spec, config_of(bvh::BuildMethod::binned_sah), true);
}

/// The Morton builder into fresh storage.
void BM_BuildMorton(benchmark::State& state, const std::string& spec) {
    time_builds(state, spec, config_of(bvh::BuildMethod::morton), false);
}

/// The Morton builder into the previous iteration's tree: the engine's fast rebuild of an
/// object every frame. Compare with BM_BuildEmbreeLowRecommit.
void BM_BuildMortonRecycled(benchmark::State& state, const std::string& spec) {
    time_builds(state, spec, config_of(bvh::BuildMethod::morton), true);
}

/// The Morton builder's binary tree alone (no collapse), recycled.
void BM_BuildMortonBinaryOnly(benchmark::State& state, const std::string& spec) {
    time_builds(state, spec, config_of(bvh::BuildMethod::morton, false), true);
}

/// build_triangle_bvh without the wide tree (BuildConfig::wide off): what the collapse adds is
/// the difference to BM_BuildTriangleBvh.
void BM_BuildTriangleBvhBinaryOnly(benchmark::State& state, const std::string& spec) {
    time_builds(state, spec, config_of(bvh::BuildMethod::binned_sah, false), false);
}

/// collapse_to_wide alone, of a binary tree built once, at width N, into fresh storage; with
/// the wide tree's shape as counters.
template <int N>
void BM_CollapseToWide(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    bvh::BuildConfig config;
    config.wide = false;
    const bvh::TriangleBvh accel = bvh::build_triangle_bvh(input.triangles, config);
    bvh::WideBvhOf<N> wide;
    for (auto _ : state) {
        const Clock::time_point start = Clock::now();
        bvh::WideBvhOf<N> built = bvh::collapse_to_wide<N>(accel.bvh, accel.tris);
        state.SetIterationTime(seconds_since(start));
        wide = std::move(built);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.triangles.size()));
    const bvh::WideStats stats = bvh::compute_stats(wide);
    state.counters["nodes"] = static_cast<double>(stats.nodes);
    state.counters["leaves"] = static_cast<double>(stats.leaves);
    state.counters["children"] = stats.children_mean;
    state.counters["block_fill"] = stats.block_fill;
    state.counters["bytes_per_tri"] =
        static_cast<double>(stats.bytes) / static_cast<double>(input.triangles.size());
}

void BM_CollapseToWide8(benchmark::State& state, const std::string& spec) {
    BM_CollapseToWide<8>(state, spec);
}
void BM_CollapseToWide4(benchmark::State& state, const std::string& spec) {
    BM_CollapseToWide<4>(state, spec);
}

/// build_binned_sah over precomputed boxes and centres: binning and partitioning alone.
void BM_BuildBinnedSahFromBoxes(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    std::vector<bvh::Aabb> boxes;
    std::vector<glm::vec3> centers;
    for (const bvh::Triangle& t : input.triangles) {
        boxes.push_back(t.bounds());
        centers.push_back(boxes.back().center());
    }
    const bvh::BuildConfig config;
    bvh::Bvh tree;
    for (auto _ : state) {
        const Clock::time_point start = Clock::now();
        bvh::Bvh built = bvh::build_binned_sah(boxes, centers, config);
        state.SetIterationTime(seconds_since(start));
        tree = std::move(built);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(boxes.size()));
    report_tree(state, tree, config);
}

#if DYNRT_HAVE_EMBREE
/// rtcCommitScene of a fresh scene over shared buffers (scene setup and release not timed).
void BM_BuildEmbreeMedium(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    for (auto _ : state) {
        RTCScene scene = make_embree_scene(input);
        const Clock::time_point start = Clock::now();
        rtcCommitScene(scene);
        state.SetIterationTime(seconds_since(start));
        rtcReleaseScene(scene);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.triangles.size()));
}

/// rtcCommitScene of a fresh scene at RTC_BUILD_QUALITY_LOW (Embree's Morton builder).
void BM_BuildEmbreeLow(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    for (auto _ : state) {
        RTCScene scene = make_embree_scene(input, false, nullptr, RTC_BUILD_QUALITY_LOW);
        const Clock::time_point start = Clock::now();
        rtcCommitScene(scene);
        state.SetIterationTime(seconds_since(start));
        rtcReleaseScene(scene);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.triangles.size()));
}

/// Embree rebuilding the same LOW-quality scene every frame, as an animation loop does: the
/// vertex buffers marked updated, the geometries and the scene committed again (the commits
/// timed). Embree reuses its scene's storage, as BM_BuildMortonRecycled does.
void BM_BuildEmbreeLowRecommit(benchmark::State& state, const std::string& spec) {
    const SceneInput& input = scene_input(spec);
    RTCScene scene = make_embree_scene(input, false, nullptr, RTC_BUILD_QUALITY_LOW);
    rtcCommitScene(scene);
    for (auto _ : state) {
        const Clock::time_point start = Clock::now();
        for (unsigned id = 0; id < input.positions.size(); ++id) {
            RTCGeometry geometry = rtcGetGeometry(scene, id);
            rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
            rtcCommitGeometry(geometry);
        }
        rtcCommitScene(scene);
        state.SetIterationTime(seconds_since(start));
    }
    rtcReleaseScene(scene);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.triangles.size()));
}
#endif

// Two seconds of untimed builds first: the first few builds of a process pay for faulting in
// fresh memory while the allocator and the kernel's huge pages settle (measured: the first five
// dynrt builds of 1M triangles take up to twice the steady time). An engine rebuilding every
// frame lives in the steady state, which is what these figures report.
#define DYNRT_BUILD_BENCHMARK(fn, name, spec)                                              \
    BENCHMARK_CAPTURE(fn, name, std::string(spec))                                         \
        ->UseManualTime()                                                                  \
        ->MinWarmUpTime(2.0)                                                               \
        ->Unit(benchmark::kMillisecond)

DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvh, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvh, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvhIndexed, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvhIndexed, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvhRecycled, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvhRecycled, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildMorton, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildMorton, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildMortonRecycled, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildMortonRecycled, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildMortonBinaryOnly, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildMortonBinaryOnly, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvhBinaryOnly, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildTriangleBvhBinaryOnly, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_CollapseToWide8, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_CollapseToWide8, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_CollapseToWide4, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_CollapseToWide4, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildBinnedSahFromBoxes, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildBinnedSahFromBoxes, soup_1M, "soup:1000000");
#if DYNRT_HAVE_EMBREE
DYNRT_BUILD_BENCHMARK(BM_BuildEmbreeMedium, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildEmbreeMedium, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildEmbreeLow, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildEmbreeLow, soup_1M, "soup:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildEmbreeLowRecommit, sphere_1M, "sphere:1000000");
DYNRT_BUILD_BENCHMARK(BM_BuildEmbreeLowRecommit, soup_1M, "soup:1000000");
#endif

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
