#pragma once
// The conservative single-ray box test of the BVH traversals (Ize 2013, "Robust BVH Ray
// Traversal", JCGT 2(2)), shared by the triangle BVH (triangle_bvh.cpp) and the top level of
// the two-level BVH (two_level_bvh.cpp). Moved here unchanged from triangle_bvh.cpp: both must
// round exactly alike, so that a box containing another never rejects a ray the inner one's
// test accepts (the slab distances are monotone in the planes).

#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/box_test_scale.h"
#include "dynrt/bvh/ray.h"

#include <glm/vec3.hpp>

#include <cmath>
#include <limits>

namespace dynrt::bvh::detail {

// ---- Robust box test ------------------------------------------------------------------------
//
// The far distance grows by kFarScale (box_test_scale.h, Ize 2013). The same factor is applied
// to the ray's current tmax: a triangle whose watertight t equals the closest hit so far may lie
// exactly on the box's near face, and a rounded-up near distance must not hide it.
using bvh::kFarScale;

/// Per-ray constants of the box test.
//
// Zero direction components: inv_dir is then +-inf and a plane through the origin gives
// (plane - org) * inv_dir = 0 * inf = NaN. Every max/min below is written `x > acc ? x : acc`
// (resp. `<`), which keeps the accumulator when x is NaN, so such a slab simply does not
// constrain the interval. That is exact: a ray parallel to a slab and lying on its boundary
// plane is inside the closed slab for all t. A ray parallel to the slab and strictly outside
// gets +inf as near or -inf as far distance and misses, also exact. Components so small that
// 1/d overflows (|d| < 2^-128) behave as zero. A packet version must keep the NaN-ignoring
// operand order (x86 maxps/minps return their second operand when either is NaN).
struct BoxRay {
    glm::vec3 org;
    glm::vec3 inv_dir;

    explicit BoxRay(const Ray& ray)
        : org(ray.org), inv_dir(1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z) {}
};

/// The ray's octant: bit a set where direction component a is negative (or -0), so the near
/// plane on that axis is the box's `hi`. Traversal is instantiated per octant, which turns the
/// near/far plane choice into plain loads.
inline int octant_of(const glm::vec3& dir) {
    return (std::signbit(dir.x) ? 1 : 0) | (std::signbit(dir.y) ? 2 : 0) |
           (std::signbit(dir.z) ? 4 : 0);
}

/// Clips [near, far] (on entry the segment's tmin and tmax) by the six slab distances, in the
/// one order and NaN-ignoring form every box test of the bvh module uses, so they all round and
/// treat NaNs alike: on floats here, on SIMD vectors of distances in the wide tree's test.
template <class T>
inline void clip_to_slabs(T t0x, T t1x, T t0y, T t1y, T t0z, T t1z, T& near, T& far) {
    near = t0x > near ? t0x : near;
    near = t0y > near ? t0y : near;
    near = t0z > near ? t0z : near;
    far = t1x < far ? t1x : far;
    far = t1y < far ? t1y : far;
    far = t1z < far ? t1z : far;
}

/// True when the ray segment [tmin, tmax] may meet `box`; `tnear` gets the entry distance.
template <int kOctant>
inline bool hit_box(const Aabb& box, const BoxRay& r, float tmin, float tmax, float& tnear) {
    constexpr bool kNegX = (kOctant & 1) != 0;
    constexpr bool kNegY = (kOctant & 2) != 0;
    constexpr bool kNegZ = (kOctant & 4) != 0;
    const float t0x = ((kNegX ? box.hi.x : box.lo.x) - r.org.x) * r.inv_dir.x;
    const float t1x = ((kNegX ? box.lo.x : box.hi.x) - r.org.x) * r.inv_dir.x;
    const float t0y = ((kNegY ? box.hi.y : box.lo.y) - r.org.y) * r.inv_dir.y;
    const float t1y = ((kNegY ? box.lo.y : box.hi.y) - r.org.y) * r.inv_dir.y;
    const float t0z = ((kNegZ ? box.hi.z : box.lo.z) - r.org.z) * r.inv_dir.z;
    const float t1z = ((kNegZ ? box.lo.z : box.hi.z) - r.org.z) * r.inv_dir.z;
    float tn = tmin;
    float tf = tmax;
    clip_to_slabs(t0x, t1x, t0y, t1y, t0z, t1z, tn, tf);
    tnear = tn;
    return tn <= tf * kFarScale;
}

}  // namespace dynrt::bvh::detail
