#pragma once
// The static group's tree layout chosen by a memory budget (UpdatePolicy::memory_budget,
// `--memory-budget`, issue 43): the fastest layout whose build is predicted to keep the
// process's resident memory within the budget.
//
// The layouts, fastest first, and what each adds to the resident set at its build's peak per
// static triangle (the binned SAH build's scratch with the tree it writes; the finished tree is
// smaller). Groups of 2^23 triangles or more with compact leaves are built with coarser binary
// leaves (lean_leaf_size_min below), so the compact layouts have two figures. Measured on
// sphere:N and soup:N (AMD EPYC, AVX-512; `dynrt render ... --leaves L --nodes M`, the peak
// minus what was resident before the build, as `--memory-budget` reports it), the larger of the
// two scenes, rounded up:
//
//                                   below 2^23 (measured at 4M)    from 2^23 (measured at 20M)
//   full leaves, float nodes         110 B  (sphere 73, soup 103)   110 B  (sphere 72, soup 101)
//   compact leaves, float nodes       60 B  (sphere 50, soup 57)     40 B  (sphere 39, soup 39)
//   compact leaves, quantized nodes   52 B  (sphere 43, soup 50)     40 B  (sphere 39, soup 39)
//
// From 2^23 triangles the two compact layouts peak alike (the peak is the binary build's, before
// any node is quantised), so the faster of them is chosen whenever either fits.
//
// Quantised nodes with full leaves are not on the ladder: they halve the finished nodes (8 B a
// triangle) but not the build's peak, which comes before them.
//
// The prediction is what is resident when the group is about to be built (the scene model,
// trees built before, the libraries) plus the layout's bytes per triangle. It is a prediction,
// not a bound: the report states it beside the measured peak. The objects outside the static
// group (whose trees may be refitted and keep full leaves and float nodes) are not counted.

#include <cstddef>
#include <cstdint>
#include <string>

namespace dynrt {

struct StaticGroupLayout {
    bool compact_leaves = false;
    bool quantized_nodes = false;

    /// "full leaves, float nodes", "compact leaves, quantized nodes", ...
    std::string name() const;
};

struct StaticLayoutChoice {
    StaticGroupLayout layout;
    /// The chosen layout's predicted peak (resident bytes).
    std::size_t predicted_peak = 0;
    /// Whether it is within the budget; when no layout is, the smallest is chosen.
    bool fits = true;
    /// Why, e.g. "budget 2.0 GB: predicted peak 1.6 GB (0.4 GB resident + 20000000 triangles x
    /// 60 B); full leaves, float nodes would peak at 2.6 GB".
    std::string why;
};

/// The smallest binary leaf (bvh::BuildConfig::leaf_size_min) a tree of `triangles` with
/// compact leaves (the static group's, or a moving object's, UpdatePolicy::
/// compact_moving_objects) is built with: the build's node arrays (binary nodes, then the
/// collapse's records of them) shrink with its leaves, and from a million triangles they are
/// its peak.
///   - Below 2^20 triangles, 1: the finest tree (the build peaks at tens of MB; leaves of four
///     cost 5% of MetalRoughSpheres' frame).
///   - From 2^20, 4: about half the nodes, which the collapse regroups into blocks of four
///     anyway.
///   - From 2^23, 8: half as many again. soup:20000000 then peaks at 94 B/tri instead of 103
///     (over the 100 of issue 43), and its frames and sphere:20000000's were no slower (AMD
///     EPYC, AVX-512: 612 against 671 ms and 307 against 314 ms at 1920x1080, medians of
///     three). At 4M triangles leaves of eight were 5% slower on the sphere, within the noise.
std::uint32_t lean_leaf_size_min(std::size_t triangles);

/// Predicted bytes the build of `layout` adds per static triangle at its peak, for a group of
/// `triangles` (the table above).
std::size_t layout_peak_bytes_per_triangle(const StaticGroupLayout& layout, std::size_t triangles);

/// The fastest layout of the ladder above whose predicted peak, `resident` + `triangles` x its
/// bytes per triangle, is at most `budget` bytes; the smallest layout (fits false) when none is.
StaticLayoutChoice choose_static_group_layout(std::size_t triangles, std::size_t resident, std::size_t budget);

}  // namespace dynrt
