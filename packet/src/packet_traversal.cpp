// Packet traversal of a triangle BVH: closest hit and any hit for 256 rays sharing one stack.
//
// Per node (ranged traversal, Wald, Boulos and Shirley 2007; Overbeck, Ramamoorthi and Mark
// 2008): the packet carries a range [first, last] of SIMD chunks that may still hit the node.
//   1. early hit: the first active ray of the range hits the box -> descend for the whole range
//      without testing the others;
//   2. early miss: interval arithmetic over all active rays (bounds on origin and reciprocal
//      direction) shows that no ray can hit -> skip the subtree;
//   3. otherwise the rays are box-tested chunk by chunk from both ends, which narrows the range
//      to the first and last chunk with a hit (or skips the node when there is none).
// Children are pushed so that the one nearer along the packet's mean direction is visited
// first. At a leaf, the rays of the range are box-tested lane by lane (per-ray masks, culling
// stage "ab"), then each triangle goes through Reshetov's vertex culling (Reshetov 2007,
// "Faster Ray Packets - Triangle Intersection through Vertex Culling") against the beam of
// exactly the rays to be tested, and finally through the SIMD watertight test.
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

#include "dynrt/packet/packet_traversal.h"

#include "packet_work.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace dynrt::packet {

PacketStats& PacketStats::operator+=(const PacketStats& o) {
    packets += o.packets;
    nodes_visited += o.nodes_visited;
    leaves_visited += o.leaves_visited;
    early_hits += o.early_hits;
    early_misses += o.early_misses;
    ray_box_tests += o.ray_box_tests;
    ray_triangle_tests += o.ray_triangle_tests;
    culled_active_bounds += o.culled_active_bounds;
    culled_beam_planes += o.culled_beam_planes;
    culled_triangle_edges += o.culled_triangle_edges;
    culled_near_far += o.culled_near_far;
    return *this;
}

PacketCulling PacketCulling::parse(std::string_view list) {
    if (list == "all") return PacketCulling{};
    if (list == "none" || list.empty()) return PacketCulling::none();
    PacketCulling c = PacketCulling::none();
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const std::string_view item = list.substr(start, comma - start);
        if (item == "ab") {
            c.active_bounds = true;
        } else if (item == "bp") {
            c.beam_planes = true;
        } else if (item == "edge") {
            c.triangle_edges = true;
        } else if (item == "nf") {
            c.near_far = true;
        } else {
            throw std::invalid_argument("packet culling '" + std::string(list) + "': unknown stage '" +
                                        std::string(item) + "' (known: ab, bp, edge, nf, all, none)");
        }
        start = comma + 1;
    }
    return c;
}

std::string PacketCulling::to_string() const {
    std::string out;
    const auto add = [&](bool on, const char* name) {
        if (!on) return;
        if (!out.empty()) out += ',';
        out += name;
    };
    add(active_bounds, "ab");
    add(beam_planes, "bp");
    add(triangle_edges, "edge");
    add(near_far, "nf");
    return out.empty() ? "none" : out;
}

