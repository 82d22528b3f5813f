#include "dynrt/bvh/radix_sort.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace dynrt::bvh {

namespace {

constexpr int kRadixBits = 10;
constexpr std::uint32_t kBuckets = 1u << kRadixBits;
/// Keys per block of a pass: each block keeps a histogram of kBuckets counters (4 KB, in L1)
/// and scatters into kBuckets streams.
constexpr std::size_t kSortBlock = 32 * 1024;

}  // namespace

std::uint64_t* radix_sort_bits(std::uint64_t* keys, std::uint64_t* scratch, std::size_t n,
                               int first_bit, int bit_count) {
    const std::size_t blocks = (n + kSortBlock - 1) / kSortBlock;
    std::vector<std::uint32_t> counts(blocks * kBuckets);
    std::uint64_t* in = keys;
    std::uint64_t* out = scratch;
    for (int shift = first_bit; shift < first_bit + bit_count; shift += kRadixBits) {
        // The last pass's digit stops at the range's end.
        const int bits = std::min(kRadixBits, first_bit + bit_count - shift);
        const std::uint32_t mask = (1u << bits) - 1;
        const auto digit = [shift, mask](std::uint64_t key) {
            return static_cast<std::uint32_t>(key >> shift) & mask;
        };
        tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
            std::uint32_t* count = counts.data() + b * kBuckets;
            std::fill(count, count + kBuckets, 0u);
            const std::size_t end = std::min(n, (b + 1) * kSortBlock);
            for (std::size_t i = b * kSortBlock; i < end; ++i) ++count[digit(in[i])];
        });
        // Exclusive prefix over (digit, block): block b's keys of digit d go after every key
        // of a smaller digit and after block b' < b's keys of digit d.
        std::uint32_t sum = 0;
        for (std::uint32_t d = 0; d < kBuckets; ++d) {
            for (std::size_t b = 0; b < blocks; ++b) {
                const std::uint32_t c = counts[b * kBuckets + d];
                counts[b * kBuckets + d] = sum;
                sum += c;
            }
        }
        tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
            std::uint32_t* offset = counts.data() + b * kBuckets;
            const std::size_t end = std::min(n, (b + 1) * kSortBlock);
            for (std::size_t i = b * kSortBlock; i < end; ++i) {
                out[offset[digit(in[i])]++] = in[i];
            }
        });
        std::swap(in, out);
    }
    return in;
}

}  // namespace dynrt::bvh
