#pragma once
// Adaptive image-space sampling of one 16x16 tile (TraceSettings::adaptive_tolerance > 0), the
// renderer's opt-in approximate mode: trace a sparse grid, and fill the tile by bilinear
// interpolation when the samples agree, else trace the tile exactly.
//
// Grid: tile columns and rows 0, 8 and the tile's last (15 for a full tile): 9 samples, traced
// one by one (cheaper than a packet for so few rays), and 4 cells. The tile is interpolated
// when in every cell
//   * the four corner samples all miss, or all hit the same object with the same shadow
//     verdict for every light, normals within 1 - dot <= tolerance of the first corner's and
//     colours within the tolerance per channel, and
//   * no object but that one (no object at all, for a cell of misses) has a world box reaching
//     into the cell's frustum, the pyramid from the eye through the four corner rays, which
//     holds every pixel ray of the cell (for a cell on an object, only in front of its
//     farthest corner hit counts).
// So no other object can hide between the samples, at any tolerance. What interpolation can
// still get wrong: a fold of the same object between the samples (the normal and colour tests
// catch most), and a shadow edge that crosses a cell without changing any corner's verdict.
// Otherwise the tile is traced exactly: part of a tile costs a packet about as much as all of
// it.

#include "dynrt/engine/renderer.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/tiling.h"
#include "update/scene_accel.h"
#include "rendering/stage_work.h"
#include "rendering/tile_shading.h"
#include "dynrt/engine/trace_backend.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dynrt::detail {

/// What adaptive sampling needs besides the tile; fixed for a frame.
struct AdaptiveFrame {
    const SceneAccel& accel;
    const packet::PinholeRays& pinhole;
    std::span<const PointLight> lights;
    const TileShading& shading;
    const std::vector<std::int32_t>& object_material;
    const TraceBackend& tracer;
    float tolerance;  ///< > 0
    int width;
};

/// Renders `tile` adaptively into `out` (buffers already sized) and `hits` (the traced pixels'
/// hits; interpolated pixels get a miss), adding its work to `work` (its traversal counters
/// too when `count`).
void trace_tile_adaptive(const AdaptiveFrame& frame, const packet::Tile& tile,
                         std::vector<bvh::InstanceHit>& hits, RenderedFrame& out, StageWork& work,
                         bool count);

}  // namespace dynrt::detail
