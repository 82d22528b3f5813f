#pragma once
// The watertight ray/triangle test (Woop, Benthin and Wald 2013) on a block of four triangles
// in one SIMD pass: the arithmetic of watertight_kernel.h lane by lane, in the same order with
// the same roundings (the bvh library is compiled with -ffp-contract=off), so every lane's t,
// u and v are bit for bit what the single-triangle test computes. The double-precision
// fallback for edge functions that round to zero runs per lane, as rarely as in the scalar
// test.

#include "dynrt/bvh/watertight_intersector.h"
#include "dynrt/bvh/wide_bvh.h"

#include "watertight_kernel.h"

#include "wide_simd.h"

#include <cstdint>
#include <cstring>

namespace dynrt::bvh::detail {

/// What the block test leaves for the caller: per lane the distance and the two quantities
/// the barycentrics are divided from (u = bary_v / det, v = bary_w / det, computed only for a
/// hit that is kept).
struct BlockHits {
    using F = WideLanes<kBlockLanes>::F;
    F t, bary_v, bary_w, det;
    /// Lanes whose triangle is hit with tmin <= t <= tmax.
    std::uint32_t mask = 0;
};

/// The per-ray constants of the block test, broadcast once per ray rather than per block.
struct BlockRay {
    using F = WideLanes<kBlockLanes>::F;
    F org[3];
    F sx, sy, sz;
    int kx, ky, kz;

    explicit BlockRay(const WatertightRay& ray)
        : org{splat<kBlockLanes>(ray.org.x), splat<kBlockLanes>(ray.org.y),
              splat<kBlockLanes>(ray.org.z)},
          sx(splat<kBlockLanes>(ray.sx)), sy(splat<kBlockLanes>(ray.sy)),
          sz(splat<kBlockLanes>(ray.sz)), kx(ray.kx), ky(ray.ky), kz(ray.kz) {}
};

__attribute__((always_inline)) inline BlockHits watertight_block(const BlockRay& ray,
                                                                 const TriangleBlock& block,
                                                                 WideLanes<kBlockLanes>::F tmin,
                                                                 WideLanes<kBlockLanes>::F tmax) {
    using F = WideLanes<kBlockLanes>::F;
    using I = WideLanes<kBlockLanes>::I;
    F a[3], b[3], c[3];
    for (int axis = 0; axis < 3; ++axis) {
        a[axis] = load_lanes<kBlockLanes>(block.v0[axis]) - ray.org[axis];
        b[axis] = load_lanes<kBlockLanes>(block.v1[axis]) - ray.org[axis];
        c[axis] = load_lanes<kBlockLanes>(block.v2[axis]) - ray.org[axis];
    }
    const F sx = ray.sx;
    const F sy = ray.sy;
    const F ax = a[ray.kx] - sx * a[ray.kz];
    const F ay = a[ray.ky] - sy * a[ray.kz];
    const F bx = b[ray.kx] - sx * b[ray.kz];
    const F by = b[ray.ky] - sy * b[ray.kz];
    const F cx = c[ray.kx] - sx * c[ray.kz];
    const F cy = c[ray.ky] - sy * c[ray.kz];

    F u = cx * by - cy * bx;
    F v = ax * cy - ay * cx;
    F w = bx * ay - by * ax;

    static_assert(sizeof(block.prim) == sizeof(I));
    I prims;
    std::memcpy(&prims, block.prim, sizeof prims);
    const I valid = prims != splat<kBlockLanes>(static_cast<std::int32_t>(kInvalidId));
    const F zero = splat<kBlockLanes>(0.0f);
    std::uint32_t exact = lane_mask<kBlockLanes>(((u == zero) | (v == zero) | (w == zero)) & valid);
    // The scalar test's fallback, lane by lane.
    while (exact != 0) {
        const int lane = __builtin_ctz(exact);
        exact &= exact - 1;
        float lu, lv, lw;
        exact_edge_functions(ax[lane], ay[lane], bx[lane], by[lane], cx[lane], cy[lane], lu, lv, lw);
        u[lane] = lu;
        v[lane] = lv;
        w[lane] = lw;
    }

    const I outside = ((u < zero) | (v < zero) | (w < zero)) & ((u > zero) | (v > zero) | (w > zero));
    const F det = u + v + w;
    const F sz = ray.sz;
    const F az = sz * a[ray.kz];
    const F bz = sz * b[ray.kz];
    const F cz = sz * c[ray.kz];
    const F t_scaled = u * az + v * bz + w * cz;
    // Lanes with det == 0 divide by zero here; they are masked out below, and a float division
    // by zero is well defined (an infinity or NaN), never a trap.
    const F t = t_scaled / det;
    const I hit = valid & ~outside & (det != zero) & (t >= tmin) & (t <= tmax);
    BlockHits result;
    result.t = t;
    result.bary_v = v;
    result.bary_w = w;
    result.det = det;
    result.mask = lane_mask<kBlockLanes>(hit);
    return result;
}

}  // namespace dynrt::bvh::detail
