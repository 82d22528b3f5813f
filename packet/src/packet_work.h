#pragma once
// The working copy of one packet during a trace: per-lane constants of the box and triangle
// tests in SoA arrays, the lanes still active per SIMD chunk, and the packet-wide bounds (the
// beam) that let whole subtrees and triangles be skipped for all rays at once.

#include "dynrt/bvh/watertight_intersector.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/simd.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dynrt::packet::detail {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

/// Packet-wide bounds over the active lanes, computed once per trace.
struct Beam {
    /// All active origins are bit-identical; then origin[] is that origin.
    bool common_origin = false;
    float origin[3] = {};
    float org_lo[3] = {}, org_hi[3] = {};
    /// Axis a has one direction sign over all active lanes (signbit, so -0 counts as negative);
    /// `negative[a]` is that sign. With all three, the box test's near planes are common.
    bool sign_common[3] = {};
    bool negative[3] = {};
    bool common_octant = false;
    /// Interval arithmetic on axis a is valid: common sign and every 1/dir finite. Then
    /// inv_lo/hi bound the reciprocal directions.
    bool interval_ok[3] = {};
    float inv_lo[3] = {}, inv_hi[3] = {};
    /// All active lanes share the watertight test's axis permutation (kx, ky, kz).
    bool common_perm = false;
    int kx = 0, ky = 1, kz = 2;
    /// Sum of the active directions: the packet's dominant direction for child ordering.
    float mean_dir[3] = {};
    /// Index of the near and far plane on each axis in (lo.x, lo.y, lo.z, hi.x, hi.y, hi.z)
    /// for the axis's common sign (meaningful where sign_common).
    int near_index[3] = {0, 1, 2};
    int far_index[3] = {3, 4, 5};
    /// Smallest tmin and largest tmax over the active lanes.
    float tnear_lo = kInf;
    float tmax_hi = -kInf;
    /// Any-hit traces only (prepare<W, true>): the active rays' end points (origin + tmax dir)
    /// lie closer together than their origins, as shadow rays from surface points toward one
    /// light do (the renderer's shadow rays start at the light instead). The any-hit
    /// traversals of both trees then visit first the children at the end where the rays
    /// converge: the free space around the light, where an occluder ends
    /// a ray early, before the surfaces the rays spread over, which hold the most triangles
    /// and, at a ray's own surface, none that can occlude it. On soup:1000000's shadow rays
    /// the other order costs 20-25% more time, whichever way the rays point (bm_trace).
    bool ends_converge = false;
};

/// Per-lane state. Inactive (or, for any-hit, occluded) lanes have tnear = +inf and
/// tfar = -inf, so every box and triangle test misses for them without a mask.
struct alignas(64) Work {
    alignas(64) float org[3][kPacketRays];
    alignas(64) float inv[3][kPacketRays];
    /// The watertight test's shear constants sx, sy, sz.
    alignas(64) float shear[3][kPacketRays];
    /// The watertight test's axes kx, ky, kz.
    alignas(64) std::int32_t perm[3][kPacketRays];
    alignas(64) float tnear[kPacketRays];
    /// Current tmax: the closest hit so far for closest-hit traversal.
    alignas(64) float tfar[kPacketRays];
    /// Closest-hit results (t lives in tfar).
    alignas(64) float hit_u[kPacketRays];
    alignas(64) float hit_v[kPacketRays];
    alignas(64) std::uint32_t hit_prim[kPacketRays];
    /// Active lanes of chunk c (lanes [c W, c W + W)) as W bits.
    std::uint16_t chunk_bits[kPacketRays];
    /// Largest tfar of chunk c's lanes, kept exact by closest-hit traversal as hits shorten
    /// the rays (any hit only lowers tfar of terminated lanes and may leave it larger).
    float chunk_tfar_max[kPacketRays];
    /// First and last chunk with an active lane; first > last when none.
    int first_chunk = 0;
    int last_chunk = -1;
    int active_lanes = 0;
    Beam beam;
};

