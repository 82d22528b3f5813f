#pragma once
// The per-lane kernels of the packet tracers (packet_traversal.cpp on the binary tree,
// wide_packet_traversal.cpp on the wide tree): the box test of a SIMD chunk of rays, the
// early miss of a whole packet from interval bounds, the watertight triangle test of a chunk,
// and the leaf-level vertex culling of Reshetov 2007, "Faster Ray Packets - Triangle
// Intersection through Vertex Culling".
//
// ---- Why the results equal the single-ray tracer's, bit for bit ----
// * Box tests: per lane the very arithmetic of bvh/src/triangle_bvh.cpp (Ize 2013): the same
//   subtractions, products, NaN-ignoring max/min chains in the same order and the same
//   (1 + 2 gamma(3)) growth of the far distance. Shortcuts that broadcast a common near plane or
//   (plane - origin) compute the same values, since the origin bits are identical.
// * Triangle tests: per lane the arithmetic of bvh/src/watertight_kernel.h, including the
//   double-precision fallback for edge functions that round to zero, with the same operation
//   order (-ffp-contract=off keeps every product rounded, in vectors too).
// * Ties: both tracers keep, among the hits at the smallest t, the lowest primitive index, so
//   the order in which leaves are visited does not matter; no node is culled whose entry
//   distance equals the current hit (the comparisons are <=, as in the single-ray tracer).
// * Every skip is conservative with respect to the float tests above, not only to exact
//   geometry: rounding is monotone, so evaluating the same float expression on the bounds of
//   its inputs bounds its result over all lanes. The early miss evaluates each slab distance
//   (plane - org) * inv at the corners of the lanes' origin and reciprocal-direction intervals;
//   the beam-plane and near/far stages do the same for the watertight test's sheared vertex
//   coordinates a[kx] - sx * a[kz] and sz * a[kz]. The watertight test decides inside/outside
//   exactly for those float coordinates (its edge-function signs are exact, with the double
//   fallback for zeros), so a ray whose sheared triangle lies strictly on one side of its
//   origin cannot hit. The edge stage, evaluated in double, keeps a margin that covers the
//   rounding of the sheared coordinates (derivation at triangle_edges_cull).
//   The arguments assume no underflow: coordinates relative to the ray origin above ~1e-18 in
//   magnitude, the same range in which the watertight test's own fallback is exact.

#include "packet_work.h"

#include "dynrt/bvh/box_test_scale.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/packet/packet_traversal.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dynrt::packet::detail {


// The single-ray box test's growth of far distances (dynrt/bvh/box_test_scale.h, Ize 2013): the
// same constant, so that the box tests agree bit for bit.
using bvh::kFarScale;

// ---- Box tests ------------------------------------------------------------------------------

/// How the per-lane box test gets its near and far planes: per lane from the direction signs
/// (kGeneral), common to the packet (kOctant), or common with a common origin, so that
/// plane - origin is one scalar (kOctantOrigin).
enum class BoxMode { kGeneral, kOctant, kOctantOrigin };

/// One node's planes for a packet with a common octant: near and far plane per axis (box.lo
/// or box.hi by the direction's sign), and the same minus the common origin.
struct NodePlanes {
    float near[3], far[3];
    float near_rel[3], far_rel[3];

    __attribute__((always_inline)) NodePlanes(const bvh::Aabb& box, const Beam& beam) {
        float corners[6];  // lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        std::memcpy(corners, &box, sizeof corners);
        for (int a = 0; a < 3; ++a) {
            near[a] = corners[beam.near_index[a]];
            far[a] = corners[beam.far_index[a]];
            near_rel[a] = near[a] - beam.origin[a];
            far_rel[a] = far[a] - beam.origin[a];
        }
    }
};
static_assert(sizeof(bvh::Aabb) == 6 * sizeof(float));

