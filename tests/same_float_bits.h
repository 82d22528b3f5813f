#pragma once
// Bit-for-bit float equality for the packet tests (packet_pinhole_test.cpp,
// packet_traversal_test.cpp), in one header: the unity build may put both files in one batch.

#include <bit>
#include <cstdint>

namespace dynrt::packet {

/// True when `a` and `b` have the same bits (so NaNs of one pattern compare equal, and 0 and
/// -0 do not).
inline bool same_bits(float a, float b) {
    return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

}  // namespace dynrt::packet
