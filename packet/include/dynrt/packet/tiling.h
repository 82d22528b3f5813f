#pragma once
// The image is traced in 16x16 pixel tiles: the unit of parallel work today and the footprint
// of one ray packet once packet tracing lands. Edge tiles are clipped to the image.

#include <algorithm>

namespace dynrt::packet {

inline constexpr int kTileSize = 16;

struct Tile {
    int x0, y0;  ///< first pixel (inclusive)
    int x1, y1;  ///< one past the last pixel
};

/// Row-major tiling of a width x height image.
class Tiling {
public:
    Tiling(int width, int height)
        : width_(width), height_(height),
          tiles_x_((width + kTileSize - 1) / kTileSize),
          tiles_y_((height + kTileSize - 1) / kTileSize) {}

    int count() const { return tiles_x_ * tiles_y_; }

    /// Tile `i` in [0, count()).
    Tile tile(int i) const {
        const int tx = i % tiles_x_, ty = i / tiles_x_;
        return Tile{tx * kTileSize, ty * kTileSize, std::min((tx + 1) * kTileSize, width_),
                    std::min((ty + 1) * kTileSize, height_)};
    }

private:
    int width_, height_, tiles_x_, tiles_y_;
};

}  // namespace dynrt::packet