/// The Ize box test for the lanes of chunk `c`; bit i set where lane c W + i hits `box`.
template <int W, BoxMode M>
inline std::uint32_t box_chunk(const Work& w, const bvh::Aabb& box, const NodePlanes& np, int c) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    const int base = c * W;
    F tn = L::load(w.tnear + base);
    F tf = L::load(w.tfar + base);
    for (int a = 0; a < 3; ++a) {
        const F inv = L::load(w.inv[a] + base);
        F t0, t1;
        if constexpr (M == BoxMode::kOctantOrigin) {
            t0 = L::splat(np.near_rel[a]) * inv;
            t1 = L::splat(np.far_rel[a]) * inv;
        } else if constexpr (M == BoxMode::kOctant) {
            const F o = L::load(w.org[a] + base);
            t0 = (L::splat(np.near[a]) - o) * inv;
            t1 = (L::splat(np.far[a]) - o) * inv;
        } else {
            const F o = L::load(w.org[a] + base);
            const F t_lo = (L::splat(box.lo[a]) - o) * inv;
            const F t_hi = (L::splat(box.hi[a]) - o) * inv;
            const I negative = inv < L::splat(0.0f);
            t0 = L::select(negative, t_hi, t_lo);
            t1 = L::select(negative, t_lo, t_hi);
        }
        tn = L::max_into(t0, tn);
        tf = L::min_into(t1, tf);
    }
    return L::bits(tn <= tf * L::splat(kFarScale));
}

/// x in every lane of V, a float (one box) or a SIMD vector of floats (one box per lane):
/// x - 0 is x exactly, -0 and NaN included.
template <class V>
inline V broadcast(float x) {
    return x - V{};
}

/// The box test of one lane (the early-hit ray) against boxes with planes lo[axis], hi[axis]:
/// one box (V = float, a bool back) or one per SIMD lane (a lane mask back), the same
/// arithmetic either way.
template <class V>
inline auto lane_hits_boxes(const Work& w, int lane, const V (&lo)[3], const V (&hi)[3]) {
    V tn = broadcast<V>(w.tnear[lane]);
    V tf = broadcast<V>(w.tfar[lane]);
    for (int a = 0; a < 3; ++a) {
        const float inv = w.inv[a][lane];
        const V o = broadcast<V>(w.org[a][lane]);
        const bool negative = inv < 0.0f;
        const V t0 = ((negative ? hi[a] : lo[a]) - o) * broadcast<V>(inv);
        const V t1 = ((negative ? lo[a] : hi[a]) - o) * broadcast<V>(inv);
        tn = t0 > tn ? t0 : tn;
        tf = t1 < tf ? t1 : tf;
    }
    return tn <= tf * broadcast<V>(kFarScale);
}

/// lane_hits_boxes for one box.
inline bool lane_hits_box(const Work& w, const bvh::Aabb& box, int lane) {
    const float lo[3] = {box.lo.x, box.lo.y, box.lo.z};
    const float hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    return lane_hits_boxes<float>(w, lane, lo, hi);
}

/// Early miss: true only if no active lane's box test can hit. Lane i's entry distance is the
/// NaN-ignoring max of tmin_i and (near - org_i) * inv_i over the axes; on an axis with a
/// common sign and finite reciprocals the latter is never NaN and, rounding being monotone, is
/// at least the smallest product at the corners of [near - org_hi, near - org_lo] x
/// [inv_lo, inv_hi]. Likewise the exit distance is at most the largest such product for the
/// far plane, so entry_lo > exit_hi * kFarScale rules out every lane. Axes without valid
/// intervals are simply left out, which only weakens the bound. `tfar_hi` bounds the current
/// tmax of the lanes concerned (those of the node's range). `near` and `far` are the planes
/// for each axis's common sign (on axes whose sign is not common the interval is not valid
/// anyway), for one box (V = float, a bool back) or one per SIMD lane (a lane mask back).
template <class V>
inline auto beam_misses_boxes(const Beam& b, const V (&near)[3], const V (&far)[3], float tfar_hi) {
    // std::min / std::max's order: NaN-ignoring in the same way.
    const auto min = [](V x, V y) { return y < x ? y : x; };
    const auto max = [](V x, V y) { return x < y ? y : x; };
    V tn = broadcast<V>(b.tnear_lo);
    V tf = broadcast<V>(tfar_hi);
    for (int a = 0; a < 3; ++a) {
        if (!b.interval_ok[a]) continue;
        const V i_lo = broadcast<V>(b.inv_lo[a]), i_hi = broadcast<V>(b.inv_hi[a]);
        V t0, t1;
        if (b.common_origin) {
            const V n = near[a] - broadcast<V>(b.origin[a]), f = far[a] - broadcast<V>(b.origin[a]);
            t0 = min(n * i_lo, n * i_hi);
            t1 = max(f * i_lo, f * i_hi);
        } else {
            const V o_lo = broadcast<V>(b.org_lo[a]), o_hi = broadcast<V>(b.org_hi[a]);
            const V n_lo = near[a] - o_hi, n_hi = near[a] - o_lo;
            const V f_lo = far[a] - o_hi, f_hi = far[a] - o_lo;
            t0 = min(min(n_lo * i_lo, n_lo * i_hi), min(n_hi * i_lo, n_hi * i_hi));
            t1 = max(max(f_lo * i_lo, f_lo * i_hi), max(f_hi * i_lo, f_hi * i_hi));
        }
        tn = max(tn, t0);
        tf = min(tf, t1);
    }
    return tn > tf * broadcast<V>(kFarScale);
}

