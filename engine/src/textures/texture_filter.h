#pragma once
// Trilinear MIP-map filtering of W lookups at once (Williams 1983, "Pyramidal Parametrics"),
// over a MipPyramid (mip_pyramid.h), with the rules of OpenImageIO's TextureSystem for an
// isotropic footprint in its trilinear mode (texturesys.cpp, compute_miplevels and
// sample_bilinear), so that dynrt's lookups agree with the ones they replace:
//
// - Level choice: for a footprint `width` wide in texture coordinates, the first level m
//   whose min(width_m, height_m) * width <= 1 texel; levels m - 1 and m are blended with
//   weight b = clamp(2 * width * min_side_m - 1, 0, 1) on level m. A footprint under a texel
//   of level 0 (magnification, or width 0) reads level 0 alone; one wider than the whole
//   image reads the 1x1 level.
// - Within a level: bilinear between the four texels around (s * w - 0.5, t * h - 0.5),
//   texel centres at half-integers, t running down the image from its top row.
// - Wrap modes fold texel indices: repeat tiles, clamp extends the edge texels, mirror tiles
//   with every other copy mirrored about the image's edge.
//
// Everything is lane-wise SIMD (packet/simd.h): the texel reads are gathers. Coordinates are
// folded into one period before scaling, so a non-finite or huge s or t (|s| >= 2^23, where
// a float has no fraction left) reads as 0 and never indexes outside the pyramid.

#include "textures/mip_pyramid.h"

#include "dynrt/packet/simd.h"

#include <cmath>
#include <cstdint>

