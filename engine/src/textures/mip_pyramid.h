#pragma once
// A texture's MIP pyramid held in memory in the layout the shading kernel reads
// (texture_filter.h). Williams 1983, "Pyramidal Parametrics": level 0 is the image, each next
// level half the size in each direction (rounded down, at least 1), down to 1x1.
//
// Each coarser level is made as OpenImageIO's TextureSystem makes the levels of an image that
// has none ("automip", ImageCacheFile::read_unmipped): texel (i, j) of level m is the bilinear
// interpolation of level m - 1 at the texel's centre, ((i + 0.5) / w_m, (j + 0.5) / h_m), a 2x2
// box for even sizes, computed in float from the finer level's stored values and stored
// rounded like them. So lookups here and through the TextureSystem read the same texels
// (textures_test.cpp compares them).
//
// Layout: texels are RGBA, 8 bits a channel in one 32-bit word (R lowest) for 8-bit images,
// or four floats for deeper ones (16-bit PNGs, EXR); grey images are widened to RGB, the
// alpha kept (and unused). Each level is stored in blocks of 4x4 texels, blocks row by row:
// a 4x4 block of 8-bit texels is one 64-byte cache line, so a bilinear lookup's 2x2 texels
// sit in one line 9 times in 16 instead of straddling two rows almost always.

#include "dynrt/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynrt::textures {

/// Block edge, in texels.
inline constexpr int kBlock = 4;

class MipPyramid {
public:
    /// One level: its size, blocks per row and where its first texel is.
    struct Level {
        std::int32_t width = 0, height = 0;
        std::int32_t blocks_x = 0;  ///< ceil(width / kBlock)
        std::int32_t first = 0;     ///< index of the level's first texel in the texel arrays
    };

    /// The pyramid of `image` (decoded texels: 1-4 channels, rows from the top-left).
    /// Precondition: the image is not empty and each side is at most kMaxTextureSide (so
    /// there are at most kMaxLevels levels, and every texel index of every level, times four
    /// floats, fits the kernel's 32-bit gather offsets).
    explicit MipPyramid(const TexelArray& image);

    static constexpr int kMaxLevels = 15;  ///< log2(kMaxTextureSide) + 1

    /// 8-bit texels (`rgba8`), else float ones (`rgba_float`, four per texel).
    bool eight_bit() const { return eight_bit_; }
    const std::uint32_t* rgba8() const { return rgba8_.data(); }
    const float* rgba_float() const { return rgba_float_.data(); }

    const std::vector<Level>& levels() const { return levels_; }
    /// Per level, where it starts (16 entries, the unused ones 0) and its smaller side (for the
    /// level choice), as the kernel reads them by level index (its sides it computes: level m is max(1, width >> m)
    /// x max(1, height >> m)).
    const std::int32_t (&level_first() const)[16] { return first_; }
    const float* level_min_side() const { return min_side_.data(); }

    /// Bytes held, every level and table included.
    std::size_t bytes() const;

    /// The texel index of (x, y) within `level` (blocked layout).
    static std::size_t texel_index(const Level& level, int x, int y) {
        return std::size_t(level.first) +
               (std::size_t(y / kBlock) * std::size_t(level.blocks_x) + std::size_t(x / kBlock)) * kBlock * kBlock +
               std::size_t(y % kBlock) * kBlock + std::size_t(x % kBlock);
    }

    /// Texel (x, y) of `level`, channel c (0-3), as a value in [0, 1] for 8-bit texels.
    float texel(int level, int x, int y, int c) const;

private:
    void add_levels(int width, int height);


    bool eight_bit_ = true;
    std::vector<Level> levels_;
    std::int32_t first_[16] = {};
    std::vector<float> min_side_;
    std::vector<std::uint32_t> rgba8_;
    std::vector<float> rgba_float_;
};

}  // namespace dynrt::textures
