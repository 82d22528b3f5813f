#pragma once
// The packet tracer's only SIMD vocabulary: float and int32 vectors of W lanes written with
// GCC/Clang vector extensions, so the kernels use plain operators (+, *, <, ?:) and never an
// intrinsic or an ISA name; the exceptions (a comparison as a bit mask, the square root) live
// here.
//
// Why a template on the lane width rather than one width fixed by a macro: the packet kernels
// are templates on W and the library instantiates both the machine's native width
// (kNativeLanes) and W = 1 in the same build. W = 1 compiles to scalar code, so the scalar
// fallback is not a second implementation that could drift: it is the same source, and the
// tests run every packet test through both widths on every machine. The native width comes
// from the ISA the build targets: 16 with AVX-512F, 8 with AVX2, 4 with SSE2 or NEON, else 1.
//
// Every min and max is written as `x < acc ? x : acc` (resp. `>`): a NaN in x keeps the
// accumulator. The single-ray box test relies on that order (bvh/src/triangle_bvh.cpp), and the
// packet box test must round and ignore NaNs exactly as it does.

#include <cstdint>
#include <cstring>
#include <utility>

#if defined(__AVX__) || defined(__SSE2__)
#include <immintrin.h>
#endif

namespace dynrt::packet::simd {

#if defined(__AVX512F__)
inline constexpr int kNativeLanes = 16;
#elif defined(__AVX2__)
inline constexpr int kNativeLanes = 8;
#elif defined(__SSE2__) || defined(__ARM_NEON)
inline constexpr int kNativeLanes = 4;
#else
inline constexpr int kNativeLanes = 1;
#endif

namespace detail {
// Vector types cannot be declared with a dependent vector_size, hence one specialisation each.
template <int W> struct VectorTypes;
template <> struct VectorTypes<1> {
    typedef float F __attribute__((vector_size(4)));
    typedef std::int32_t I __attribute__((vector_size(4)));
    typedef std::uint32_t U __attribute__((vector_size(4)));
};
template <> struct VectorTypes<4> {
    typedef float F __attribute__((vector_size(16)));
    typedef std::int32_t I __attribute__((vector_size(16)));
    typedef std::uint32_t U __attribute__((vector_size(16)));
};
template <> struct VectorTypes<8> {
    typedef float F __attribute__((vector_size(32)));
    typedef std::int32_t I __attribute__((vector_size(32)));
    typedef std::uint32_t U __attribute__((vector_size(32)));
};
template <> struct VectorTypes<16> {
    typedef float F __attribute__((vector_size(64)));
    typedef std::int32_t I __attribute__((vector_size(64)));
    typedef std::uint32_t U __attribute__((vector_size(64)));
};
}  // namespace detail

/// W lanes of float (F), int32 (I, also the type of comparison results: -1 true, 0 false) and
/// uint32 (U). All functions are lane-wise unless they say otherwise.
template <int W>
struct Lanes {
    static_assert(W == 1 || W == 4 || W == 8 || W == 16, "lane widths are 1, 4, 8 or 16");
    static constexpr int kWidth = W;
    using F = typename detail::VectorTypes<W>::F;
    using I = typename detail::VectorTypes<W>::I;
    using U = typename detail::VectorTypes<W>::U;
    /// The lane bits of one vector: W low bits.
    static constexpr std::uint32_t kAllBits = (1u << W) - 1u;

