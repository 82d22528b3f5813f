#pragma once
// Bit-for-bit equality of floats and buffers, for the tests that require a fast path to give
// exactly what another gives (not merely close values). One definition for every test file:
// dynrt_tests is built as unity batches, where two files' same-named helpers would collide.

#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

namespace dynrt::test {

inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

/// Same size and the same bytes; T is trivially copyable (floats, ids, glm vectors).
template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace dynrt::test
