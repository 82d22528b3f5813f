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
// Everything is lane-wise SIMD (packet/simd.h): the texel reads are gathers, the small tables
// (where each level starts, the sRGB cubics) are permutations within registers. Coordinates are
// folded into one period before scaling, so a non-finite or huge s or t (|s| >= 2^23, where
// a float has no fraction left) reads as 0 and never indexes outside the pyramid.

#include "textures/mip_pyramid.h"
#include "textures/srgb_decode.h"

#include "dynrt/packet/simd.h"

#include <cmath>
#include <cstdint>

namespace dynrt::textures {

template <int W>
struct TrilinearFilter {
    using L = packet::simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    using U = typename L::U;

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

    /// Where a bilinear lookup of level `level` (per lane) at folded coordinates (s, t)
    /// reads: its four texels' indices (top-left, top-right, bottom-left, bottom-right) and
    /// its weights across (sx) and down (ty).
    static void corners(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, I level, F s, F t,
                        I index[4], F& sx, F& ty) {
        // A level's sides halve down to 1 (mip_pyramid.h): max(1, side >> level), computed;
        // where the level starts comes from a 16-entry table, within registers.
        const I one = L::splat(std::int32_t(1));
        const I width = max_int(L::splat(std::int32_t(pyramid.levels()[0].width)) >> level, one);
        const I height = max_int(L::splat(std::int32_t(pyramid.levels()[0].height)) >> level, one);
        const I blocks_x = (width + L::splat(std::int32_t(kBlock - 1))) >> 2;
        const I first = L::table16(pyramid.level_first(), level);
        const F half = L::splat(0.5f);
        const F x = s * L::to_float(width) - half, y = t * L::to_float(height) - half;
        const F x_floor = L::floor(x), y_floor = L::floor(y);
        sx = x - x_floor;
        ty = y - y_floor;
        const I x0 = L::truncate(x_floor), y0 = L::truncate(y_floor);
        const I xs[2] = {wrap_index(wrap_s, x0, width), wrap_index(wrap_s, x0 + one, width)};
        const I ys[2] = {wrap_index(wrap_t, y0, height), wrap_index(wrap_t, y0 + one, height)};
        const I three = L::splat(std::int32_t(kBlock - 1));
        for (int r = 0; r < 2; ++r) {
            const I row = first + (ys[r] >> 2) * blocks_x * L::splat(std::int32_t(kBlock * kBlock)) +
                          ((ys[r] & three) << 2);
            for (int c = 0; c < 2; ++c) index[2 * r + c] = row + ((xs[c] >> 2) << 4) + (xs[c] & three);
        }
    }

    /// The bilinear RGB from the four texels at `index` (corners' order) and the weights.
    static void bilerp(const MipPyramid& pyramid, const I index[4], F sx, F ty, F rgb[3]) {
        F texel[4][3];
        if (pyramid.eight_bit()) {
            const U mask = L::splat(std::uint32_t(0xff));
            for (int corner = 0; corner < 4; ++corner) {
                const U word = L::gather(pyramid.rgba8(), index[corner]);
                for (int k = 0; k < 3; ++k) texel[corner][k] = L::to_float(I((word >> (8 * k)) & mask));
            }
        } else {
            const I four = L::splat(std::int32_t(4));
            for (int corner = 0; corner < 4; ++corner) {
                const I base = index[corner] * four;
                for (int k = 0; k < 3; ++k) {
                    texel[corner][k] = L::gather(pyramid.rgba_float(), base + L::splat(std::int32_t(k)));
                }
            }
        }
        const F scale = L::splat(pyramid.eight_bit() ? 1.0f / 255.0f : 1.0f);
        const F s1 = L::splat(1.0f) - sx, t1 = L::splat(1.0f) - ty;
        for (int k = 0; k < 3; ++k) {
            const F value = t1 * (texel[0][k] * s1 + texel[1][k] * sx) + ty * (texel[2][k] * s1 + texel[3][k] * sx);
            rgb[k] = value * scale;
        }
    }

    /// The alpha channel at (s, t) (not folded), bilinear within level 0 whatever the
    /// footprint: what a cut-out compares with its cutoff (dynrt/engine/alpha_mask.h). The
    /// finest level, so that a cut-out's edge does not move with distance (a coarser level
    /// averages alpha, and a mask thins out or swells as it recedes). Alpha is linear.
    static F alpha(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, F s, F t) {
        I index[4];
        F sx, ty;
        corners(pyramid, wrap_s, wrap_t, L::splat(std::int32_t(0)), fold(wrap_s, s), fold(wrap_t, t), index, sx, ty);
        F texel[4];
        for (int corner = 0; corner < 4; ++corner) {
            if (pyramid.eight_bit()) {
                const U word = L::gather(pyramid.rgba8(), index[corner]);
                texel[corner] = L::to_float(I(word >> 24));
            } else {
                texel[corner] = L::gather(pyramid.rgba_float(), index[corner] * L::splat(std::int32_t(4)) +
                                                                   L::splat(std::int32_t(3)));
            }
        }
        const F s1 = L::splat(1.0f) - sx, t1 = L::splat(1.0f) - ty;
        const F value = t1 * (texel[0] * s1 + texel[1] * sx) + ty * (texel[2] * s1 + texel[3] * sx);
        return value * L::splat(pyramid.eight_bit() ? 1.0f / 255.0f : 1.0f);
    }

