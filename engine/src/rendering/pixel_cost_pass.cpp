// trace_pixel_costs (pixel_cost_pass.h).

#include "rendering/pixel_cost_pass.h"

#include "dynrt/packet/pinhole.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <limits>

namespace dynrt::detail {

namespace {

std::uint32_t clamp32(std::uint64_t n) {
    return std::uint32_t(std::min<std::uint64_t>(n, std::numeric_limits<std::uint32_t>::max()));
}

}  // namespace

void trace_pixel_costs(const bvh::TwoLevelBvh& tlas, const Camera& camera, int width, int height,
                       packet::TileShare share, std::vector<PixelCost>& cost) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    if (cost.size() != pixels) cost.assign(pixels, PixelCost{});
    const packet::PinholeRays pinhole(camera, width, height);
    const packet::Tiling tiling(width, height, share);
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        const packet::Tile tile = tiling.tile(i);
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                // The camera ray of a one-sample frame, bit for bit (pinhole.h).
                bvh::TraversalStats work;
                bvh::intersect_closest(tlas, pinhole.ray(x, y), work);
                cost[std::size_t(y) * std::size_t(width) + std::size_t(x)] =
                    PixelCost{clamp32(work.nodes_visited), clamp32(work.triangles_tested)};
            }
        }
    });
}

}  // namespace dynrt::detail
