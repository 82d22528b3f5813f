#pragma once
// Four-lane float and int vectors for the builder's inner loops (binning and partitioning) and
// the traversal's two-box test, written with GCC/Clang vector extensions: plain C++ operators
// that compile to SSE/AVX on x86 and to NEON or scalar code elsewhere, so there are no
// intrinsics and no ISA names. This is the only place the bvh module spells out SIMD. Where a
// vector holds a point or box corner, lane 3 is a don't-care lane.

#include <cstdint>
#include <cstring>

namespace dynrt::bvh::detail {

using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

/// Unaligned load of four floats (the fourth is whatever follows the three we want).
inline Float4 load4(const void* p) {
    Float4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

/// Lane-wise `a < b ? a : b`: returns b where either is NaN, like x86 minps.
inline Float4 min4(Float4 a, Float4 b) { return a < b ? a : b; }
/// Lane-wise `a > b ? a : b`: returns b where either is NaN, like x86 maxps.
inline Float4 max4(Float4 a, Float4 b) { return a > b ? a : b; }

inline Float4 splat4(float x) { return Float4{x, x, x, x}; }

/// Truncation towards zero; lanes must be in int range.
inline Int4 truncate4(Float4 v) { return __builtin_convertvector(v, Int4); }

/// The low bytes of the four lanes packed into one integer (lane 0 lowest); lanes must be in
/// [0, 255].
inline std::uint32_t pack_low_bytes(Int4 v) {
    using Byte16 = unsigned char __attribute__((vector_size(16)));
    using UInt4 = std::uint32_t __attribute__((vector_size(16)));
    // Casts between vector types of one size reinterpret the bits (no conversion).
    const Byte16 bytes = (Byte16)v;
    const Byte16 picked =
        __builtin_shuffle(bytes, Byte16{0, 4, 8, 12, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    return ((UInt4)picked)[0];
}

}  // namespace dynrt::bvh::detail
