#pragma once
// sRGB-encoded values to linear (IEC 61966-2-1), lane-wise, for the texture filter: textures
// are filtered as stored and decoded after (texture_filter.h). No memory is read per lane: the
// power branch is 16 cubic pieces whose coefficients are picked by permutation within
// registers; on AMD Zen 4 the 1025-entry table it replaced, read by two gathers a channel,
// was a third of the filter's time.

#include "dynrt/packet/simd.h"

#include <cmath>
#include <cstdint>
#include <utility>

namespace dynrt::textures {

/// The sRGB decoding's (IEC 61966-2-1: c / 12.92 up to 0.04045, then the power) power branch, ((c + 0.055) / 1.055)^2.4 for c > 0.04045, as 16 cubics in
/// u = c - k / 16 on [k / 16, (k + 1) / 16] (the first from 0.04045), each interpolating the
/// curve at the four Chebyshev nodes of its piece: within 1e-7 of it in float (the test
/// checks). Coefficients by degree: cubic[d][k].
struct SrgbCubics {
    float cubic[4][16];

    static const SrgbCubics& get() {
        static const SrgbCubics cubics = make();
        return cubics;
    }

private:
    static SrgbCubics make() {
        SrgbCubics out{};
        const double pi = 3.14159265358979323846;
        for (int k = 0; k < 16; ++k) {
            const double low = k == 0 ? 0.04045 : k / 16.0, high = (k + 1) / 16.0;
            const double mid = 0.5 * (low + high), half = 0.5 * (high - low);
            // The Vandermonde system in u at the nodes, solved by Gaussian elimination.
            double a[4][5];
            for (int j = 0; j < 4; ++j) {
                const double c = mid + half * std::cos((2 * j + 1) * pi / 8.0);
                const double u = c - k / 16.0;
                for (int d = 0; d < 4; ++d) a[j][d] = std::pow(u, d);
                a[j][4] = std::pow((c + 0.055) / 1.055, 2.4);
            }
            for (int col = 0; col < 4; ++col) {
                int pivot = col;
                for (int r = col + 1; r < 4; ++r) {
                    if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
                }
                for (int d = 0; d < 5; ++d) std::swap(a[col][d], a[pivot][d]);
                for (int r = 0; r < 4; ++r) {
                    if (r == col) continue;
                    const double f = a[r][col] / a[col][col];
                    for (int d = col; d < 5; ++d) a[r][d] -= f * a[col][d];
                }
            }
            for (int d = 0; d < 4; ++d) out.cubic[d][k] = float(a[d][4] / a[d][d]);
        }
        return out;
    }
};

/// sRGB -> linear lane-wise: c / 12.92 up to 0.04045, else SrgbCubics' piece, its
/// coefficients picked within registers (table16). Values are clamped to [0, 1] first (NaN to
/// 0), as the exact decoding does.
template <int W>
typename packet::simd::Lanes<W>::F srgb_decode(typename packet::simd::Lanes<W>::F encoded) {
    using L = packet::simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    F c = L::select(encoded > zero, encoded, zero);  // NaN -> 0
    c = L::select(c < one, c, one);
    const I top = L::splat(std::int32_t(15));
    I piece = L::truncate(c * L::splat(16.0f));
    piece = L::select(piece < top, piece, top);
    const F u = c - L::to_float(piece) * L::splat(0.0625f);
    const SrgbCubics& cubics = SrgbCubics::get();
    F power = L::table16(cubics.cubic[3], piece);
    for (int d = 2; d >= 0; --d) power = power * u + L::table16(cubics.cubic[d], piece);
    return L::select(c <= L::splat(0.04045f), c * L::splat(1.0f / 12.92f), power);
}

}  // namespace dynrt::textures
