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
#include "rendering/stage_work.h"
#include "rendering/tile_pass.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dynrt::detail {

/// What adaptive sampling needs besides the tile; fixed for a frame.
struct AdaptiveFrame {
    /// The frame's tile pass (without secondary rays), which a tile not interpolated takes.
    const TilePass& pass;
    float tolerance;  ///< > 0
};

/// Renders tile number `index`, `tile`, adaptively into `out` (buffers already sized) and the
/// pass's hits (the traced pixels' hits; interpolated pixels get a miss), adding its work to
/// `work`.
void trace_tile_adaptive(const AdaptiveFrame& frame, int index, const packet::Tile& tile,
                         RenderedFrame& out, StageWork& work);

}  // namespace dynrt::detail