/// beam_misses_boxes for one node's planes.
inline bool beam_misses(const Beam& b, const NodePlanes& np, float tfar_hi) {
    return beam_misses_boxes<float>(b, np.near, np.far, tfar_hi);
}

// ---- Triangle tests -------------------------------------------------------------------------

/// How lanes get the watertight test's vertex coordinates: the packet shares origin and axis
/// permutation, so a[k] = v[k] - org[k] is one scalar per triangle (kRelative); it shares the
/// permutation only, so v[k] is a scalar and org[k] per lane (kPermuted); or each lane permutes
/// on its own (kGeneral).
enum class TriMode { kRelative, kPermuted, kGeneral };

/// One leaf triangle, prepared for the packet: coordinates as the TriMode needs them (three per
/// vertex), and its primitive index.
struct TriData {
    float p[9];
    std::uint32_t prim;
};

/// The per-lane constants of the watertight test for one chunk.
template <int W>
struct ChunkRays {
    using L = simd::Lanes<W>;
    typename L::F sx, sy, sz;
    typename L::F o0, o1, o2;  ///< origin: permuted (kPermuted) or x, y, z (kGeneral)
    typename L::I kx0, kx1, ky0, ky1, kz0, kz1;  ///< kGeneral: lane's axis == 0, == 1

    ChunkRays(const Work& w, const Beam& beam, TriMode mode, int c) {
        const int base = c * W;
        sx = L::load(w.shear[0] + base);
        sy = L::load(w.shear[1] + base);
        sz = L::load(w.shear[2] + base);
        if (mode == TriMode::kPermuted) {
            o0 = L::load(w.org[beam.kx] + base);
            o1 = L::load(w.org[beam.ky] + base);
            o2 = L::load(w.org[beam.kz] + base);
        } else if (mode == TriMode::kGeneral) {
            o0 = L::load(w.org[0] + base);
            o1 = L::load(w.org[1] + base);
            o2 = L::load(w.org[2] + base);
            const typename L::I kx = L::load(w.perm[0] + base);
            const typename L::I ky = L::load(w.perm[1] + base);
            const typename L::I kz = L::load(w.perm[2] + base);
            kx0 = kx == 0;
            kx1 = kx == 1;
            ky0 = ky == 0;
            ky1 = ky == 1;
            kz0 = kz == 0;
            kz1 = kz == 1;
        }
    }
};

