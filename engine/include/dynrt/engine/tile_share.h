#pragma once
// A frame split across processes (`mpirun dynrt render --distribute tiles`): each renders its
// TileShare of the 16x16 tiles (TraceSettings::tiles), packs those tiles' pixels into one
// contiguous buffer, and one process unpacks every share into the whole frame.

#include "dynrt/engine/renderer.h"
#include "dynrt/packet/tiling.h"

#include <cstddef>
#include <span>
#include <vector>

namespace dynrt {

/// Floats one pixel takes in a packed share: its colour (3) and, with hit buffers, depth (1),
/// object and primitive (1 each, their int bits) and normal (3).
inline constexpr std::size_t kPackedColorFloats = 3;
inline constexpr std::size_t kPackedHitFloats = 6;
std::size_t packed_floats_per_pixel(bool hit_buffers);

/// Floats a packed `share` of a width x height frame takes.
std::size_t packed_share_size(int width, int height, packet::TileShare share, bool hit_buffers);

/// Appends the pixels of `share`'s tiles of `frame` to `out`: tile by tile in share order,
/// each tile's pixels row by row, each pixel's floats as packed_floats_per_pixel says. The
/// hit buffers go when the frame has them. Bit-exact: unpacking gives the same bits back.
void pack_tiles(const RenderedFrame& frame, packet::TileShare share, std::vector<float>& out);

/// Writes a packed `share` (as pack_tiles made it) into `frame`, whose size and buffers must
/// already be set (the hit buffers are written when `hit_buffers`). Throws
/// std::invalid_argument when `packed` is not packed_share_size floats long.
void unpack_tiles(std::span<const float> packed, packet::TileShare share, bool hit_buffers,
                  RenderedFrame& frame);

}  // namespace dynrt
