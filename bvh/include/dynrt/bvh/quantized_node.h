#pragma once
// A wide node with its child boxes quantised to 8 bits per plane, relative to the node's own
// box (BuildConfig::quantized_nodes): half the bytes of a float node (128 instead of 256 for
// N = 8, 64 instead of 128 for N = 4), so twice the nodes per cache line and per byte of
// memory, for a few instructions per node to decode the boxes.
//
// The encoding follows Ylitie, Karras and Laine 2017, "Efficient Incoherent Ray Traversal on
// GPUs Through Compressed Wide BVHs" (section 3.1), as Embree's compressed nodes do too: per
// axis, an origin (the node box's lower corner) and a power-of-two scale 2^e, and per child
// plane an 8-bit q, decoded as origin + q * 2^e. q * 2^e is exact (an 8-bit integer times a
// power of two, kept below FLT_MAX), so the decode rounds once, with or without a fused
// multiply-add, on any ISA; and the encoder computes that same float for every q it picks,
// taking the lower planes down and the upper planes up until the decoded box holds the exact
// one. A decoded box is therefore never smaller than the exact box, however far from the
// origin it lies, and every ray the exact box passes, its decoded box passes: the slab test is
// monotone in each plane, and rounding is monotone. The traversal may visit more nodes; it
// finds the same hits bit for bit (ties go to the lower primitive index in every kernel, so
// the order of visits does not matter).
//
// A decoded child box may stick out of its parent's decoded box (each is rounded outwards from
// its own exact box on its own grid); traversal does not need nesting, only that each decoded
// box contains its triangles (validate checks that).

#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/ray.h"

#include <bit>
#include <cstdint>
#include <cstring>

namespace dynrt::bvh {

/// The smallest and largest scale exponent a quantised node uses. 255 * 2^119 is below FLT_MAX,
/// so q * 2^e never overflows; 2^-126 is the smallest normal float, so it is never flushed.
inline constexpr int kQuantizedExponentMin = -126;
inline constexpr int kQuantizedExponentMax = 119;

/// 2^exponent, built from its bits (exponent within the two bounds above).
__attribute__((always_inline)) inline float quantized_step(int exponent) {
    return std::bit_cast<float>(static_cast<std::uint32_t>(exponent + 127) << 23);
}

/// One node of an N-wide tree with quantised child boxes. child and blocks mean what they mean
/// in WideNode (an empty slot has blocks 0 and child kInvalidId).
template <int N>
struct alignas(64) QuantizedWideNode {
    static_assert(N == 4 || N == 8, "wide nodes are 4 or 8 wide");
    /// Per axis, the decoded planes' zero (the node box's lower corner)...
    float origin[3];
    /// ... and their step, 2^exponent.
    std::int8_t exponent[3];
    /// Bit i set when slot i holds a child: the decoded box of an empty slot may be hit (its
    /// planes are 0), so traversal masks the slots with this.
    std::uint8_t used;
    /// Child i's box on each axis, lo[i] and hi[i] steps above the origin; an axis's lower
    /// and upper planes side by side, decoded as one vector of 2N lanes where the ISA has
    /// them (AVX-512).
    struct AxisPlanes {
        std::uint8_t lo[N];
        std::uint8_t hi[N];
    } axis[3];
    std::uint32_t child[N];
    std::uint16_t blocks[N];

