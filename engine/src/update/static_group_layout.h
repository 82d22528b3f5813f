#pragma once
// The static group's tree layout chosen by a memory budget (UpdatePolicy::memory_budget,
// `--memory-budget`, issue 43): the fastest layout whose build is predicted to keep the
// process's resident memory within the budget.
//
// The layouts, fastest first, and what each adds to the resident set at its build's peak per
// static triangle (the binned SAH build's scratch with the tree it writes; the finished tree is
// smaller). Measured on sphere:N and soup:N at N = 4M and 20M (Intel Xeon, AVX-512; `dynrt
// render ... --leaves L --nodes M`, the peak minus the scene model and a fixed ~140 MB of
// libraries and buffers, as the slope between the two sizes), the larger of the two scenes,
// rounded up:
//
//   full leaves, float nodes            110 B  (sphere 73, soup 106)
//   compact leaves, float nodes          60 B  (sphere 51, soup 56)
//   compact leaves, quantized nodes      52 B  (sphere 45, soup 49)
//
// Quantised nodes with full leaves are not on the ladder: they halve the finished nodes (8 B a
// triangle) but not the build's peak, which comes before them.
//
// The prediction is what is resident when the group is about to be built (the scene model,
// trees built before, the libraries) plus the layout's bytes per triangle. It is a prediction,
// not a bound: the report states it beside the measured peak. The objects outside the static
// group (whose trees may be refitted and keep full leaves and float nodes) are not counted.

#include <cstddef>
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

/// Predicted bytes the build of `layout` adds per static triangle at its peak (the table above).
std::size_t layout_peak_bytes_per_triangle(const StaticGroupLayout& layout);

/// The fastest layout of the ladder above whose predicted peak, `resident` + `triangles` x its
/// bytes per triangle, is at most `budget` bytes; the smallest layout (fits false) when none is.
StaticLayoutChoice choose_static_group_layout(std::size_t triangles, std::size_t resident, std::size_t budget);

}  // namespace dynrt