namespace {

using detail::Beam;
using detail::kInf;
using detail::Work;

// The single-ray box test's growth of far distances (bvh/src/triangle_bvh.cpp, Ize 2013); the
// two must be the same constant for the box tests to agree bit for bit.
constexpr float kUnitRoundoff = std::numeric_limits<float>::epsilon() * 0.5f;
constexpr float gamma_n(int n) { return n * kUnitRoundoff / (1.0f - n * kUnitRoundoff); }
constexpr float kFarScale = 1.0f + 2.0f * gamma_n(3);

constexpr int kStackSize = 2 * static_cast<int>(bvh::kMaxDepth) + 2;
/// Fewest rays in a node's range for the early-miss beam test to run (measured on 1M-triangle
/// and 20k-triangle scenes: below this, box-testing the rays directly is as cheap).
constexpr int kBeamMinLanes = 96;
/// Leaf triangles prepared (culled, permuted) at a time before the SIMD loop.
constexpr int kTriBatch = 16;

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

/// The same test for one lane (the early-hit ray).
inline bool lane_hits_box(const Work& w, const bvh::Aabb& box, int lane) {
    float tn = w.tnear[lane];
    float tf = w.tfar[lane];
    for (int a = 0; a < 3; ++a) {
        const float inv = w.inv[a][lane];
        const float o = w.org[a][lane];
        const bool negative = inv < 0.0f;
        const float t0 = ((negative ? box.hi[a] : box.lo[a]) - o) * inv;
        const float t1 = ((negative ? box.lo[a] : box.hi[a]) - o) * inv;
        tn = t0 > tn ? t0 : tn;
        tf = t1 < tf ? t1 : tf;
    }
    return tn <= tf * kFarScale;
}

/// Early miss: true only if no active lane's box test can hit. Lane i's entry distance is the
/// NaN-ignoring max of tmin_i and (near - org_i) * inv_i over the axes; on an axis with a
/// common sign and finite reciprocals the latter is never NaN and, rounding being monotone, is
/// at least the smallest product at the corners of [near - org_hi, near - org_lo] x
/// [inv_lo, inv_hi]. Likewise the exit distance is at most the largest such product for the
/// far plane, so entry_lo > exit_hi * kFarScale rules out every lane. Axes without valid
/// intervals are simply left out, which only weakens the bound. `tfar_hi` bounds the current
/// tmax of the lanes concerned (those of the node's range). With a common octant, or per axis
/// with a common sign, the near and far planes are the NodePlanes' (for axes whose sign is not
/// common the interval is not valid anyway).
inline bool beam_misses(const Beam& b, const NodePlanes& np, float tfar_hi) {
    float tn = b.tnear_lo;
    float tf = tfar_hi;
    for (int a = 0; a < 3; ++a) {
        if (!b.interval_ok[a]) continue;
        const float i_lo = b.inv_lo[a], i_hi = b.inv_hi[a];
        float t0, t1;
        if (b.common_origin) {
            const float n = np.near_rel[a], f = np.far_rel[a];
            t0 = std::min(n * i_lo, n * i_hi);
            t1 = std::max(f * i_lo, f * i_hi);
        } else {
            const float n_lo = np.near[a] - b.org_hi[a], n_hi = np.near[a] - b.org_lo[a];
            const float f_lo = np.far[a] - b.org_hi[a], f_hi = np.far[a] - b.org_lo[a];
            t0 = std::min(std::min(n_lo * i_lo, n_lo * i_hi), std::min(n_hi * i_lo, n_hi * i_hi));
            t1 = std::max(std::max(f_lo * i_lo, f_lo * i_hi), std::max(f_hi * i_lo, f_hi * i_hi));
        }
        tn = std::max(tn, t0);
        tf = std::min(tf, t1);
    }
    return tn > tf * kFarScale;
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

// ---- Traversal ------------------------------------------------------------------------------

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

template <int W, bool kAnyHit, bool kCount>
class Traversal {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    using U = typename L::U;
    static constexpr int kChunks = kPacketRays / W;

public:
    Traversal(const bvh::TriangleBvh& accel, Work& w, const PacketConfig& config,
              PacketStats* stats, LaneMask* occluded)
        : accel_(accel), w_(w), config_(config), culling_(config.culling), stats_(stats),
          occluded_(occluded) {}

    void run() {
        if (accel_.bvh.nodes.empty() || w_.first_chunk > w_.last_chunk) return;
        const Beam& beam = w_.beam;
        if (beam.common_octant) {
            if (beam.common_origin) {
                run_with<BoxMode::kOctantOrigin>();
            } else {
                run_with<BoxMode::kOctant>();
            }
        } else {
            run_with<BoxMode::kGeneral>();
        }
    }

private:
    struct Entry {
        std::uint32_t node;
        std::uint16_t first, last;
    };

    template <BoxMode M>
    void run_with() {
        const Beam& beam = w_.beam;
        if (beam.common_perm) {
            if (beam.common_origin) {
                traverse<M, TriMode::kRelative>();
            } else {
                traverse<M, TriMode::kPermuted>();
            }
        } else {
            traverse<M, TriMode::kGeneral>();
        }
    }

    template <BoxMode M>
    std::uint32_t box(const bvh::Aabb& box, const NodePlanes& np, int c) {
        if constexpr (kCount) stats_->ray_box_tests += std::popcount(unsigned(w_.chunk_bits[c]));
        return box_chunk<W, M>(w_, box, np, c) & w_.chunk_bits[c];
    }

    /// Narrows [first, last] to the first and last chunk with a lane hitting `b`, whose hit
    /// lanes come back in first_bits and last_bits; false when no chunk has one.
    template <BoxMode M>
    bool narrow(const bvh::Aabb& b, const NodePlanes& np, int& first, int& last,
                std::uint32_t& first_bits, std::uint32_t& last_bits) {
        int c = first;
        for (; c <= last; ++c) {
            if (w_.chunk_bits[c] == 0) continue;
            first_bits = box<M>(b, np, c);
            if (first_bits != 0) break;
        }
        if (c > last) return false;
        first = c;
        last_bits = first_bits;
        for (c = last; c > first; --c) {
            if (w_.chunk_bits[c] == 0) continue;
            const std::uint32_t bits = box<M>(b, np, c);
            if (bits != 0) {
                last_bits = bits;
                break;
            }
        }
        last = c;
        return true;
    }

    /// The early miss for the lanes of chunks [first, last].
    bool beam_rules_out(const NodePlanes& np, int first, int last) const {
        // Over a short range, testing the rays themselves costs no more than the beam test and
        // the beam rarely succeeds, so it runs on long ranges only.
        if ((last - first + 1) * W < kBeamMinLanes) return false;
        // Any hit never shortens a ray, so the packet's largest tmax serves every range.
        if constexpr (kAnyHit) return beam_misses(w_.beam, np, w_.beam.tmax_hi);
        return beam_misses(w_.beam, np, range_tfar_max(first, last));
    }

    /// Largest tfar over the lanes of chunks [first, last].
    float range_tfar_max(int first, int last) const {
        const float* m = w_.chunk_tfar_max;
        int c = first;
        float hi = -kInf;
        if constexpr (W > 1) {
            if (last - first + 1 >= W) {
                F acc = L::load(m + c);
                for (c += W; c + W <= last + 1; c += W) acc = L::max_into(L::load(m + c), acc);
                hi = L::reduce_max(acc);
            }
        }
        for (; c <= last; ++c) hi = m[c] > hi ? m[c] : hi;
        return hi;
    }

    template <BoxMode BM, TriMode TM>
    void traverse() {
        const bvh::BvhNode* nodes = accel_.bvh.nodes.data();
        const Beam& beam = w_.beam;
        Entry stack[kStackSize];
        int top = 0;
        stack[top++] = Entry{0, std::uint16_t(w_.first_chunk), std::uint16_t(w_.last_chunk)};
        while (top > 0) {
            const Entry e = stack[--top];
            const bvh::BvhNode& node = nodes[e.node];
            int first = e.first, last = e.last;
            if constexpr (kAnyHit) {
                // Occluded rays are gone: trim chunks without active lanes from the range.
                while (first <= last && w_.chunk_bits[first] == 0) ++first;
                while (last >= first && w_.chunk_bits[last] == 0) --last;
                if (first > last) continue;
            }
            if constexpr (kCount) ++stats_->nodes_visited;
            if (!node.is_leaf()) {
                const std::uint32_t early_bits = w_.chunk_bits[first];
                const bool early_hit =
                    early_bits != 0 &&
                    lane_hits_box(w_, node.box, first * W + std::countr_zero(early_bits));
                if (early_hit) {
                    if constexpr (kCount) ++stats_->early_hits;
                } else {
                    const NodePlanes np(node.box, beam);
                    if (beam_rules_out(np, first, last)) {
                        if constexpr (kCount) ++stats_->early_misses;
                        continue;
                    }
                    std::uint32_t first_bits = 0, last_bits = 0;
                    if (!narrow<BM>(node.box, np, first, last, first_bits, last_bits)) continue;
                    // Few rays left in a narrow range: trace them one by one below this node
                    // (Embree's "hybrid" traversal), which costs far less per node than the
                    // packet machinery does for a handful of rays.
                    if (last - first <= 1) {
                        const std::uint32_t lanes[2] = {first_bits, last != first ? last_bits : 0u};
                        if (std::popcount(lanes[0]) + std::popcount(lanes[1]) <= config_.single_ray_max) {
                            for (int i = 0; i < 2; ++i) {
                                for (std::uint32_t b = lanes[i]; b != 0; b &= b - 1) {
                                    trace_lane<TM>(e.node, (first + i) * W + std::countr_zero(b));
                                }
                            }
                            if constexpr (kAnyHit) {
                                if (w_.active_lanes == 0) return;
                            }
                            continue;
                        }
                    }
                }
                // Nearer child (along the packet's mean direction) on top of the stack.
                const bvh::Aabb& l = nodes[node.first].box;
                const bvh::Aabb& r = nodes[node.first + 1].box;
                float along = 0.0f;
                for (int a = 0; a < 3; ++a) {
                    along += ((r.lo[a] + r.hi[a]) - (l.lo[a] + l.hi[a])) * beam.mean_dir[a];
                }
                const std::uint32_t near = along < 0.0f ? node.first + 1 : node.first;
                const std::uint32_t far = along < 0.0f ? node.first : node.first + 1;
                // What the children will read next (their children's boxes, or a leaf's
                // triangles) is far apart in memory: start fetching it now.
                prefetch_below(nodes[far]);
                prefetch_below(nodes[near]);
                stack[top++] = Entry{far, std::uint16_t(first), std::uint16_t(last)};
                stack[top++] = Entry{near, std::uint16_t(first), std::uint16_t(last)};
                continue;
            }
            const NodePlanes np(node.box, beam);
            if (beam_rules_out(np, first, last)) {
                if constexpr (kCount) ++stats_->early_misses;
                continue;
            }
            // The lanes to test: the range's lanes hitting the leaf box (ab), or all active.
            int n = 0;
            if (culling_.active_bounds) {
                for (int c = first; c <= last; ++c) {
                    if (w_.chunk_bits[c] == 0) continue;
                    const std::uint32_t bits = box<BM>(node.box, np, c);
                    if (bits == 0) continue;
                    leaf_chunk_[n] = std::uint16_t(c);
                    leaf_bits_[n] = bits;
                    ++n;
                }
            } else {
                for (int c = w_.first_chunk; c <= w_.last_chunk; ++c) {
                    if (w_.chunk_bits[c] == 0) continue;
                    leaf_chunk_[n] = std::uint16_t(c);
                    leaf_bits_[n] = w_.chunk_bits[c];
                    ++n;
                }
            }
            if (n == 0) continue;
            intersect_leaf<TM>(node, n);
            if constexpr (kAnyHit) {
                if (w_.active_lanes == 0) return;  // every ray is occluded
            }
        }
    }

    template <TriMode TM>
    void intersect_leaf(const bvh::BvhNode& node, int n) {
        const Beam& beam = w_.beam;
        const bvh::Triangle* tris = accel_.tris.data();
        const std::uint32_t* prim_ids = accel_.bvh.prim_ids.data();
        int tested_lanes = 0;  // for the counters only
        if constexpr (kCount) {
            for (int i = 0; i < n; ++i) tested_lanes += std::popcount(leaf_bits_[i]);
            ++stats_->leaves_visited;
            stats_->culled_active_bounds +=
                std::uint64_t(w_.active_lanes - tested_lanes) * node.count;
        }
        // Culling a triangle costs about as much as testing a few chunks, so it only runs
        // when there are enough chunks to test for it to pay. Packets without a common origin
        // (incoherent rays) skip it: their beam is wide and the stages cull next to nothing
        // (measured: none at all for sphere:1000000's shadow rays when they started at the hit
        // points).
        const bool leaf_culling =
            n >= config_.cull_min_steps && beam.common_origin && beam.common_perm &&
            (culling_.beam_planes || culling_.triangle_edges || culling_.near_far);
        LeafBeam lb;
        if (leaf_culling) compute_leaf_beam<W>(w_, leaf_chunk_, leaf_bits_, n, lb);

        const std::uint32_t end = node.first + node.count;
        for (std::uint32_t batch = node.first; batch < end; batch += kTriBatch) {
            // Cull and prepare up to kTriBatch triangles.
            TriData prepared[kTriBatch];
            int count = 0;
            const std::uint32_t batch_end = std::min(end, batch + kTriBatch);
            for (std::uint32_t k = batch; k < batch_end; ++k) {
                const bvh::Triangle& tri = tris[k];
                if (leaf_culling) {
                    const Verdict verdict = cull_triangle(tri, beam, lb, culling_);
                    if (verdict != Verdict::kTest) {
                        if constexpr (kCount) {
                            std::uint64_t& counter =
                                verdict == Verdict::kBeamPlanes      ? stats_->culled_beam_planes
                                : verdict == Verdict::kTriangleEdges ? stats_->culled_triangle_edges
                                                                     : stats_->culled_near_far;
                            counter += std::uint64_t(tested_lanes);
                        }
                        continue;
                    }
                }
                prepare_triangle<TM>(TriangleCoords(tri), beam, prim_ids[k], prepared[count++]);
            }
            if (count == 0) continue;
            for (int i = 0; i < n; ++i) {
                if constexpr (kAnyHit) {
                    if (leaf_bits_[i] == 0) continue;
                    intersect_chunk_any<TM>(leaf_chunk_[i], leaf_bits_[i], prepared, count);
                } else {
                    intersect_chunk_closest<TM>(leaf_chunk_[i], leaf_bits_[i], prepared, count);
                }
            }
            if constexpr (kAnyHit) {
                if (w_.active_lanes == 0) return;
            }
        }
    }

    template <TriMode TM>
    bool intersect_chunk_closest(int c, std::uint32_t lanes, const TriData* tris, int count) {
        const int base = c * W;
        const ChunkRays<W> r(w_, w_.beam, TM, c);
        const I lane_mask = L::from_bits(lanes);
        const F tnear = L::load(w_.tnear + base);
        F tfar = L::load(w_.tfar + base);
        F hu = L::load(w_.hit_u + base);
        F hv = L::load(w_.hit_v + base);
        U prim = L::load(w_.hit_prim + base);
        bool updated = false;
        for (int j = 0; j < count; ++j) {
            if constexpr (kCount) stats_->ray_triangle_tests += std::popcount(lanes);
            F t, det, v, w;
            const I hit = watertight_chunk<W, TM>(r, tris[j], tnear, tfar, lanes, t, det, v, w) &
                          lane_mask;
            if (L::bits(hit) == 0) continue;
            // t <= tfar in hit lanes; a tie goes to the lower primitive index, as in the
            // single-ray tracer.
            const U candidate = L::splat(tris[j].prim);
            const I accept = hit & ((t < tfar) | (candidate < prim));
            if (L::bits(accept) == 0) continue;
            tfar = L::select(accept, t, tfar);
            hu = L::select(accept, v / det, hu);
            hv = L::select(accept, w / det, hv);
            prim = L::select(accept, candidate, prim);
            updated = true;
        }
        if (updated) {
            L::store(w_.tfar + base, tfar);
            L::store(w_.hit_u + base, hu);
            L::store(w_.hit_v + base, hv);
            L::store(w_.hit_prim + base, prim);
            w_.chunk_tfar_max[c] = L::reduce_max(tfar);
        }
        return updated;
    }

    template <TriMode TM>
    void intersect_chunk_any(int c, std::uint32_t& lanes, const TriData* tris, int count) {
        const int base = c * W;
        const ChunkRays<W> r(w_, w_.beam, TM, c);
        const F tnear = L::load(w_.tnear + base);
        const F tfar = L::load(w_.tfar + base);
        std::uint32_t live = lanes & w_.chunk_bits[c];
        std::uint32_t hits = 0;
        for (int j = 0; j < count && live != 0; ++j) {
            if constexpr (kCount) stats_->ray_triangle_tests += std::popcount(live);
            F t, det, v, w;
            const std::uint32_t hit =
                L::bits(watertight_chunk<W, TM>(r, tris[j], tnear, tfar, live, t, det, v, w)) & live;
            hits |= hit;
            live &= ~hit;
        }
        lanes = live;
        for (std::uint32_t h = hits; h != 0; h &= h - 1) terminate(base + std::countr_zero(h));
    }

    /// Any hit: `lane` is occluded; no box or triangle test can hit it any more.
    void terminate(int lane) {
        const int c = lane / W;
        w_.chunk_bits[c] = std::uint16_t(w_.chunk_bits[c] & ~(1u << (lane % W)));
        --w_.active_lanes;
        w_.tnear[lane] = kInf;
        w_.tfar[lane] = -kInf;
        occluded_->set(lane);
    }

    /// Single-ray traversal of the subtree at `root` (whose box the lane hits) for one lane,
    /// continuing from the lane's current hit: the same box and triangle arithmetic (the W = 1
    /// kernels), children nearest first by entry distance as in the single-ray tracer.
    template <TriMode TM>
    void trace_lane(std::uint32_t root, int lane) {
        using L1 = simd::Lanes<1>;
        const bvh::BvhNode* nodes = accel_.bvh.nodes.data();
        const bvh::Triangle* tris = accel_.tris.data();
        const std::uint32_t* prim_ids = accel_.bvh.prim_ids.data();
        const Beam& beam = w_.beam;
        const ChunkRays<1> ray(w_, beam, TM, lane);
        const float org[3] = {w_.org[0][lane], w_.org[1][lane], w_.org[2][lane]};
        const float inv[3] = {w_.inv[0][lane], w_.inv[1][lane], w_.inv[2][lane]};
        const bool negative[3] = {inv[0] < 0.0f, inv[1] < 0.0f, inv[2] < 0.0f};
        const float tnear = w_.tnear[lane];
        float tfar = w_.tfar[lane];
        const auto entry = [&](const bvh::Aabb& box, float& t_entry) {
            float tn = tnear, tf = tfar;
            for (int a = 0; a < 3; ++a) {
                const float t0 = ((negative[a] ? box.hi[a] : box.lo[a]) - org[a]) * inv[a];
                const float t1 = ((negative[a] ? box.lo[a] : box.hi[a]) - org[a]) * inv[a];
                tn = t0 > tn ? t0 : tn;
                tf = t1 < tf ? t1 : tf;
            }
            t_entry = tn;
            return tn <= tf * kFarScale;
        };
        struct LaneEntry {
            std::uint32_t node;
            float tnear;
        };
        LaneEntry stack[kStackSize];
        int top = 0;
        std::uint32_t index = root;
        bool updated = false;
        while (true) {
            const bvh::BvhNode& node = nodes[index];
            if constexpr (kCount) ++stats_->nodes_visited;
            if (!node.is_leaf()) {
                float t_left, t_right;
                const bool hit_left = entry(nodes[node.first].box, t_left);
                const bool hit_right = entry(nodes[node.first + 1].box, t_right);
                if constexpr (kCount) stats_->ray_box_tests += 2;
                if (hit_left && hit_right) {
                    const bool right_first = t_right < t_left;
                    stack[top++] = LaneEntry{right_first ? node.first : node.first + 1,
                                             right_first ? t_left : t_right};
                    index = right_first ? node.first + 1 : node.first;
                    continue;
                }
                if (hit_left || hit_right) {
                    index = hit_left ? node.first : node.first + 1;
                    continue;
                }
            } else {
                if constexpr (kCount) ++stats_->leaves_visited;
                const std::uint32_t end = node.first + node.count;
                for (std::uint32_t k = node.first; k < end; ++k) {
                    TriData d;
                    prepare_triangle<TM>(TriangleCoords(tris[k]), beam, prim_ids[k], d);
                    if constexpr (kCount) ++stats_->ray_triangle_tests;
                    typename L1::F t, det, v, w;
                    const bool hit = L1::bits(watertight_chunk<1, TM>(
                                         ray, d, L1::splat(tnear), L1::splat(tfar), 1u, t, det,
                                         v, w)) != 0;
                    if (!hit) continue;
                    if constexpr (kAnyHit) {
                        terminate(lane);
                        return;
                    } else {
                        if (t[0] < tfar || d.prim < w_.hit_prim[lane]) {
                            tfar = t[0];
                            w_.hit_u[lane] = v[0] / det[0];
                            w_.hit_v[lane] = w[0] / det[0];
                            w_.hit_prim[lane] = d.prim;
                            updated = true;
                        }
                    }
                }
            }
            while (true) {
                if (top == 0) {
                    if (updated) {
                        w_.tfar[lane] = tfar;
                        const int c = lane / W;
                        w_.chunk_tfar_max[c] = L::reduce_max(L::load(w_.tfar + c * W));
                    }
                    return;
                }
                const LaneEntry e = stack[--top];
                if (e.tnear <= tfar * kFarScale) {
                    index = e.node;
                    break;
                }
            }
        }
    }

    void prefetch_below(const bvh::BvhNode& node) {
        if (node.is_leaf()) {
            const char* first = reinterpret_cast<const char*>(accel_.tris.data() + node.first);
            const char* end = reinterpret_cast<const char*>(accel_.tris.data() + node.first + node.count);
            for (const char* p = first; p < end; p += 64) __builtin_prefetch(p);
            __builtin_prefetch(end - 1);
            __builtin_prefetch(accel_.bvh.prim_ids.data() + node.first);
        } else {
            // A child pair is 64 bytes but need not start on a cache line.
            __builtin_prefetch(accel_.bvh.nodes.data() + node.first);
            __builtin_prefetch(accel_.bvh.nodes.data() + node.first + 1);
        }
    }

    const bvh::TriangleBvh& accel_;
    Work& w_;
    const PacketConfig& config_;
    const PacketCulling& culling_;
    PacketStats* stats_;
    LaneMask* occluded_;
    std::uint16_t leaf_chunk_[kChunks];
    std::uint32_t leaf_bits_[kChunks];
};

template <int W>
void closest_with(const bvh::TriangleBvh& accel, const RayPacket& packet, PacketHits& hits,
                  const PacketConfig& config, PacketStats* stats) {
    Work w;
    detail::prepare<W>(packet, w);
    if (stats) {
        ++stats->packets;
        Traversal<W, false, true>(accel, w, config, stats, nullptr).run();
    } else {
        Traversal<W, false, false>(accel, w, config, nullptr, nullptr).run();
    }
    using L = simd::Lanes<W>;
    for (int base = 0; base < kPacketRays; base += W) {
        const typename L::U prim = L::load(w.hit_prim + base);
        const typename L::I hit = prim != L::splat(bvh::kInvalidId);
        L::store(hits.t + base, L::select(hit, L::load(w.tfar + base), L::splat(kInf)));
        L::store(hits.u + base, L::load(w.hit_u + base));
        L::store(hits.v + base, L::load(w.hit_v + base));
        L::store(hits.prim + base, prim);
    }
}

template <int W>
void any_with(const bvh::TriangleBvh& accel, const RayPacket& packet, LaneMask& occluded,
              const PacketConfig& config, PacketStats* stats) {
    Work w;
    detail::prepare<W>(packet, w);
    occluded = LaneMask{};
    if (stats) {
        ++stats->packets;
        Traversal<W, true, true>(accel, w, config, stats, &occluded).run();
    } else {
        Traversal<W, true, false>(accel, w, config, nullptr, &occluded).run();
    }
}

void check_lanes(int lanes) {
    if (lanes != simd::kNativeLanes && lanes != 1) {
        throw std::invalid_argument("packet tracer: lanes must be " +
                                    std::to_string(simd::kNativeLanes) + " or 1, not " +
                                    std::to_string(lanes));
    }
}

}  // namespace

void intersect_closest(const bvh::TriangleBvh& accel, const RayPacket& packet, PacketHits& hits,
                       const PacketConfig& config, PacketStats* stats) {
    check_lanes(config.lanes);
    if (config.lanes == 1) {
        closest_with<1>(accel, packet, hits, config, stats);
    } else {
        closest_with<simd::kNativeLanes>(accel, packet, hits, config, stats);
    }
}

void intersect_any(const bvh::TriangleBvh& accel, const RayPacket& packet, LaneMask& occluded,
                   const PacketConfig& config, PacketStats* stats) {
    check_lanes(config.lanes);
    if (config.lanes == 1) {
        any_with<1>(accel, packet, occluded, config, stats);
    } else {
        any_with<simd::kNativeLanes>(accel, packet, occluded, config, stats);
    }
}

}  // namespace dynrt::packet
