#pragma once
// The image is traced in 16x16 pixel tiles: the unit of parallel work and the footprint of one
// ray packet. Edge tiles are clipped to the image. A frame split across processes gives each a
// TileShare, an interleaved subset of the tiles.

#include <algorithm>
#include <cstddef>

namespace dynrt::packet {

inline constexpr int kTileSize = 16;

struct Tile {
    int x0, y0;  ///< first pixel (inclusive)
    int x1, y1;  ///< one past the last pixel
};

/// Tiles index, index + count, index + 2 count, ... of the row-major tile order: one of `count`
/// processes' part of a frame. Interleaved rather than in bands, so that every part holds
/// tiles from all over the image and costly regions are spread evenly (the classic static
/// load balance of tiled parallel ray tracers). The default is the whole image.
struct TileShare {
    int index = 0;
    int count = 1;
    bool whole() const { return count == 1; }
    bool valid() const { return count >= 1 && index >= 0 && index < count; }
    friend bool operator==(const TileShare&, const TileShare&) = default;
};

/// Row-major tiling of a width x height image, or of a share of its tiles.
class Tiling {
public:
    Tiling(int width, int height, TileShare share = {})
        : width_(width), height_(height),
          tiles_x_((width + kTileSize - 1) / kTileSize),
          tiles_y_((height + kTileSize - 1) / kTileSize), share_(share) {}

    /// Tiles in the share (all of them by default).
    int count() const {
        const int all = tiles_x_ * tiles_y_;
        return share_.index < all ? (all - share_.index + share_.count - 1) / share_.count : 0;
    }

    /// Tile `i` in [0, count()) of the share.
    Tile tile(int i) const {
        const int t = share_.index + i * share_.count;
        const int tx = t % tiles_x_, ty = t / tiles_x_;
        return Tile{tx * kTileSize, ty * kTileSize, std::min((tx + 1) * kTileSize, width_),
                    std::min((ty + 1) * kTileSize, height_)};
    }

    /// Calls visit(pixel index y * width + x) for every pixel of the share: tile by tile in
    /// share order, each tile's pixels row by row. The order a split frame's pixels are packed
    /// and unpacked in (dynrt/engine/tile_share.h, the library API's tile_share_pixels).
    template <typename Visit>
    void for_each_pixel(Visit&& visit) const {
        for (int i = 0; i < count(); ++i) {
            const Tile t = tile(i);
            for (int y = t.y0; y < t.y1; ++y) {
                for (int x = t.x0; x < t.x1; ++x) visit(std::size_t(y) * std::size_t(width_) + std::size_t(x));
            }
        }
    }

    /// Pixels in the share's tiles.
    std::size_t pixel_count() const {
        std::size_t pixels = 0;
        for (int i = 0; i < count(); ++i) {
            const Tile t = tile(i);
            pixels += std::size_t(t.x1 - t.x0) * std::size_t(t.y1 - t.y0);
        }
        return pixels;
    }

private:
    int width_, height_, tiles_x_, tiles_y_;
    TileShare share_;
};

}  // namespace dynrt::packet
