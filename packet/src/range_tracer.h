#pragma once
// What the packet traversals of the binary and the wide tree share: a packet's range of SIMD
// chunks [first, last] that may still hit a node, narrowed by box tests from both ends
// (ranged traversal: Wald, Boulos and Shirley 2007; Overbeck, Ramamoorthi and Mark 2008); the
// early miss of a whole range from the packet's interval bounds; and the leaf test: the rays
// of the range box-tested lane by lane (culling stage "ab"), each triangle culled against the
// beam of exactly those rays (Reshetov 2007), the survivors run through the SIMD watertight
// test chunk by chunk. The traversals own the stacks and decide the order of nodes; results
// do not depend on that order (packet_kernels.h).

#include "packet_kernels.h"
#include "packet_work.h"

#include "dynrt/bvh/triangle.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/simd.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>

namespace dynrt::packet::detail {

/// Fewest rays in a node's range for the early-miss beam test to run (measured on 1M-triangle
/// and 20k-triangle scenes: below this, box-testing the rays directly is as cheap).
inline constexpr int kBeamMinLanes = 96;
/// Leaf triangles prepared (culled, permuted) at a time before the SIMD loop.
inline constexpr int kTriBatch = 16;

/// Calls `traversal.template traverse<BoxMode, TriMode>()` with the fastest modes the packet's
/// beam allows: a common octant (and origin) for the box test, a common axis permutation (and
/// origin) for the triangle test.
template <class Traversal>
void traverse_in_modes(const Beam& beam, Traversal& traversal) {
    const auto with_box = [&]<BoxMode BM>() {
        if (!beam.common_perm) {
            traversal.template traverse<BM, TriMode::kGeneral>();
        } else if (beam.common_origin) {
            traversal.template traverse<BM, TriMode::kRelative>();
        } else {
            traversal.template traverse<BM, TriMode::kPermuted>();
        }
    };
    if (!beam.common_octant) {
        with_box.template operator()<BoxMode::kGeneral>();
    } else if (beam.common_origin) {
        with_box.template operator()<BoxMode::kOctantOrigin>();
    } else {
        with_box.template operator()<BoxMode::kOctant>();
    }
}

/// The range and leaf machinery for one packet trace at W lanes per chunk, closest hit or any
/// hit (kAnyHit), with or without work counters (kCount). The traversals derive from it.
template <int W, bool kAnyHit, bool kCount>
class RangeTracer {
protected:
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    using U = typename L::U;
    static constexpr int kChunks = kPacketRays / W;

    RangeTracer(Work& w, const PacketConfig& config, PacketStats* stats, LaneMask* occluded)
        : w_(w), config_(config), culling_(config.culling), stats_(stats), occluded_(occluded) {}

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

    /// Collects in leaf_chunk_/leaf_bits_ the lanes of [first, last] to test at a leaf with
    /// box `b`: those hitting the box (stage ab), or every active lane; returns their chunks.
    template <BoxMode M>
    int select_leaf_lanes(const bvh::Aabb& b, const NodePlanes& np, int first, int last) {
        int n = 0;
        if (culling_.active_bounds) {
            for (int c = first; c <= last; ++c) {
                if (w_.chunk_bits[c] == 0) continue;
                const std::uint32_t bits = box<M>(b, np, c);
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
        return n;
    }

    /// Tests the n chunks of leaf_chunk_/leaf_bits_ against a leaf's `slots` triangles:
    /// `slot(k, tri)` writes slot k's triangle and returns its primitive index, kInvalidId for
    /// an unused slot (skipped).
    template <TriMode TM, class Slot>
    void intersect_leaf(int n, std::uint32_t slots, Slot&& slot) {
        const Beam& beam = w_.beam;
        int tested_lanes = 0;  // for the counters only
        if constexpr (kCount) {
            for (int i = 0; i < n; ++i) tested_lanes += std::popcount(leaf_bits_[i]);
            ++stats_->leaves_visited;
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

        for (std::uint32_t batch = 0; batch < slots; batch += kTriBatch) {
            // Cull and prepare up to kTriBatch triangles.
            TriData prepared[kTriBatch];
            int count = 0;
            const std::uint32_t batch_end = std::min(slots, batch + kTriBatch);
            for (std::uint32_t k = batch; k < batch_end; ++k) {
                bvh::Triangle tri;
                const std::uint32_t prim = slot(k, tri);
                if (prim == bvh::kInvalidId) continue;
                if constexpr (kCount) {
                    stats_->culled_active_bounds += std::uint64_t(w_.active_lanes - tested_lanes);
                }
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
                prepare_triangle<TM>(TriangleCoords(tri), beam, prim, prepared[count++]);
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

    // Inlined into both callers (the leaf test and intersect_first): called out of line it cost
    // BART kitchen's shadow rays a sixth of their time.
    template <TriMode TM>
    __attribute__((always_inline)) void intersect_chunk_any(int c, std::uint32_t& lanes, const TriData* tris, int count) {
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
            if (hit == 0) continue;
            // The occluder, for a caller's occluder cache (OccluderSearch::occluder).
            L::store(w_.hit_prim + base, L::select(L::from_bits(hit), L::splat(tris[j].prim), L::load(w_.hit_prim + base)));
            hits |= hit;
            live &= ~hit;
        }
        lanes = live;
        for (std::uint32_t h = hits; h != 0; h &= h - 1) terminate(base + std::countr_zero(h));
    }

    /// Any hit, before the traversal: the active lanes, chunk by chunk, against `tris` (at most
    /// kTriBatch triangles a caller expects to block the whole packet) as one leaf, without
    /// culling. It stops at the first chunk with a lane they do not block: the packet must be
    /// traversed then, and blocking a few of its rays sooner saves less than testing the rest
    /// costs. Returns true when every lane is blocked.
    template <TriMode TM>
    bool intersect_first(std::span<const PrimTriangle> tris) {
        TriData prepared[kTriBatch];
        int count = 0;
        for (std::size_t k = 0; k < tris.size() && k < std::size_t(kTriBatch); ++k) {
            prepare_triangle<TM>(TriangleCoords(tris[k].triangle), w_.beam, tris[k].prim, prepared[count++]);
        }
        for (int c = w_.first_chunk; c <= w_.last_chunk; ++c) {
            std::uint32_t lanes = w_.chunk_bits[c];
            if (lanes == 0) continue;
            intersect_chunk_any<TM>(c, lanes, prepared, count);
            if (w_.chunk_bits[c] != 0) return false;
        }
        return w_.active_lanes == 0;
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

    Work& w_;
    const PacketConfig& config_;
    const PacketCulling& culling_;
    PacketStats* stats_;
    LaneMask* occluded_;
    std::uint16_t leaf_chunk_[kChunks];
    std::uint32_t leaf_bits_[kChunks];
};

}  // namespace dynrt::packet::detail
