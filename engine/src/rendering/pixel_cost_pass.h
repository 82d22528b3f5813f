#pragma once
// The cost view's pass (dynrt/engine/pixel_cost.h): each pixel's camera ray traced alone
// through the frame's two-level tree with its counters on.

#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/pixel_cost.h"
#include "dynrt/packet/tiling.h"

#include <vector>

namespace dynrt::detail {

/// Fills `cost` (sized width x height, rows from the top; pixels outside `share` are left as
/// they were, or 0 when it had another size) with the work of each pixel's centre ray through
/// `tlas`. Parallel over tiles on the caller's arena.
void trace_pixel_costs(const bvh::TwoLevelBvh& tlas, const Camera& camera, int width, int height,
                       packet::TileShare share, std::vector<PixelCost>& cost);

}  // namespace dynrt::detail
