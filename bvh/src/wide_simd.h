#pragma once
// N-lane float and int vectors for the wide tree's box test (N = 4 or 8) and its four-lane
// triangle test, in GCC/Clang vector extensions like float4.h: plain operators that compile to
// SSE or AVX on x86 and to scalar code elsewhere. The one exception is the lane mask of a
// comparison, which has an x86 instruction the compiler does not find from a loop.

#include <cstdint>
#include <cstring>

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace dynrt::bvh::detail {

template <int N> struct WideLanes;

template <> struct WideLanes<4> {
    typedef float F __attribute__((vector_size(16)));
    typedef std::int32_t I __attribute__((vector_size(16)));
};
template <> struct WideLanes<8> {
    typedef float F __attribute__((vector_size(32)));
    typedef std::int32_t I __attribute__((vector_size(32)));
};

template <int N>
inline typename WideLanes<N>::F load_lanes(const float* p) {
    typename WideLanes<N>::F v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <int N>
inline typename WideLanes<N>::I load_lanes(const std::int32_t* p) {
    typename WideLanes<N>::I v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

/// All lanes x. Written as x - (+0) lane-wise, which GCC and Clang broadcast (a lane-by-lane
/// fill compiles to one insert per lane) and which is x exactly, -0 and NaN included.
template <int N>
inline typename WideLanes<N>::F splat(float x) {
    return x - typename WideLanes<N>::F{};
}

template <int N>
inline typename WideLanes<N>::I splat(std::int32_t x) {
    return x - typename WideLanes<N>::I{};
}

/// Bit i set where lane i of a comparison result (-1 true, 0 false) is true.
template <int N>
inline std::uint32_t lane_mask(typename WideLanes<N>::I m) {
#if defined(__AVX__)
    if constexpr (N == 8) {
        __m256 v;
        std::memcpy(&v, &m, sizeof v);
        return static_cast<std::uint32_t>(_mm256_movemask_ps(v));
    }
#endif
#if defined(__SSE__)
    if constexpr (N == 4) {
        __m128 v;
        std::memcpy(&v, &m, sizeof v);
        return static_cast<std::uint32_t>(_mm_movemask_ps(v));
    }
#endif
    std::uint32_t bits = 0;
    for (int i = 0; i < N; ++i) bits |= static_cast<std::uint32_t>(m[i] & 1) << i;
    return bits;
}

}  // namespace dynrt::bvh::detail
