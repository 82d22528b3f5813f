#pragma once
// Morton codes of points in a box (Morton 1966; Lauterbach et al. 2009, "Fast BVH Construction
// on GPUs", build trees over them): a point's cell on a 1024^3 grid over the box, its three
// 10-bit coordinates interleaved, so points close along the code are close in space. The Morton
// builder orders primitives by them; the renderer orders secondary rays by their origins'.

#include "dynrt/bvh/aabb.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>

namespace dynrt::bvh {

/// The 10 low bits of x spread to every third bit (bit i -> bit 3i).
inline std::uint32_t spread_bits(std::uint32_t x) {
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

/// Quantises points to the grid over a box and interleaves the axes into a 30-bit code.
struct MortonGrid {
    static constexpr int kBitsPerAxis = 10;

    glm::vec3 lo;
    glm::vec3 scale;

    explicit MortonGrid(const Aabb& box) : lo(box.lo) {
        const glm::vec3 extent = box.hi - box.lo;
        constexpr float kCells = float(1u << kBitsPerAxis);
        for (int axis = 0; axis < 3; ++axis) {
            // A flat axis (every point equal on it) gets cell 0 for all.
            scale[axis] = extent[axis] > 0.0f ? kCells * 0.99999f / extent[axis] : 0.0f;
        }
    }

    std::uint32_t code(const glm::vec3& c) const {
        std::uint32_t cell[3];
        for (int axis = 0; axis < 3; ++axis) {
            const float q = (c[axis] - lo[axis]) * scale[axis];
            // Clamped before the conversion: rounding may put the largest point a hair past
            // the last cell, and a point outside the box lands in its nearest cell (NaN in
            // cell 0).
            constexpr float kLast = float((1u << kBitsPerAxis) - 1);
            cell[axis] = static_cast<std::uint32_t>(q > 0.0f ? std::min(q, kLast) : 0.0f);
        }
        return spread_bits(cell[0]) | (spread_bits(cell[1]) << 1) | (spread_bits(cell[2]) << 2);
    }
};

}  // namespace dynrt::bvh
