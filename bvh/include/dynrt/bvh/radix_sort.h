#pragma once
// A parallel, stable LSD radix sort of 64-bit keys by a range of their bits, for keys that carry a
// code above and an index below (Morton-ordered primitives in the Morton builder, sorted rays
// in the renderer's secondary stage): 10 bits a pass, each pass a histogram per block of keys
// then a scatter (Satish, Harris and Garland 2009, "Designing Efficient Sorting Algorithms for
// Manycore GPUs", describe the blocked form).

#include <cstddef>
#include <cstdint>

namespace dynrt::bvh {

/// Sorts `keys[0, n)` by bits [first_bit, first_bit + bit_count) (within 0-63), keeping keys
/// equal there in their order, using `scratch` (room for n keys). Returns the buffer holding
/// the sorted keys: `keys` or `scratch`.
std::uint64_t* radix_sort_bits(std::uint64_t* keys, std::uint64_t* scratch, std::size_t n,
                               int first_bit, int bit_count);

}  // namespace dynrt::bvh
