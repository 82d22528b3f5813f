// The binned SAH builder's two phases (Wald 2007), timed apart on the scenes through
// the builder's own code (bvh/src/binned_sah_phases.h): binning (centres to bins, bin bounds
// and counts, the sweep for the cheapest split) and the in-place partition by that split.
// Two node sizes: the root, all references (memory-bound; binned in parallel, partitioned on
// one thread, as the builder does), and a node of 2048 references (cache-resident; the size at
// which the builder's serial subtrees start). Items are references, i.e. triangles.

#include "bm_scenes.h"

#include "binned_sah_phases.h"
#include "prim_ref.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

/// Bins per axis the builder gives a node of this many references at the default bin_count
/// (Embree's rule, min(4 + n/20, 16)).
std::uint32_t builder_bins(std::size_t n) {
    return static_cast<std::uint32_t>(std::min<std::size_t>(4 + n / 20, 16));
}

/// A node's references, made from triangles as build_triangle_bvh makes them (degenerate
/// ones skipped, binned by the centre of the box), with the bounds of their centres.
struct NodeRefs {
    std::vector<bvh::detail::BoxCenterRef> refs;
    bvh::Aabb center_box;
};

/// The references of the first `count` triangles of `spec` (all of them for count 0).
const NodeRefs& node_refs(const std::string& spec, std::size_t count) {
    static std::map<std::pair<std::string, std::size_t>, std::unique_ptr<NodeRefs>> cache;
    auto& slot = cache[{spec, count}];
    if (slot) return *slot;
    const std::vector<bvh::Triangle>& tris = scene_input(spec).triangles;
    const std::size_t n = count == 0 ? tris.size() : std::min(count, tris.size());
    auto node = std::make_unique<NodeRefs>();
    for (std::size_t i = 0; i < n; ++i) {
        if (bvh::is_degenerate(tris[i])) continue;
        const bvh::Aabb box = tris[i].bounds();
        node->refs.push_back({box.lo, static_cast<std::uint32_t>(i), box.hi, 0});
        node->center_box.extend(box.center());  // (lo + hi) * 0.5, the builder's centre
    }
    slot = std::move(node);
    return *slot;
}

/// Binning phase: every iteration bins the same references (binning only rewrites their
/// scratch bin ids) and picks the split. `parallel`: oneTBB blocks as the builder does for
/// nodes of 16K references or more; otherwise one thread.
void BM_Binning(benchmark::State& state, const std::string& spec, std::size_t count,
                bool parallel) {
    std::vector<bvh::detail::BoxCenterRef> refs = node_refs(spec, count).refs;
    const bvh::Aabb center_box = node_refs(spec, count).center_box;
    const std::uint32_t bins = builder_bins(refs.size());
    bvh::detail::BinnedSplit split;
    for (auto _ : state) {
        split = bvh::detail::bin_node(refs.data(), refs.size(), center_box, bins, parallel);
        benchmark::DoNotOptimize(split);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(refs.size()));
    state.counters["bins"] = bins;
    state.counters["split_axis"] = split.axis;
}

/// Partitioning phase: the references binned once (untimed), then each iteration restores
/// their order (untimed) and partitions them by the split binning chose, on one thread.
void BM_Partitioning(benchmark::State& state, const std::string& spec, std::size_t count) {
    std::vector<bvh::detail::BoxCenterRef> binned = node_refs(spec, count).refs;
    const bvh::detail::BinnedSplit split =
        bvh::detail::bin_node(binned.data(), binned.size(), node_refs(spec, count).center_box,
                              builder_bins(binned.size()), true);
    if (!split.found()) {
        state.SkipWithError("no binned split");
        return;
    }
    std::vector<bvh::detail::BoxCenterRef> work(binned.size());
    std::size_t left = 0;
    for (auto _ : state) {
        std::copy(binned.begin(), binned.end(), work.begin());
        const auto start = std::chrono::steady_clock::now();
        left = bvh::detail::partition_node(work.data(), work.size(), split);
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(work.size()));
    state.counters["left_fraction"] = static_cast<double>(left) / static_cast<double>(work.size());
}

constexpr std::size_t kRoot = 0;
constexpr std::size_t kSmallNode = 2048;

BENCHMARK_CAPTURE(BM_Binning, sphere_1M_root, std::string("sphere:1000000"), kRoot, true)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Binning, soup_1M_root, std::string("soup:1000000"), kRoot, true)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Binning, sphere_1M_root_1thread, std::string("sphere:1000000"), kRoot, false)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Binning, soup_1M_root_1thread, std::string("soup:1000000"), kRoot, false)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Binning, sphere_1M_node2048, std::string("sphere:1000000"), kSmallNode, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Binning, soup_1M_node2048, std::string("soup:1000000"), kSmallNode, false)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Partitioning, sphere_1M_root, std::string("sphere:1000000"), kRoot)
    ->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Partitioning, soup_1M_root, std::string("soup:1000000"), kRoot)
    ->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Partitioning, sphere_1M_node2048, std::string("sphere:1000000"), kSmallNode)
    ->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Partitioning, soup_1M_node2048, std::string("soup:1000000"), kSmallNode)
    ->UseManualTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