    /// The level choice (compute_miplevels) for footprints `width` wide: the finer level
    /// read, the coarser one (the same where nothing is blended) and the coarser one's weight.
    static void choose_levels(const MipPyramid& pyramid, F width, I& fine, I& coarse, F& blend) {
        // The first level whose smaller side spans at most one footprint.
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
        fine = L::select(none, L::splat(std::int32_t(levels - 1)), L::select(blended, chosen - 1, zero));
        coarse = L::select(blended, chosen, fine);
        const F blend_raw = L::splat(2.0f) * chosen_span - L::splat(1.0f);
        blend = L::select(blend_raw > L::splat(0.0f), blend_raw, L::splat(0.0f));
        blend = L::select(blend < L::splat(1.0f), blend, L::splat(1.0f));
        blend = L::select(blended, blend, L::splat(0.0f));
    }
};

/// Up to kMax lookups of one texture filtered in three passes over their vectors of W: where
/// (levels, texel indices, weights), what (texels gathered, blended), then the sRGB decoding.
/// Each pass's vectors are independent of each other, so the core overlaps their gathers; one
/// pass doing everything per vector makes a chain too long for it to see past. The passes do
/// exactly what one lookup does, in the same order per lane: the bits do not depend on how
/// many lookups go together.
template <int W>
class TrilinearBatch {
public:
    static constexpr int kMax = 256;
    using Filter = TrilinearFilter<W>;
    using L = typename Filter::L;
    using F = typename Filter::F;
    using I = typename Filter::I;

    /// Lookups i in [0, count) at (s[i], t[i]) over footprints width[i] (texture_set.h) into
    /// rgb[0..2][i], linear (decoded from sRGB when `srgb`). `count` is a multiple of W, at
    /// most kMax.
    void run(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, bool srgb, int count,
             const float* s_in, const float* t_in, const float* width_in, float* const rgb_out[3]) {
        // Where.
        bool any_coarse = false;
        for (int v = 0; v < count; v += W) {
            const F s = Filter::fold(wrap_s, L::load(s_in + v)), t = Filter::fold(wrap_t, L::load(t_in + v));
            I fine, coarse;
            F blend;
            Filter::choose_levels(pyramid, L::load(width_in + v), fine, coarse, blend);
            store_corners(pyramid, wrap_s, wrap_t, 0, v, fine, s, t);
            L::store(blend_ + v, blend);
            if (L::bits(blend > L::splat(0.0f)) != 0) {
                store_corners(pyramid, wrap_s, wrap_t, 1, v, coarse, s, t);
                any_coarse = true;
            }
            coarse_[v / W] = L::bits(blend > L::splat(0.0f)) != 0;
        }
        // What: the finer level, blended with the coarser one where it weighs anything.
        float* const encoded[3] = {srgb ? encoded_[0] : rgb_out[0], srgb ? encoded_[1] : rgb_out[1],
                                   srgb ? encoded_[2] : rgb_out[2]};
        for (int v = 0; v < count; v += W) {
            F rgb[3];
            bilerp_stored(pyramid, 0, v, rgb);
            if (any_coarse && coarse_[v / W]) {
                F coarse[3];
                bilerp_stored(pyramid, 1, v, coarse);
                const F blend = L::load(blend_ + v);
                const F keep = L::splat(1.0f) - blend;
                for (int k = 0; k < 3; ++k) rgb[k] = keep * rgb[k] + blend * coarse[k];
            }
            for (int k = 0; k < 3; ++k) L::store(encoded[k] + v, rgb[k]);
        }
        if (!srgb) return;
        for (int k = 0; k < 3; ++k) {
            for (int v = 0; v < count; v += W) L::store(rgb_out[k] + v, srgb_decode<W>(L::load(encoded_[k] + v)));
        }
    }

private:
    void store_corners(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, int level, int v, I which,
                       F s, F t) {
        I index[4];
        F sx, ty;
        Filter::corners(pyramid, wrap_s, wrap_t, which, s, t, index, sx, ty);
        for (int c = 0; c < 4; ++c) L::store(index_[level][c] + v, index[c]);
        L::store(weight_[level][0] + v, sx);
        L::store(weight_[level][1] + v, ty);
    }

    void bilerp_stored(const MipPyramid& pyramid, int level, int v, F rgb[3]) const {
        I index[4];
        for (int c = 0; c < 4; ++c) index[c] = L::load(index_[level][c] + v);
        Filter::bilerp(pyramid, index, L::load(weight_[level][0] + v), L::load(weight_[level][1] + v), rgb);
    }

    alignas(64) std::int32_t index_[2][4][kMax];  ///< [finer, coarser][corner][lookup]
    alignas(64) float weight_[2][2][kMax];        ///< [finer, coarser][sx, ty][lookup]
    alignas(64) float blend_[kMax];
    alignas(64) float encoded_[3][kMax];
    bool coarse_[kMax / W];
};

/// W lookups (one vector) through this thread's batch: TrilinearBatch<W>::run with count W.
template <int W>
void trilinear_lookup(const MipPyramid& pyramid, TextureWrap wrap_s, TextureWrap wrap_t, bool srgb, const float* s,
                      const float* t, const float* width, float* const rgb[3]) {
    thread_local TrilinearBatch<W> batch;
    batch.run(pyramid, wrap_s, wrap_t, srgb, W, s, t, width, rgb);
}

}  // namespace dynrt::textures
