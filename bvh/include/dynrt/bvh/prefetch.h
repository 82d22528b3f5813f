#pragma once
// A software prefetch that the compiler keeps.

namespace dynrt::bvh {

/// Asks the CPU to start loading the cache line holding `p` (a hint: nothing is read, and an
/// address outside any object is harmless).
///
/// Not a bare __builtin_prefetch: GCC 12 deletes those as dead code in some functions, where
/// the address is computed for the prefetch alone (every prefetch in the wide refit and in both
/// packet traversals was gone from the objects, found by counting prefetcht0 instructions).
/// The empty asm that takes the address makes it live, and the prefetch stays.
inline void prefetch_line(const void* p) {
    __builtin_prefetch(p);
    asm volatile("" : : "r"(p));
}

}  // namespace dynrt::bvh
