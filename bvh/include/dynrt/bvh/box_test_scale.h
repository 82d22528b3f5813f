#pragma once
// How far the conservative box tests grow a ray's far distance (Ize 2013, "Robust BVH Ray
// Traversal", JCGT 2(2)): with the reciprocal direction rounded and t = (plane - org) * inv_dir
// rounded twice more, each slab distance is within gamma(3) of the exact value, where
// gamma(n) = n u / (1 - n u) and u = 2^-24 is the unit roundoff. Growing the far distance by
// (1 + 2 gamma(3)) therefore never rejects a box the exact ray meets (for t >= 0, i.e. rays
// with tmin >= 0, which is every ray the engine makes). The single-ray traversals
// (bvh/src/robust_box_test.h) and the packet ones (packet/) use this one constant, so their box
// tests agree bit for bit.

#include <limits>

namespace dynrt::bvh {

constexpr float kUnitRoundoff = std::numeric_limits<float>::epsilon() * 0.5f;
constexpr float gamma_n(int n) { return n * kUnitRoundoff / (1.0f - n * kUnitRoundoff); }
constexpr float kFarScale = 1.0f + 2.0f * gamma_n(3);

}  // namespace dynrt::bvh
