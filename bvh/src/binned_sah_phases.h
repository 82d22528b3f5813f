#pragma once
// The binned SAH builder's two phases at one node, callable one at a time so benchmarks can
// time them apart (Wald 2007: bin the references and choose the split, then partition them in
// place). The builder runs the very same code (find_split and partition_refs in
// binned_sah_builder.cpp); these entry points only wrap it. For measurement, not for building.

#include "prim_ref.h"

#include "dynrt/bvh/aabb.h"

#include <cstddef>
#include <cstdint>

namespace dynrt::bvh::detail {

/// The split the binning phase chose for a node.
struct BinnedSplit {
    /// -1 when no bin boundary separates the references (the builder then splits at the median).
    int axis = -1;
    /// The left side is bins [0, bin] along `axis`.
    std::uint32_t bin = 0;
    /// A(left) n(left) + A(right) n(right), half areas; +inf when none was found.
    float cost = 0.0f;

    bool found() const { return axis >= 0; }
};

/// Binning phase of a node holding `refs[0, count)` (count >= 1): maps every reference's centre
/// to one of `bin_count` bins per axis over `center_box` (the bounds of the references'
/// centres; bin_count is clamped to [2, 64]), bounds and counts the bins, and sweeps them for
/// the cheapest split. Stores each reference's bins in its `bin_ids` for partition_node. With
/// `parallel`, a node of at least 16K references is binned in blocks by oneTBB tasks, as the
/// builder does near the root; otherwise on this thread, as in the builder's lower levels.
/// (The builder gives a node of n references min(4 + n/20, BuildConfig::bin_count) bins.)
BinnedSplit bin_node(BoxCenterRef* refs, std::size_t count, const Aabb& center_box,
                     std::uint32_t bin_count, bool parallel);

/// Partitioning phase: reorders `refs[0, count)` in place so the references in bins
/// [0, split.bin] along split.axis come first, on this thread as in the builder, and returns
/// how many they are. `refs` must hold the bin_ids of the bin_node call that returned `split`,
/// and `split.found()` must hold.
std::size_t partition_node(BoxCenterRef* refs, std::size_t count, const BinnedSplit& split);

}  // namespace dynrt::bvh::detail