    /// Loads and stores of W consecutive elements; any alignment.
    static F load(const float* p) {
        F v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    static I load(const std::int32_t* p) {
        I v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    static U load(const std::uint32_t* p) {
        U v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    static void store(float* p, F v) { std::memcpy(p, &v, sizeof v); }
    static void store(std::int32_t* p, I v) { std::memcpy(p, &v, sizeof v); }
    static void store(std::uint32_t* p, U v) { std::memcpy(p, &v, sizeof v); }

    /// x in every lane. (Not `F{} + x`: 0 + -0 is +0, and the sign of a zero can reach a
    /// result's bits.)
    static F splat(float x) { return splat_lanes(x, std::make_index_sequence<W>{}); }
    static I splat(std::int32_t x) { return I{} + x; }
    static U splat(std::uint32_t x) { return U{} + x; }

    /// `mask ? a : b`; mask lanes must be -1 or 0 (comparison results).
    static F select(I mask, F a, F b) { return mask ? a : b; }
    static I select(I mask, I a, I b) { return mask ? a : b; }
    static U select(I mask, U a, U b) { return mask ? a : b; }

    /// NaN-ignoring accumulation: x where x < acc (resp. x > acc), else acc.
    static F min_into(F x, F acc) { return x < acc ? x : acc; }
    static F max_into(F x, F acc) { return x > acc ? x : acc; }

    /// Lane i of the mask (-1 or 0 lanes) as bit i of the result.
    static std::uint32_t bits(I mask) {
        if constexpr (W == 1) {
            return std::uint32_t(mask[0]) & 1u;
#if defined(__AVX512F__)
        } else if constexpr (W == 16) {
            return std::uint32_t(_mm512_cmplt_epi32_mask(__m512i(mask), _mm512_setzero_si512()));
#endif
#if defined(__AVX__)
        } else if constexpr (W == 8) {
            return std::uint32_t(_mm256_movemask_ps(__m256(mask)));
#endif
#if defined(__SSE2__)
        } else if constexpr (W == 4) {
            return std::uint32_t(_mm_movemask_ps(__m128(mask)));
#endif
        } else {
            std::uint32_t out = 0;
            for (int i = 0; i < W; ++i) out |= std::uint32_t(mask[i] < 0) << i;
            return out;
        }
    }

    /// Lane mask (-1 or 0 lanes) from bit i of `b`.
    static I from_bits(std::uint32_t b) {
        I lane_bit;
        for (int i = 0; i < W; ++i) lane_bit[i] = std::int32_t(1u << i);
        return (splat(std::int32_t(b)) & lane_bit) != 0;
    }

    /// Conversion toward zero, like a C++ float -> int32 cast (lanes must be in range).
    static I truncate(F v) { return __builtin_convertvector(v, I); }
    /// int32 -> float, rounded to nearest like a C++ cast.
    static F to_float(I v) { return __builtin_convertvector(v, F); }
    /// The bits of one type as the other (no conversion).
    static I bits_of(F v) { return I(v); }
    static F float_of(I v) { return F(v); }
    /// |v|: the sign bit cleared, like std::fabs.
    static F abs(F v) { return F(I(v) & splat(std::int32_t(0x7fffffff))); }

    /// Correctly rounded square root (IEEE, like std::sqrt).
    static F sqrt(F v) {
        if constexpr (W == 1) {
            return F{__builtin_sqrtf(v[0])};
#if defined(__AVX512F__)
        } else if constexpr (W == 16) {
            // The masked form with every lane set: the same result, and GCC 12 sees no
            // "maybe uninitialized" pass-through operand (_mm512_sqrt_ps's _mm512_undefined_ps).
            return F(_mm512_mask_sqrt_ps(__m512(v), __mmask16(0xffff), __m512(v)));
#endif
#if defined(__AVX__)
        } else if constexpr (W == 8) {
            return F(_mm256_sqrt_ps(__m256(v)));
#endif
#if defined(__SSE2__)
        } else if constexpr (W == 4) {
            return F(_mm_sqrt_ps(__m128(v)));
#endif
        } else {
            F out;
            for (int i = 0; i < W; ++i) out[i] = __builtin_sqrtf(v[i]);
            return out;
        }
    }

    /// Rounded toward minus infinity, like std::floor (lanes must be within +-2^31).
    static F floor(F v) {
        const F toward_zero = to_float(truncate(v));
        return select(toward_zero > v, toward_zero - splat(1.0f), toward_zero);
    }

    /// base[index[i]] in lane i (indices non-negative and in bounds): one gather instruction
    /// where the ISA has one, else W loads.
    static U gather(const std::uint32_t* base, I index) {
#if defined(__AVX512F__)
        // The masked forms with every lane set, as in sqrt: GCC 12 sees no uninitialised
        // pass-through operand.
        if constexpr (W == 16) {
            return U(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), __mmask16(0xffff), __m512i(index), base, 4));
        }
#endif
#if defined(__AVX2__)
        if constexpr (W == 8) {
            return U(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), __m256i(index), 4));
        }
#endif
        std::uint32_t values[W];
        for (int i = 0; i < W; ++i) values[i] = base[index[i]];
        return load(values);
    }
    static F gather(const float* base, I index) {
#if defined(__AVX512F__)
        if constexpr (W == 16) {
            return F(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), __mmask16(0xffff), __m512i(index), base, 4));
        }
#endif
#if defined(__AVX2__)
        if constexpr (W == 8) return F(_mm256_i32gather_ps(base, __m256i(index), 4));
#endif
        float values[W];
        for (int i = 0; i < W; ++i) values[i] = base[index[i]];
        return load(values);
    }

    /// table[index[i]] in lane i from a table of 16 (indices in [0, 16)): a permutation within
    /// registers where the ISA has one (AVX-512's vpermd, AVX2's two-source shuffle), no
    /// memory access per lane.
    static I table16(const std::int32_t (&table)[16], I index) {
        if constexpr (W == 16) {
            I all;
            std::memcpy(&all, table, sizeof all);
            return __builtin_shuffle(all, index);
        } else if constexpr (W == 8) {
            I low, high;
            std::memcpy(&low, table, sizeof low);
            std::memcpy(&high, table + 8, sizeof high);
            return __builtin_shuffle(low, high, index);
        } else {
            std::int32_t values[W];
            for (int i = 0; i < W; ++i) values[i] = table[index[i]];
            return load(values);
        }
    }

    static F table16(const float (&table)[16], I index) {
        std::int32_t bits[16];
        std::memcpy(bits, table, sizeof bits);
        return float_of(table16(bits, index));
    }

    /// Horizontal reductions, for NaN-free lanes: halves folded onto each other.
    static float reduce_min(F v) {
        if constexpr (W >= 16) v = min_into(fold<8>(v), v);
        if constexpr (W >= 8) v = min_into(fold<4>(v), v);
        if constexpr (W >= 4) v = min_into(fold<2>(v), v);
        if constexpr (W >= 2) v = min_into(fold<1>(v), v);
        return v[0];
    }
    static float reduce_max(F v) {
        if constexpr (W >= 16) v = max_into(fold<8>(v), v);
        if constexpr (W >= 8) v = max_into(fold<4>(v), v);
        if constexpr (W >= 4) v = max_into(fold<2>(v), v);
        if constexpr (W >= 2) v = max_into(fold<1>(v), v);
        return v[0];
    }

private:
    template <std::size_t... kLane>
    static F splat_lanes(float x, std::index_sequence<kLane...>) {
        return F{((void)kLane, x)...};
    }

    /// Lane i gets lane i + k (lane i - k for the upper lanes), as an index shuffle.
    template <int k>
    static F fold(F v) {
        I index;
        for (int i = 0; i < W; ++i) index[i] = (i ^ k);
        return __builtin_shuffle(v, index);
    }

public:
};

}  // namespace dynrt::packet::simd