/// The watertight test (bvh/src/watertight_kernel.h) for the lanes of one chunk against one
/// triangle, operation for operation. Returns the lanes that hit within [tnear, tfar] (only
/// lanes in `lanes` are guaranteed meaningful); t, det and the scaled barycentrics v, w (so
/// u = v / det, v = w / det) come back for the caller to keep.
template <int W, TriMode M>
inline typename simd::Lanes<W>::I watertight_chunk(const ChunkRays<W>& r, const TriData& tri,
                                                   typename simd::Lanes<W>::F tnear,
                                                   typename simd::Lanes<W>::F tfar,
                                                   std::uint32_t lanes,
                                                   typename simd::Lanes<W>::F& t_out,
                                                   typename simd::Lanes<W>::F& det_out,
                                                   typename simd::Lanes<W>::F& v_out,
                                                   typename simd::Lanes<W>::F& w_out) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    // a[k], b[k], c[k]: vertices relative to the origin, in the lane's axis order kx, ky, kz.
    F a[3], b[3], c[3];
    F* const out[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
        const float* p = tri.p + 3 * i;
        if constexpr (M == TriMode::kRelative) {
            out[i][0] = L::splat(p[0]);
            out[i][1] = L::splat(p[1]);
            out[i][2] = L::splat(p[2]);
        } else if constexpr (M == TriMode::kPermuted) {
            out[i][0] = L::splat(p[0]) - r.o0;
            out[i][1] = L::splat(p[1]) - r.o1;
            out[i][2] = L::splat(p[2]) - r.o2;
        } else {
            const F x = L::splat(p[0]) - r.o0;
            const F y = L::splat(p[1]) - r.o1;
            const F z = L::splat(p[2]) - r.o2;
            out[i][0] = L::select(r.kx0, x, L::select(r.kx1, y, z));
            out[i][1] = L::select(r.ky0, x, L::select(r.ky1, y, z));
            out[i][2] = L::select(r.kz0, x, L::select(r.kz1, y, z));
        }
    }
    // Shear so that the ray is the +z axis.
    const F ax = a[0] - r.sx * a[2];
    const F ay = a[1] - r.sy * a[2];
    const F bx = b[0] - r.sx * b[2];
    const F by = b[1] - r.sy * b[2];
    const F cx = c[0] - r.sx * c[2];
    const F cy = c[1] - r.sy * c[2];

    F u = cx * by - cy * bx;
    F v = ax * cy - ay * cx;
    F w = bx * ay - by * ax;

    const F zero = L::splat(0.0f);
    std::uint32_t zeros = L::bits((u == zero) | (v == zero) | (w == zero)) & lanes;
    while (zeros != 0) {
        // The double-precision fallback, lane by lane (rare: rays through edges and vertices).
        const int i = std::countr_zero(zeros);
        zeros &= zeros - 1;
        const double cxby = static_cast<double>(cx[i]) * static_cast<double>(by[i]);
        const double cybx = static_cast<double>(cy[i]) * static_cast<double>(bx[i]);
        u[i] = static_cast<float>(cxby - cybx);
        const double axcy = static_cast<double>(ax[i]) * static_cast<double>(cy[i]);
        const double aycx = static_cast<double>(ay[i]) * static_cast<double>(cx[i]);
        v[i] = static_cast<float>(axcy - aycx);
        const double bxay = static_cast<double>(bx[i]) * static_cast<double>(ay[i]);
        const double byax = static_cast<double>(by[i]) * static_cast<double>(ax[i]);
        w[i] = static_cast<float>(bxay - byax);
    }

    const I negative = (u < zero) | (v < zero) | (w < zero);
    const I positive = (u > zero) | (v > zero) | (w > zero);
    const F det = u + v + w;
    const F az = r.sz * a[2];
    const F bz = r.sz * b[2];
    const F cz = r.sz * c[2];
    const F t_scaled = u * az + v * bz + w * cz;
    const F t = t_scaled / det;
    t_out = t;
    det_out = det;
    v_out = v;
    w_out = w;
    return ~(negative & positive) & (det != zero) & (t >= tnear) & (t <= tfar);
}

// ---- Leaf culling (Reshetov 2007), against the beam of the rays tested at the leaf ---------

/// Bounds over the lanes to be tested at one leaf of a packet with a common origin and axis
/// permutation: their shear constants and t intervals.
struct LeafBeam {
    float s_lo[3], s_hi[3];  ///< sx, sy, sz
    float tnear_lo, tfar_hi;
};

template <int W>
void compute_leaf_beam(const Work& w, const std::uint16_t* chunks, const std::uint32_t* bits,
                       int n, LeafBeam& lb) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    const F inf = L::splat(kInf), minus_inf = L::splat(-kInf);
    F s_lo[3] = {inf, inf, inf}, s_hi[3] = {minus_inf, minus_inf, minus_inf};
    F tn = inf, tf = minus_inf;
    for (int i = 0; i < n; ++i) {
        const int base = chunks[i] * W;
        const I m = L::from_bits(bits[i]);
        for (int a = 0; a < 3; ++a) {
            const F s = L::load(w.shear[a] + base);
            s_lo[a] = L::min_into(L::select(m, s, inf), s_lo[a]);
            s_hi[a] = L::max_into(L::select(m, s, minus_inf), s_hi[a]);
        }
        tn = L::min_into(L::select(m, L::load(w.tnear + base), inf), tn);
        tf = L::max_into(L::select(m, L::load(w.tfar + base), minus_inf), tf);
    }
    for (int a = 0; a < 3; ++a) {
        lb.s_lo[a] = L::reduce_min(s_lo[a]);
        lb.s_hi[a] = L::reduce_max(s_hi[a]);
    }
    lb.tnear_lo = L::reduce_min(tn);
    lb.tfar_hi = L::reduce_max(tf);
}

