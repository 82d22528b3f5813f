// MipPyramid (mip_pyramid.h): level 0 from the decoded texels, each coarser level from the one
// above, rows in parallel.

#include "textures/mip_pyramid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace dynrt::textures {

namespace {

/// OpenImageIO's float -> uint8 conversion (scaled_conversion): scaled, rounded half up,
/// clamped.
std::uint8_t to_byte(float v) {
    return std::uint8_t(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f));
}

/// The texel's four channels from a decoded image of 1-4 channels: grey widened to RGB, alpha
/// `opaque` (1, or 255 for bytes) where the image has none.
template <typename T>
void widen(const T* in, int channels, T opaque, T out[4]) {
    const bool grey = channels <= 2;
    out[0] = in[0];
    out[1] = grey ? in[0] : in[1];
    out[2] = grey ? in[0] : in[2];
    out[3] = channels == 2 ? in[1] : channels == 4 ? in[3] : opaque;
}

/// Where texel i of a level `size` texels across reads the finer level, `finer` texels across:
/// at the texel's centre, between texels `low` and `high` (the same one at the edge of a side
/// already 1 texel wide, where its weight is 0), `high` weighing `weight`.
struct Tap {
    int low, high;
    float weight;
};
Tap tap(int i, int size, int finer) {
    const float centre = (float(i) + 0.5f) / float(size);
    const float at = centre * float(finer) - 0.5f;
    const float low = std::floor(at);
    return {int(low), std::min(int(low) + 1, finer - 1), at - low};
}

std::uint32_t pack(const std::uint8_t c[4]) {
    return std::uint32_t(c[0]) | std::uint32_t(c[1]) << 8 | std::uint32_t(c[2]) << 16 | std::uint32_t(c[3]) << 24;
}

}  // namespace

void MipPyramid::add_levels(int width, int height) {
    std::int32_t first = 0;
    // Halving with floor down to 1, m times over, is max(1, side >> m), which the kernel
    // computes instead of reading.
    for (int m = 0;; ++m) {
        Level level;
        level.width = std::max(1, width >> m);
        level.height = std::max(1, height >> m);
        level.blocks_x = (level.width + kBlock - 1) / kBlock;
        level.first = first;
        levels_.push_back(level);
        first_[m] = level.first;
        min_side_.push_back(float(std::min(level.width, level.height)));
        const std::int32_t blocks_y = (level.height + kBlock - 1) / kBlock;
        first += level.blocks_x * blocks_y * kBlock * kBlock;
        if (level.width == 1 && level.height == 1) break;
    }
    if (eight_bit()) {
        rgba8_.assign(std::size_t(first), 0u);
    } else {
        rgba_float_.assign(std::size_t(first) * 4, 0.0f);
    }
}

float MipPyramid::texel(int level, int x, int y, int c) const {
    const std::size_t i = texel_index(levels_[std::size_t(level)], x, y);
    if (eight_bit()) return float((rgba8_[i] >> (8 * c)) & 0xffu) * (1.0f / 255.0f);
    return rgba_float_[i * 4 + std::size_t(c)];
}

MipPyramid::MipPyramid(const TexelArray& image) {
    eight_bit_ = !image.floating;
    add_levels(image.width, image.height);
    const int channels = image.channels;
    const Level& top = levels_.front();
    // Level 0: the image's texels, widened to RGBA.
    tbb::parallel_for(0, image.height, [&](int y) {
        for (int x = 0; x < image.width; ++x) {
            const std::size_t in = (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * std::size_t(channels);
            const std::size_t out = texel_index(top, x, y);
            if (image.floating) {
                float values[4];
                std::memcpy(values, image.bytes.data() + in * sizeof(float), std::size_t(channels) * sizeof(float));
                widen(values, channels, 1.0f, &rgba_float_[out * 4]);
            } else {
                std::uint8_t c[4];
                widen<std::uint8_t>(image.bytes.data() + in, channels, 255, c);
                rgba8_[out] = pack(c);
            }
        }
    });
    // Each coarser level: the finer one interpolated bilinearly at each texel's centre, in
    // float from its stored values, as read_unmipped does (mip_pyramid.h).
    for (std::size_t m = 1; m < levels_.size(); ++m) {
        const Level& up = levels_[m - 1];
        const Level& level = levels_[m];
        tbb::parallel_for(0, level.height, [&](int j) {
            const Tap y = tap(j, level.height, up.height);
            for (int i = 0; i < level.width; ++i) {
                const Tap x = tap(i, level.width, up.width);
                const float s1 = 1.0f - x.weight, t1 = 1.0f - y.weight, sx = x.weight, ty = y.weight;
                const int x0 = x.low, x1 = x.high, y0 = y.low, y1 = y.high;
                float v[4];
                for (int c = 0; c < 4; ++c) {
                    const float a = texel(int(m - 1), x0, y0, c), b = texel(int(m - 1), x1, y0, c);
                    const float d = texel(int(m - 1), x0, y1, c), e = texel(int(m - 1), x1, y1, c);
                    v[c] = t1 * (a * s1 + b * sx) + ty * (d * s1 + e * sx);
                }
                const std::size_t out = texel_index(level, i, j);
                if (eight_bit()) {
                    const std::uint8_t c[4] = {to_byte(v[0]), to_byte(v[1]), to_byte(v[2]), to_byte(v[3])};
                    rgba8_[out] = pack(c);
                } else {
                    std::memcpy(&rgba_float_[out * 4], v, sizeof v);
                }
            }
        });
    }
}

std::size_t MipPyramid::bytes() const {
    return sizeof(*this) + rgba8_.capacity() * sizeof(std::uint32_t) + rgba_float_.capacity() * sizeof(float) +
           levels_.capacity() * sizeof(Level) + min_side_.capacity() * sizeof(float);
}

}  // namespace dynrt::textures