/// Fills `w` from `packet`, W lanes at a time. The per-lane constants are those of
/// bvh::WatertightRay and of the single-ray box test (1 / dir), computed with the same
/// operations lane by lane, so they are bit-identical. For an any-hit trace (kAnyHit) the beam
/// also says whether the rays converge at their ends (Beam::ends_converge); closest-hit traces
/// skip bounding the end points.
template <int W, bool kAnyHit>
void prepare(const RayPacket& packet, Work& w) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    constexpr int kChunks = kPacketRays / W;
    Beam& b = w.beam;
    b = Beam{};
    w.active_lanes = packet.active.count();
    w.first_chunk = kChunks;
    w.last_chunk = -1;

    // The first active lane is the reference for "common" origin and axis permutation.
    int first_lane = -1;
    for (int i = 0; i < 4 && first_lane < 0; ++i) {
        if (packet.active.words[i] != 0) first_lane = 64 * i + std::countr_zero(packet.active.words[i]);
    }
    const float* const org_in[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* const dir_in[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    std::int32_t ref_org[3] = {}, ref_perm[3] = {};
    if (first_lane >= 0) {
        const bvh::WatertightRay wt(packet.ray(first_lane));
        ref_perm[0] = wt.kx;
        ref_perm[1] = wt.ky;
        ref_perm[2] = wt.kz;
        for (int a = 0; a < 3; ++a) ref_org[a] = std::bit_cast<std::int32_t>(org_in[a][first_lane]);
    }

    const F inf = L::splat(kInf), minus_inf = L::splat(-kInf), zero = L::splat(0.0f);
    const I abs_mask = L::splat(std::int32_t(0x7fffffff));
    F org_lo[3], org_hi[3], inv_lo[3], inv_hi[3], dir_sum[3], end_lo[3], end_hi[3];
    // Lane flags accumulated over chunks (-1 where some chunk's lane had the property).
    I negative_any[3], positive_any[3], infinite_any[3];
    I origin_differs = L::splat(0), perm_differs = L::splat(0);
    for (int a = 0; a < 3; ++a) {
        org_lo[a] = inv_lo[a] = end_lo[a] = inf;
        org_hi[a] = inv_hi[a] = end_hi[a] = minus_inf;
        dir_sum[a] = zero;
        negative_any[a] = positive_any[a] = infinite_any[a] = L::splat(0);
    }
    F tnear_lo = inf, tmax_hi = minus_inf;

    for (int c = 0; c < kChunks; ++c) {
        const int base = c * W;
        const std::uint32_t active = packet.active.extract(base, W);
        w.chunk_bits[c] = std::uint16_t(active);
        if (active == 0) {
            // A chunk without active lanes is never tested (every test skips chunks whose
            // bits are 0, and bits only ever clear): only what is read for all lanes is
            // written. The packets a two-level trace makes per instance are mostly empty.
            L::store(w.tnear + base, inf);
            L::store(w.tfar + base, minus_inf);
            L::store(w.hit_u + base, zero);
            L::store(w.hit_v + base, zero);
            L::store(w.hit_prim + base, L::splat(bvh::kInvalidId));
            w.chunk_tfar_max[c] = -kInf;
            // What the heuristic mean direction sums for inactive lanes, (0, 0, 1) each.
            dir_sum[2] = dir_sum[2] + L::splat(1.0f);
            continue;
        }
        if (w.first_chunk == kChunks) w.first_chunk = c;
        w.last_chunk = c;
        const I m = L::from_bits(active);
        // Inactive lanes get a harmless ray (origin 0, direction +z) so that nothing below
        // reads an arbitrary value; tnear = +inf and tfar = -inf make them miss everything.
        F o[3], d[3];
        for (int a = 0; a < 3; ++a) {
            o[a] = L::select(m, L::load(org_in[a] + base), zero);
            d[a] = L::select(m, L::load(dir_in[a] + base), L::splat(a == 2 ? 1.0f : 0.0f));
        }
        // bvh::WatertightRay: kz is the axis of the largest |dir| (ties to the lowest axis),
        // kx and ky follow cyclically and swap for a negative dir[kz].
        const F mx = F(I(d[0]) & abs_mask), my = F(I(d[1]) & abs_mask), mz = F(I(d[2]) & abs_mask);
        const I z_is_x = (mx >= my) & (mx >= mz);
        const I z_is_y = ~z_is_x & (my >= mz);
        const I kz = L::select(z_is_x, L::splat(0), L::select(z_is_y, L::splat(1), L::splat(2)));
        I kx = L::select(kz == 2, L::splat(0), kz + 1);
        I ky = L::select(kx == 2, L::splat(0), kx + 1);
        const auto pick = [&](I k) { return L::select(k == 0, d[0], L::select(k == 1, d[1], d[2])); };
        const F dz = pick(kz);
        const I swap = dz < zero;
        const I kx_swapped = L::select(swap, ky, kx);
        ky = L::select(swap, kx, ky);
        kx = kx_swapped;
        const F sx = pick(kx) / dz;
        const F sy = pick(ky) / dz;
        const F sz = L::splat(1.0f) / dz;
        const I perm[3] = {kx, ky, kz};
        const F shear[3] = {sx, sy, sz};
        for (int a = 0; a < 3; ++a) {
            const F inv = L::splat(1.0f) / d[a];
            L::store(w.org[a] + base, o[a]);
            L::store(w.inv[a] + base, inv);
            L::store(w.shear[a] + base, shear[a]);
            L::store(w.perm[a] + base, perm[a]);

            // ---- Beam: bounds over the active lanes ----
            org_lo[a] = L::min_into(L::select(m, o[a], inf), org_lo[a]);
            org_hi[a] = L::max_into(L::select(m, o[a], minus_inf), org_hi[a]);
            inv_lo[a] = L::min_into(L::select(m, inv, inf), inv_lo[a]);
            inv_hi[a] = L::max_into(L::select(m, inv, minus_inf), inv_hi[a]);
            dir_sum[a] = dir_sum[a] + d[a];  // inactive lanes add (0, 0, 1): only a heuristic
            const I negative = I(d[a]) < 0;  // the sign bit, so -0 too
            negative_any[a] |= negative & m;
            positive_any[a] |= ~negative & m;
            infinite_any[a] |= (F(I(inv) & abs_mask) == inf) & m;
            // Origins compare bit for bit: -0 and +0 differ (a zero's sign can reach results).
            origin_differs |= (I(o[a]) != L::splat(ref_org[a])) & m;
            perm_differs |= (perm[a] != L::splat(ref_perm[a])) & m;
        }
        const F tmin = L::load(packet.tmin + base), tmax = L::load(packet.tmax + base);
        const F tn = L::select(m, tmin, inf), tf = L::select(m, tmax, minus_inf);
        if constexpr (kAnyHit) {
            for (int a = 0; a < 3; ++a) {
                // Only an ordering heuristic: an infinite or NaN end makes ends_converge false.
                const F end = o[a] + tmax * d[a];
                end_lo[a] = L::min_into(L::select(m, end, inf), end_lo[a]);
                end_hi[a] = L::max_into(L::select(m, end, minus_inf), end_hi[a]);
            }
        }
        L::store(w.tnear + base, tn);
        L::store(w.tfar + base, tf);
        L::store(w.hit_u + base, zero);
        L::store(w.hit_v + base, zero);
        L::store(w.hit_prim + base, L::splat(bvh::kInvalidId));
        tnear_lo = L::min_into(tn, tnear_lo);
        tmax_hi = L::max_into(tf, tmax_hi);
        w.chunk_tfar_max[c] = L::reduce_max(tf);
    }
    if (first_lane < 0) return;

    b.common_origin = L::bits(origin_differs) == 0;
    b.common_perm = L::bits(perm_differs) == 0;
    b.kx = ref_perm[0];
    b.ky = ref_perm[1];
    b.kz = ref_perm[2];
    b.common_octant = true;
    for (int a = 0; a < 3; ++a) {
        b.origin[a] = std::bit_cast<float>(ref_org[a]);
        b.org_lo[a] = L::reduce_min(org_lo[a]);
        b.org_hi[a] = L::reduce_max(org_hi[a]);
        b.inv_lo[a] = L::reduce_min(inv_lo[a]);
        b.inv_hi[a] = L::reduce_max(inv_hi[a]);
        float sum = 0.0f;
        for (int i = 0; i < W; ++i) sum += dir_sum[a][i];
        b.mean_dir[a] = sum;
        const bool negative = L::bits(negative_any[a]) != 0;
        b.sign_common[a] = !negative || L::bits(positive_any[a]) == 0;
        b.negative[a] = negative;
        b.interval_ok[a] = b.sign_common[a] && L::bits(infinite_any[a]) == 0;
        b.common_octant = b.common_octant && b.sign_common[a];
        b.near_index[a] = b.negative[a] ? a + 3 : a;
        b.far_index[a] = b.negative[a] ? a : a + 3;
    }
    b.tnear_lo = L::reduce_min(tnear_lo);
    b.tmax_hi = L::reduce_max(tmax_hi);
    if constexpr (kAnyHit) {
        float end_spread = 0.0f, origin_spread = 0.0f;
        for (int a = 0; a < 3; ++a) {
            end_spread += L::reduce_max(end_hi[a]) - L::reduce_min(end_lo[a]);
            origin_spread += b.org_hi[a] - b.org_lo[a];
        }
        b.ends_converge = end_spread < origin_spread;
    }
}

}  // namespace dynrt::packet::detail