enum class Verdict { kTest, kBeamPlanes, kTriangleEdges, kNearFar };

/// Smallest and largest of fl(x * y) over x in [x_lo, x_hi], y in [y_lo, y_hi]: the exact
/// product is bilinear, so its extremes are at corners, and rounding keeps their order.
inline void product_bounds(float x_lo, float x_hi, float y_lo, float y_hi, float& lo, float& hi) {
    const float p0 = x_lo * y_lo, p1 = x_lo * y_hi, p2 = x_hi * y_lo, p3 = x_hi * y_hi;
    lo = std::min(std::min(p0, p1), std::min(p2, p3));
    hi = std::max(std::max(p0, p1), std::max(p2, p3));
}

/// Edge stage, for a common origin o. With A = v - o exactly, the edge function U of the
/// watertight test (cx by - cy bx for the edge b-c, likewise V for c-a and W for a-b) is, as a
/// function of the lane's shear (sx, sy),
///   E(sx, sy) = E0 + sx Ex + sy Ey  (the sx sy terms cancel: it is affine),
/// so over the lanes' rectangle of (sx, sy) it is bounded by its values at the four corners.
/// The lane's float sheared coordinates differ from the exact ones with the same (sx, sy) by
/// at most 5u max|A| (one rounding in a = v - o, two in sx * a[kz], one in the difference;
/// |sx|, |sy| <= 1), so its computed edge function, whose sign the watertight test gets exactly,
/// differs from E by at most 40u M_f M_s (M: largest |A| component of the two vertices). With a
/// margin of 128u M_f M_s, E < -margin everywhere means that edge function is negative in every
/// lane. A hit needs all three of one sign (or zero), so one edge negative for all lanes and
/// another positive for all lanes means no lane can hit.
inline bool triangle_edges_cull(const double (&rel)[3][3], const LeafBeam& lb) {
    constexpr double kMargin = 128.0 * 0x1p-24;
    bool some_negative = false, some_positive = false;
    double m[3];
    for (int i = 0; i < 3; ++i) {
        m[i] = std::max(std::max(std::fabs(rel[i][0]), std::fabs(rel[i][1])), std::fabs(rel[i][2]));
    }
    // (first, second) vertex pairs of U, V, W: U = c x b, V = a x c, W = b x a in 2D.
    constexpr int kPairs[3][2] = {{2, 1}, {0, 2}, {1, 0}};
    for (const auto& pair : kPairs) {
        const double* f = rel[pair[0]];
        const double* s = rel[pair[1]];
        const double e0 = f[0] * s[1] - f[1] * s[0];
        const double ex = f[1] * s[2] - f[2] * s[1];
        const double ey = f[2] * s[0] - f[0] * s[2];
        const double x0 = double(lb.s_lo[0]) * ex, x1 = double(lb.s_hi[0]) * ex;
        const double y0 = double(lb.s_lo[1]) * ey, y1 = double(lb.s_hi[1]) * ey;
        const double lo = e0 + std::min(x0, x1) + std::min(y0, y1);
        const double hi = e0 + std::max(x0, x1) + std::max(y0, y1);
        const double margin = kMargin * m[pair[0]] * m[pair[1]];
        some_negative = some_negative || hi < -margin;
        some_positive = some_positive || lo > margin;
    }
    return some_negative && some_positive;
}

