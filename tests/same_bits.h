#pragma once
// Bit-for-bit float comparison, shared by the test files that need it (they compile in unity
// batches, where two definitions of one helper collide).

#include <bit>
#include <cstdint>

namespace dynrt::test {

/// True when `a` and `b` have the same bits (so +0 and -0 differ, and a NaN equals itself).
inline bool same_bits(float a, float b) {
    return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

}  // namespace dynrt::test