namespace dynrt::textures {

/// IEC 61966-2-1's decoding: sRGB-encoded value -> linear (exact, for tables and tests).
inline float srgb_decode_exact(float encoded) {
    const float c = encoded < 0.0f ? 0.0f : encoded > 1.0f ? 1.0f : encoded;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// The decoding sampled at kSrgbSteps + 1 points over [0, 1], for srgb_decode's
/// interpolation: within 4e-7 of the exact curve (its second derivative is below 3.5).
inline constexpr int kSrgbSteps = 1024;
inline const float* srgb_decode_table() {
    static const auto table = [] {
        static float values[kSrgbSteps + 2];
        for (int i = 0; i <= kSrgbSteps; ++i) values[i] = srgb_decode_exact(float(i) / float(kSrgbSteps));
        values[kSrgbSteps + 1] = values[kSrgbSteps];  // read with weight 0 at exactly 1
        return values;
    }();
    return table;
}

template <int W>
struct TrilinearFilter {
    using L = packet::simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    using U = typename L::U;

    /// sRGB -> linear lane-wise, by linear interpolation in srgb_decode_table (values
    /// clamped to [0, 1] first, as the exact decoding does).
    static F srgb_decode(F encoded) {
        const F zero = L::splat(0.0f), one = L::splat(1.0f);
        F c = L::select(encoded > zero, encoded, zero);  // NaN -> 0
        c = L::select(c < one, c, one);
        const F x = c * L::splat(float(kSrgbSteps));
        const I i = L::truncate(x);
        const F f = x - L::to_float(i);
        const float* table = srgb_decode_table();
        const F a = L::gather(table, i), b = L::gather(table, i + 1);
        return a + f * (b - a);
    }

    /// A coordinate folded into the period its wrap mode repeats with: [0, 1] for repeat,
    /// [0, 2] for mirror, [-1, 2] for clamp (where everything further reads the edge).
    static F fold(TextureWrap mode, F coord) {
        const F zero = L::splat(0.0f);
        const F c = L::select(L::abs(coord) < L::splat(8388608.0f), coord, zero);
        switch (mode) {
            case TextureWrap::clamp: {
                const F low = L::splat(-1.0f), high = L::splat(2.0f);
                const F lower = L::select(c > low, c, low);
                return L::select(lower < high, lower, high);
            }
            case TextureWrap::mirror: return c - L::splat(2.0f) * L::floor(c * L::splat(0.5f));
            case TextureWrap::repeat: break;
        }
        return c - L::floor(c);
    }

    static I max_int(I a, I b) { return L::select(a > b, a, b); }

    /// Texel index `i` (from a folded coordinate) folded into [0, size).
    static I wrap_index(TextureWrap mode, I i, I size) {
        const I zero = L::splat(std::int32_t(0));
        switch (mode) {
            case TextureWrap::clamp: {
                const I last = size - 1;
                const I lower = L::select(i > zero, i, zero);
                return L::select(lower < last, lower, last);
            }
            case TextureWrap::mirror: {
                const I period = size + size;
                i = L::select(i < zero, i + period, i);
                i = L::select(i >= period, i - period, i);
                return L::select(i >= size, period - 1 - i, i);
            }
            case TextureWrap::repeat: break;
        }
        i = L::select(i < zero, i + size, i);
        return L::select(i >= size, i - size, i);
    }

    /// Bilinear RGB of level `level` (per lane) at folded coordinates (s, t).
    static void bilinear(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, I level, F s, F t,
                         F rgb[3]) {
        // A level's sides halve down to 1 (mip_pyramid.h): max(1, side >> level), computed;
        // only where the level starts is read from the pyramid's table.
        const I one = L::splat(std::int32_t(1));
        const I width = max_int(L::splat(std::int32_t(pyramid.levels()[0].width)) >> level, one);
        const I height = max_int(L::splat(std::int32_t(pyramid.levels()[0].height)) >> level, one);
        const I blocks_x = (width + L::splat(std::int32_t(kBlock - 1))) >> 2;
        const I first = I(L::gather(reinterpret_cast<const std::uint32_t*>(pyramid.level_first()), level));
        const F half = L::splat(0.5f);
        const F x = s * L::to_float(width) - half, y = t * L::to_float(height) - half;
        const F x_floor = L::floor(x), y_floor = L::floor(y);
        const F sx = x - x_floor, ty = y - y_floor;
        const I x0 = L::truncate(x_floor), y0 = L::truncate(y_floor);
        const I xs[2] = {wrap_index(wrap_s, x0, width), wrap_index(wrap_s, x0 + one, width)};
        const I ys[2] = {wrap_index(wrap_t, y0, height), wrap_index(wrap_t, y0 + one, height)};
        const I three = L::splat(std::int32_t(kBlock - 1));
        I index[2][2];
        for (int r = 0; r < 2; ++r) {
            const I row = first + (ys[r] >> 2) * blocks_x * L::splat(std::int32_t(kBlock * kBlock)) +
                          ((ys[r] & three) << 2);
            for (int c = 0; c < 2; ++c) index[r][c] = row + ((xs[c] >> 2) << 4) + (xs[c] & three);
        }
        const F s1 = L::splat(1.0f) - sx, t1 = L::splat(1.0f) - ty;
        F texel[2][2][3];
        if (pyramid.eight_bit()) {
            const U mask = L::splat(std::uint32_t(0xff));
            for (int r = 0; r < 2; ++r) {
                for (int c = 0; c < 2; ++c) {
                    const U word = L::gather(pyramid.rgba8(), index[r][c]);
                    for (int k = 0; k < 3; ++k) texel[r][c][k] = L::to_float(I((word >> (8 * k)) & mask));
                }
            }
        } else {
            const I four = L::splat(std::int32_t(4));
            for (int r = 0; r < 2; ++r) {
                for (int c = 0; c < 2; ++c) {
                    const I base = index[r][c] * four;
                    for (int k = 0; k < 3; ++k) {
                        texel[r][c][k] = L::gather(pyramid.rgba_float(), base + L::splat(std::int32_t(k)));
                    }
                }
            }
        }
        const F scale = L::splat(pyramid.eight_bit() ? 1.0f / 255.0f : 1.0f);
        for (int k = 0; k < 3; ++k) {
            const F value = t1 * (texel[0][0][k] * s1 + texel[0][1][k] * sx) +
                            ty * (texel[1][0][k] * s1 + texel[1][1][k] * sx);
            rgb[k] = value * scale;
        }
    }

    /// The filtered RGB of W lookups at (s, t) over footprints `width` wide (texture_set.h),
    /// linear (decoded from sRGB when `srgb`). Reads W values from each input and writes W
    /// to each of rgb[0..2].
    static void lookup(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, bool srgb,
                       const float* s_in, const float* t_in, const float* width_in, float* const rgb_out[3]) {
        const F s = fold(wrap_s, L::load(s_in)), t = fold(wrap_t, L::load(t_in));
        const F width = L::load(width_in);
        // The level choice (compute_miplevels): the first level whose smaller side spans at
        // most one footprint.
        const int levels = int(pyramid.levels().size());
        const float* min_side = pyramid.level_min_side();
        I chosen = L::splat(std::int32_t(-1));
        F chosen_span = L::splat(0.0f);
        for (int m = 0; m < levels; ++m) {
            const F span = width * L::splat(min_side[m]);
            const I take = (span <= L::splat(1.0f)) & (chosen < L::splat(std::int32_t(0)));
            chosen = L::select(take, L::splat(std::int32_t(m)), chosen);
            chosen_span = L::select(take, span, chosen_span);
            if (L::bits(chosen >= L::splat(std::int32_t(0))) == L::kAllBits) break;
        }
        const I zero = L::splat(std::int32_t(0));
        const I none = chosen < zero;
        // Blended: levels chosen - 1 and chosen; else one level, the finest (chosen 0) or
        // the coarsest (none chosen).
        const I blended = chosen > zero;
        const I fine = L::select(none, L::splat(std::int32_t(levels - 1)),
                                 L::select(blended, chosen - 1, zero));
        const F blend_raw = L::splat(2.0f) * chosen_span - L::splat(1.0f);
        F blend = L::select(blend_raw > L::splat(0.0f), blend_raw, L::splat(0.0f));
        blend = L::select(blend < L::splat(1.0f), blend, L::splat(1.0f));
        blend = L::select(blended, blend, L::splat(0.0f));
        F rgb[3];
        bilinear(pyramid, wrap_s, wrap_t, fine, s, t, rgb);
        if (L::bits(blend > L::splat(0.0f)) != 0) {
            F coarse[3];
            bilinear(pyramid, wrap_s, wrap_t, L::select(blended, chosen, fine), s, t, coarse);
            const F keep = L::splat(1.0f) - blend;
            for (int k = 0; k < 3; ++k) rgb[k] = keep * rgb[k] + blend * coarse[k];
        }
        for (int k = 0; k < 3; ++k) L::store(rgb_out[k], srgb ? srgb_decode(rgb[k]) : rgb[k]);
    }
};

}  // namespace dynrt::textures