/// Runs the enabled culling stages for one triangle against the leaf beam (packet with a
/// common origin and axis permutation, so a[k] = v[k] - origin[k] is the very float every
/// lane's watertight test computes).
inline Verdict cull_triangle(const bvh::Triangle& tri, const Beam& beam, const LeafBeam& lb,
                             const PacketCulling& culling) {
    const int axes[3] = {beam.kx, beam.ky, beam.kz};
    float verts[3][3];  // vertex, world axis
    std::memcpy(verts, &tri, sizeof verts);
    float a[3][3];  // vertex, sheared axis (kx, ky, kz)
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) a[i][j] = verts[i][axes[j]] - beam.origin[axes[j]];
    }
    if (culling.beam_planes) {
        // The four planes of the beam, in the watertight test's sheared coordinates: if every
        // lane sees all three vertices on one side (x < 0, x > 0, y < 0 or y > 0) of its
        // origin, the origin is outside the sheared triangle for every lane. Lane values
        // a[kx] - sx * a[kz] lie between those at the extreme shears (monotone rounding).
        bool x_neg = true, x_pos = true, y_neg = true, y_pos = true;
        for (int i = 0; i < 3; ++i) {
            float p_lo, p_hi, q_lo, q_hi;
            product_bounds(lb.s_lo[0], lb.s_hi[0], a[i][2], a[i][2], p_lo, p_hi);
            product_bounds(lb.s_lo[1], lb.s_hi[1], a[i][2], a[i][2], q_lo, q_hi);
            const float x_lo = a[i][0] - p_hi, x_hi = a[i][0] - p_lo;
            const float y_lo = a[i][1] - q_hi, y_hi = a[i][1] - q_lo;
            x_neg = x_neg && x_hi < 0.0f;
            x_pos = x_pos && x_lo > 0.0f;
            y_neg = y_neg && y_hi < 0.0f;
            y_pos = y_pos && y_lo > 0.0f;
        }
        if (x_neg || x_pos || y_neg || y_pos) return Verdict::kBeamPlanes;
    }
    if (culling.triangle_edges) {
        double rel[3][3];
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                rel[i][j] = double(verts[i][axes[j]]) - double(beam.origin[axes[j]]);
            }
        }
        if (triangle_edges_cull(rel, lb)) return Verdict::kTriangleEdges;
    }
    if (culling.near_far) {
        // A hit's t = (u az + v bz + w cz) / det with u, v, w of one sign lies between the
        // smallest and largest of az, bz, cz (az = sz * a[kz]) up to 6 roundings (< 8u
        // relative), so bounds on those over the lanes, widened by 16u, bound every lane's t.
        float z_lo = kInf, z_hi = -kInf;
        for (int i = 0; i < 3; ++i) {
            float lo, hi;
            product_bounds(lb.s_lo[2], lb.s_hi[2], a[i][2], a[i][2], lo, hi);
            z_lo = std::min(z_lo, lo);
            z_hi = std::max(z_hi, hi);
        }
        constexpr double kSlack = 16.0 * 0x1p-24;
        const double t_lo = double(z_lo) - kSlack * std::fabs(double(z_lo));
        const double t_hi = double(z_hi) + kSlack * std::fabs(double(z_hi));
        if (t_lo > double(lb.tfar_hi) || t_hi < double(lb.tnear_lo)) return Verdict::kNearFar;
    }
    return Verdict::kTest;
}


/// The nine coordinates of a triangle as an array (v0.x, v0.y, v0.z, v1.x, ...), so that
/// runtime axis indices are plain array indices.
struct TriangleCoords {
    float c[9];
    explicit TriangleCoords(const bvh::Triangle& t) { std::memcpy(c, &t, sizeof c); }
};
static_assert(sizeof(bvh::Triangle) == 9 * sizeof(float));

/// Fills `d` for the TriMode from the triangle's coordinates.
template <TriMode TM>
inline void prepare_triangle(const TriangleCoords& t, const Beam& beam, std::uint32_t prim,
                             TriData& d) {
    d.prim = prim;
    for (int v = 0; v < 3; ++v) {
        const float* p = t.c + 3 * v;
        if constexpr (TM == TriMode::kRelative) {
            d.p[3 * v + 0] = p[beam.kx] - beam.origin[beam.kx];
            d.p[3 * v + 1] = p[beam.ky] - beam.origin[beam.ky];
            d.p[3 * v + 2] = p[beam.kz] - beam.origin[beam.kz];
        } else if constexpr (TM == TriMode::kPermuted) {
            d.p[3 * v + 0] = p[beam.kx];
            d.p[3 * v + 1] = p[beam.ky];
            d.p[3 * v + 2] = p[beam.kz];
        } else {
            d.p[3 * v + 0] = p[0];
            d.p[3 * v + 1] = p[1];
            d.p[3 * v + 2] = p[2];
        }
    }
}

}  // namespace dynrt::packet::detail
