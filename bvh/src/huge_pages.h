#pragma once
// Asks the kernel to back a large buffer with transparent huge pages. A 1M-triangle build
// touches over 100 MB of fresh memory; with 4 KB pages, the page faults (and the kernel's
// zeroing behind them) took more than a tenth of the build time (Linux 6.1, THP "madvise").

#include <cstddef>
#include <cstdint>
#include <memory>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace dynrt::bvh::detail {

#if defined(__linux__)
/// Gives `advice` to the kernel for the whole `align`-byte pages inside [p, p + bytes) (none
/// for a range that holds no whole page).
inline void advise_whole_pages(const void* p, std::size_t bytes, std::uintptr_t align, int advice) {
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + align - 1) & ~(align - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(align - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, advice);
}
#endif

/// Advises huge pages for the whole 2 MB pages inside [p, p + bytes). A hint only: does
/// nothing for small buffers, on systems without the feature, or when the kernel declines.
/// Call it before the buffer is first written, so the first touch already faults huge pages.
inline void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    advise_whole_pages(p, bytes, std::uintptr_t{2} << 20, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

/// Hands the whole pages inside [p, p + bytes) back to the system: they read as zeros after,
/// and are resident again only if written. For scratch a builder has read for the last time,
/// while the rest of its block is still in use.
inline void release_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
    advise_whole_pages(p, bytes, 4096, MADV_DONTNEED);
#else
    (void)p;
    (void)bytes;
#endif
}

/// Allocates storage for `count` trivially constructible objects, uninitialised, with huge
/// pages advised.
template <class T>
std::unique_ptr<T[]> make_uninitialized_buffer(std::size_t count) {
    auto buffer = std::make_unique_for_overwrite<T[]>(count);
    advise_huge_pages(buffer.get(), count * sizeof(T));
    return buffer;
}

/// Reserves room for `count` elements in `v`, advising huge pages for fresh storage before any
/// element is constructed.
template <class Vector>
void reserve_with_huge_pages(Vector& v, std::size_t count) {
    if (count > v.capacity()) {
        Vector fresh;
        fresh.reserve(count);
        advise_huge_pages(fresh.data(), count * sizeof(typename Vector::value_type));
        fresh.insert(fresh.end(), v.begin(), v.end());
        v.swap(fresh);
    }
}

/// Resizes `v` to `count` elements, advising huge pages for fresh storage before the elements
/// are constructed.
template <class Vector>
void resize_with_huge_pages(Vector& v, std::size_t count) {
    if (count > v.capacity()) {
        Vector fresh;
        fresh.reserve(count);
        advise_huge_pages(fresh.data(), count * sizeof(typename Vector::value_type));
        v.swap(fresh);
    }
    v.resize(count);
}

}  // namespace dynrt::bvh::detail
