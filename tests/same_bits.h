#pragma once
// Bit-for-bit equality of floats, for the tests that check two paths give the very same
// numbers. One definition in a header: dynrt_tests compiles as unity batches, where two files'
// copies in one namespace collide as soon as a new file puts them in the same batch.

#include <bit>
#include <cstdint>

namespace dynrt::test {

/// Whether `a` and `b` have the same bits (so -0 differs from 0, and a NaN equals itself).
inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

}  // namespace dynrt::test
