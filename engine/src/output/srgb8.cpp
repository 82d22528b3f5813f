#include "srgb8.h"

#include "srgb.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <vector>

namespace dynrt {

namespace {

/// The float path being replaced, for one value.
std::uint8_t srgb8_by_pow(float linear) {
    return std::uint8_t(std::lround(srgb_encode(linear) * 255.0f));
}

constexpr std::uint32_t kOneBits = 0x3f800000u;  // 1.0f
// Buckets of 2^15 float bit patterns: 1/256 of a binade, under one code step even where the
// curve is steepest (near 1: about 0.22 codes per bucket), so the walk below is short.
constexpr int kBucketShift = 15;

class Srgb8Table {
public:
    Srgb8Table() {
        // edge_[k]: the bits of the smallest float in [0, 1] that encodes to k or more.
        edge_[0] = 0;
        for (int k = 1; k < 256; ++k) {
            std::uint32_t lo = edge_[std::size_t(k - 1)], hi = kOneBits;
            while (lo < hi) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                if (srgb8_by_pow(std::bit_cast<float>(mid)) >= k) {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            edge_[std::size_t(k)] = lo;
        }
        edge_[256] = ~0u;  // no code past 255
        bucket_.resize((kOneBits >> kBucketShift) + 1);
        for (std::size_t b = 0; b < bucket_.size(); ++b) {
            bucket_[b] = srgb8_by_pow(std::bit_cast<float>(std::uint32_t(b << kBucketShift)));
        }
    }

    std::uint8_t encode(float linear) const {
        // Negative values and NaN encode as 0, values past 1 as 255 (as the clamp does).
        if (!(linear > 0.0f)) return 0;
        if (linear >= 1.0f) return 255;
        const std::uint32_t bits = std::bit_cast<std::uint32_t>(linear);
        unsigned code = bucket_[bits >> kBucketShift];
        while (bits >= edge_[code + 1]) ++code;
        return std::uint8_t(code);
    }

private:
    std::array<std::uint32_t, 257> edge_{};
    std::vector<std::uint8_t> bucket_;
};

const Srgb8Table& table() {
    static const Srgb8Table t;
    return t;
}

}  // namespace

std::uint8_t srgb8_encode(float linear) { return table().encode(linear); }

void encode_srgb8(std::span<const glm::vec3> pixels, std::uint8_t* out) {
    const Srgb8Table& t = table();
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        out[3 * i + 0] = t.encode(pixels[i].x);
        out[3 * i + 1] = t.encode(pixels[i].y);
        out[3 * i + 2] = t.encode(pixels[i].z);
    }
}

}  // namespace dynrt
