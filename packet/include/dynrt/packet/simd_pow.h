#pragma once
// x^s in SIMD, for the specular term of Phong shading: std::pow has no vector form, and per
// lane it cost more than the rest of the shading together.
//
// Method (Cody and Waite's reduction; the series as in Muller, "Elementary Functions", ch. 11):
//   x = 2^e m with m in [sqrt(1/2), sqrt(2)),   log2 x = e + (2 / ln 2) atanh(t),
//     t = (m - 1) / (m + 1), |t| <= 0.1716; atanh(t) = t + t^3/3 + ... + t^9/9 leaves a
//     relative truncation error below t^10 / 11 < 2^-28.
//   y = s log2 x = k + f, k the nearest integer, |f| <= 1/2 (y - k is exact in float);
//   2^f = e^g, g = f ln 2, |g| <= 0.347: Taylor to g^7 leaves g^8 / 8! < 2^-27;
//   2^k is built in the exponent field.
//
// Accuracy (normal-float results, measured against std::pow in double by
// tests/packet_shading_test.cpp over x in [0, 1.5] and s in [0, 10^4]): relative error at
// most (4 + 3|y|) units of 2^-24. The |y| term is inherent in forming y in float: log2 x
// carries a few ulps of relative error, which s carries into y, and an error of one ulp of y
// becomes |y| ln 2 ulps of 2^y. For x <= 1, as in shading where x = max(0, r.v), the result
// 2^y is at most 1, and |y| 2^y <= 1 / (e ln 2) < 0.54, so the absolute error is below
// 6 * 2^-24 whatever the shininess.
//
// Exact cases, as std::pow: x^0 = 1 (0^0 included), 1^s = 1, 0^s = 0 for s > 0.
// Limits: results below 2^-126 flush to 0; y >= 127 gives +inf.

#include "dynrt/packet/simd.h"

#include <cstdint>
#include <limits>

namespace dynrt::packet::simd {

/// x^s lane by lane for finite x >= 0 and finite s >= 0 (see the accuracy note above). Every
/// operation is lane-wise IEEE float, so every lane width gives the same bits.
template <int W>
typename Lanes<W>::F pow(typename Lanes<W>::F x, typename Lanes<W>::F s) {
    using L = Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    const F one = L::splat(1.0f);

    // ---- log2 x = e + log2 m ----
    // A subnormal x is scaled by 2^24 first, so that its exponent field holds its exponent.
    const I subnormal = x < L::splat(0x1p-126f);
    const I bits = L::bits_of(L::select(subnormal, x * L::splat(0x1p24f), x));
    I e = ((bits >> 23) & L::splat(std::int32_t(0xff))) - L::splat(std::int32_t(127)) -
          (subnormal & L::splat(std::int32_t(24)));
    F m = L::float_of((bits & L::splat(std::int32_t(0x007fffff))) |
                      L::splat(std::int32_t(0x3f800000)));  // in [1, 2)
    const I above_sqrt2 = m > L::splat(1.41421356f);
    m = L::select(above_sqrt2, m * L::splat(0.5f), m);
    e = e - above_sqrt2;  // lanes are -1 where true
    const F t = (m - one) / (m + one);  // m - 1 is exact (Sterbenz)
    const F t2 = t * t;
    const F atanh_t =
        t * (one + t2 * (L::splat(1.0f / 3.0f) +
                         t2 * (L::splat(1.0f / 5.0f) +
                               t2 * (L::splat(1.0f / 7.0f) + t2 * L::splat(1.0f / 9.0f)))));
    const F log2_x = L::to_float(e) + atanh_t * L::splat(float(2.0 / 0.69314718055994530942));

    // ---- 2^y, y = s log2 x ----
    const F y = s * log2_x;
    const F y_clamped = L::select(y < L::splat(-127.0f), L::splat(-127.0f),
                                  L::select(y > L::splat(127.0f), L::splat(127.0f), y));
    const I k = L::truncate(y_clamped + L::select(y_clamped < L::splat(0.0f), L::splat(-0.5f),
                                                  L::splat(0.5f)));
    const F g = (y_clamped - L::to_float(k)) * L::splat(0.69314718f);
    const F exp_g =
        one + g * (one + g * (L::splat(1.0f / 2) +
                              g * (L::splat(1.0f / 6) +
                                   g * (L::splat(1.0f / 24) +
                                        g * (L::splat(1.0f / 120) +
                                             g * (L::splat(1.0f / 720) +
                                                  g * L::splat(1.0f / 5040)))))));
    // k in [-127, 127]: k = -127 makes an all-zero exponent field, i.e. 0.
    const F two_k = L::float_of((k + L::splat(std::int32_t(127))) << 23);
    F result = exp_g * two_k;
    result = L::select(y < L::splat(-126.0f), L::splat(0.0f), result);
    result = L::select(y >= L::splat(127.0f), L::splat(std::numeric_limits<float>::infinity()),
                       result);
    // 0^s: log2 0 came out finite (-151), so the exact answers are put in by hand.
    const F zero_to_s = L::select(s == L::splat(0.0f), one, L::splat(0.0f));
    return L::select(x == L::splat(0.0f), zero_to_s, result);
}

}  // namespace dynrt::packet::simd
