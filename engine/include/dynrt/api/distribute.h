#pragma once
// Splitting work across the processes of an embedder's own MPI program (or any other group of
// processes), one Engine per process, each given the same meshes and moves. dynrt makes no MPI
// call itself: these helpers say which part each process renders or casts, and in what order
// its pixels go, so that the program gathers them with its own MPI_Gatherv. engine/examples/
// mpi_tiles.cpp does it end to end; `mpirun dynrt render --distribute tiles` is the same split.

#include "dynrt/api/export.h"

#include <cstddef>
#include <vector>

namespace dynrt {

/// The pixel indices (y * width + x) of tile share `share` of `shares`: the image's 16x16
/// tiles (row-major, edge tiles clipped) number `share`, `share + shares`, ..., tile by tile,
/// each tile's pixels row by row. RenderSettings::tile_share / tile_shares render exactly
/// these pixels; a gather that packs them in this order on each process and unpacks them in
/// the same order on the root rebuilds the image. Interleaved tiles spread costly regions
/// over the processes. Throws Error (invalid_argument) for a size outside 1..65536 or a share not in
/// [0, shares).
DYNRT_API std::vector<std::size_t> tile_share_pixels(int width, int height, int share, int shares);

/// Rays [begin, end) of `count` for process `share` of `shares`: contiguous, in order, sizes
/// differing by at most one. Contiguous rather than interleaved: a batch's neighbouring rays
/// are usually coherent and go into the same packets. Throws Error (invalid_argument) for a share not
/// in [0, shares).
struct RayShare {
    std::size_t begin = 0;  ///< the share's first ray
    std::size_t end = 0;    ///< one past its last ray
};
DYNRT_API RayShare ray_share(std::size_t count, int share, int shares);

}  // namespace dynrt
