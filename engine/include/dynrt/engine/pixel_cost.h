#pragma once
// The cost view (`dynrt render --aov cost`, `dynrt view`'s heat map): per pixel, the work its
// camera ray costs in the frame's trees. The ray through the pixel's centre is traced alone
// (the single-ray traversal of the two-level tree, bvh/two_level_bvh.h) with its counters on:
// top-level nodes plus each entered object's wide inner nodes and leaves, and the triangles
// its leaves tested. That is the tree's own cost for that ray, independent of how packets
// happen to share it, so it shows where a tree is poor (a refit that let boxes grow and
// overlap, long thin triangles, dense clutter) and what a rebuild buys. It is a separate pass
// after the frame, not counted in the frame's stage times; with another backend (Embree) it
// still measures dynrt's trees, which every frame keeps. Cut-out materials are not followed
// (the cost is that of the first traversal).
//
// The heat map is the per-pixel picture of traversal cost that Embree's tutorials draw from
// each pixel's cycles (their "cycles" shader), here from counted work instead of time, which
// does not move with the machine's load: dark for little work, through red and orange to
// white for the most, on a scale the caller fixes so that frames can be compared.

#include <cstdint>
#include <span>
#include <vector>

namespace dynrt {

/// One pixel's camera-ray work (0 and 0 for a pixel not in the trace's tile share).
struct PixelCost {
    std::uint32_t nodes = 0;      ///< node visits: top level, inner nodes and leaves
    std::uint32_t triangles = 0;  ///< ray/triangle tests
    friend bool operator==(const PixelCost&, const PixelCost&) = default;
};

/// Which count a heat map shows.
enum class CostMeasure { nodes, triangles };

/// The count `measure` of a pixel.
inline std::uint32_t cost_of(const PixelCost& cost, CostMeasure measure) {
    return measure == CostMeasure::nodes ? cost.nodes : cost.triangles;
}

/// A scale for a heat map of `costs`: the 99th percentile of `measure` rounded up to 1, 2 or
/// 5 times a power of ten (at least 1), so that a few extreme pixels do not wash out the rest
/// and the legend reads as a round number.
std::uint32_t cost_scale(std::span<const PixelCost> costs, CostMeasure measure);

/// The heat map of `measure` as 8-bit RGB, three bytes per pixel in the order of `costs`: 0
/// black, `scale` (and above) white, through purple, red, orange and yellow between. `scale`
/// must be at least 1.
std::vector<std::uint8_t> cost_heat_rgb8(std::span<const PixelCost> costs, CostMeasure measure,
                                         std::uint32_t scale);

}  // namespace dynrt