    bool is_empty(int i) const { return blocks[i] == 0 && child[i] == kInvalidId; }
    bool is_leaf(int i) const { return blocks[i] != 0; }
    /// 2^exponent[axis].
    __attribute__((always_inline)) float scale(int axis) const { return quantized_step(exponent[axis]); }
    /// Plane q on `axis`, as the traversal decodes it.
    __attribute__((always_inline)) float plane(int axis, std::uint8_t q) const {
        return origin[axis] + static_cast<float>(q) * scale(axis);
    }
    /// Child i's decoded box (the empty box for an empty slot). Inlined: packets decode the
    /// box of every child they pop.
    __attribute__((always_inline)) Aabb box(int i) const {
        if (is_empty(i)) return Aabb{};
        return Aabb{{plane(0, axis[0].lo[i]), plane(1, axis[1].lo[i]), plane(2, axis[2].lo[i])},
                    {plane(0, axis[0].hi[i]), plane(1, axis[1].hi[i]), plane(2, axis[2].hi[i])}};
    }
};
static_assert(sizeof(QuantizedWideNode<4>) == 64 && sizeof(QuantizedWideNode<8>) == 128);

/// An axis's 2N plane bytes and their floats, for N = 8 and N = 4.
typedef std::uint8_t PlaneBytes16 __attribute__((vector_size(16)));
typedef float PlaneFloats16 __attribute__((vector_size(64)));
typedef std::uint8_t PlaneBytes8 __attribute__((vector_size(8)));
typedef float PlaneFloats8 __attribute__((vector_size(32)));

/// Decodes axis `a` of `node` into its lower and upper planes' N-lane vectors.
template <class Q2, class F2, class Node, class F>
__attribute__((always_inline)) inline void decode_axis(const Node& node, int a, F& lo, F& hi) {
    static_assert(sizeof(Q2) == sizeof(node.axis[0]) && sizeof(F2) == 2 * sizeof(F));
    // x - (+0) lane-wise broadcasts (wide_simd.h's splat).
    const F2 scale = node.scale(a) - F2{};
    const F2 origin = node.origin[a] - F2{};
    Q2 q;
    std::memcpy(&q, &node.axis[a], sizeof q);
    // Bytes to 32-bit integers, then to floats: two vector instructions (vpmovzxbd,
    // vcvtdq2ps). Converted straight to float, GCC converts each byte on its own.
    typedef std::int32_t I2 __attribute__((vector_size(sizeof(F2))));
    const F2 planes = origin + __builtin_convertvector(__builtin_convertvector(q, I2), F2) * scale;
    std::memcpy(&lo, &planes, sizeof(F));
    std::memcpy(&hi, reinterpret_cast<const char*>(&planes) + sizeof(F), sizeof(F));
}

/// The child boxes of a node as N-lane vectors F (GCC/Clang vector extensions of N floats):
/// lo[axis] and hi[axis] lane i are child i's planes. A float node's are loaded; a quantised
/// node's decoded, the same floats as QuantizedWideNode::box.
template <class F, class Node>
__attribute__((always_inline)) inline void child_box_lanes(const Node& node, F lo[3], F hi[3]) {
    if constexpr (requires { node.lo_x; }) {
        const float* planes[6] = {node.lo_x, node.lo_y, node.lo_z, node.hi_x, node.hi_y, node.hi_z};
        for (int a = 0; a < 3; ++a) {
            std::memcpy(&lo[a], planes[a], sizeof(F));
            std::memcpy(&hi[a], planes[3 + a], sizeof(F));
        }
    } else {
        // Both planes of an axis at once: 2N lanes (one AVX-512 register for N = 8; the
        // compiler splits them where registers are narrower).
        static_assert(sizeof(F) == 32 || sizeof(F) == 16, "four or eight lanes");
        for (int a = 0; a < 3; ++a) {
            if constexpr (sizeof(F) == 32) {
                decode_axis<PlaneBytes16, PlaneFloats16>(node, a, lo[a], hi[a]);
            } else {
                decode_axis<PlaneBytes8, PlaneFloats8>(node, a, lo[a], hi[a]);
            }
        }
    }
}

/// The slots of `node` that hold a child, as bits: what a box test's lane mask is filtered by.
/// A float node's empty slots have the empty box, which no ray meets, so it needs no filter.
template <class Node>
inline std::uint32_t used_slots_filter(const Node& node) {
    if constexpr (requires { node.used; }) {
        return node.used;
    } else {
        return ~0u;
    }
}

}  // namespace dynrt::bvh
