// Packet traversal of the wide tree: 256 rays share one stack over nodes of N = 8 children.
//
// At an inner node, two tests cover all N children in one SIMD pass each:
//   1. early hit: the range's first and last active rays against every child box (their own
//      box tests): the children both hit are entered by the whole range without testing other
//      rays (its end chunks hit, so it would not narrow), the children one hits are visited;
//   2. early miss: for the other children, interval arithmetic over all active rays (bounds on
//      origin and reciprocal direction) rules out those no ray can hit (long ranges only).
// The children left are pushed farthest first along the packet's mean direction, so the
// nearest is popped next (nearest to the rays' ends for shadow rays that converge there:
// Beam::ends_converge); a child not decided by the early hit narrows the range to its first
// and last chunk with a hit when popped (Wald, Boulos and Shirley 2007; Overbeck, Ramamoorthi
// and Mark 2008), on the rays' current hit distances. When that leaves a handful of rays in at
// most two chunks, the packet has lost coherence there: those rays continue one by one through
// the single-ray traversal of the wide tree (bvh::intersect_closest on a subtree), which costs
// far less per node than the packet machinery for a few rays (Embree's "hybrid" traversal does
// the same). At a leaf, the rays of the range are box-tested lane by lane and the blocks'
// triangles go through the shared leaf test (range_tracer.h: vertex culling, then the SIMD
// watertight test per chunk).
//
// Results equal the single-ray tracer's bit for bit for the reasons given in packet_kernels.h:
// every skip (early miss, narrowing, the leaf's per-lane box test, vertex culling) is
// conservative for the very float tests the single-ray tracers run; an early hit only enters
// a child; and ties go to the lower primitive index in every path, so the order of leaves does
// not matter. The rays handed to single-ray traversal run the wide tree's own kernels, which
// equal the binary tree's (bvh/wide_bvh.h).

#include "wide_packet_traversal.h"

#include "dynrt/bvh/prefetch.h"

#include "packet_kernels.h"
#include "range_tracer.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <type_traits>

namespace dynrt::packet::detail {
namespace {

constexpr int N = bvh::kWideWidth;
constexpr int kStackSize = N * static_cast<int>(bvh::kMaxDepth) + 1;

/// The traversal of one packet over a tree whose nodes are of type Node (bvh::WideNode or
/// bvh::QuantizedWideNode: bvh::child_box_lanes reads the boxes of either).
template <int W, bool kAnyHit, bool kCount, class Node>
class WideTraversal : RangeTracer<W, kAnyHit, kCount> {
    using Base = RangeTracer<W, kAnyHit, kCount>;
    using Base::w_;
    using Base::config_;
    using Base::stats_;
    /// N lanes, one per child of a node.
    using C = simd::Lanes<N>;
    using CF = typename C::F;

public:
    WideTraversal(const bvh::WideBvh& wide, const Node* nodes, const RayPacket& packet, Work& w,
                  const PacketConfig& config, PacketStats* stats, LaneMask* occluded,
                  std::span<const PrimTriangle> first = {})
        : Base(w, config, stats, occluded), wide_(wide), nodes_(nodes), packet_(packet), first_(first) {}

    void run() {
        if (wide_.empty() || w_.first_chunk > w_.last_chunk) return;
        traverse_in_modes(w_.beam, *this);
    }

private:
    /// Child `slot` of node `node`, to be visited by the chunks [first, last]; `entered` when
    /// the early hit already decided that the range enters it (no narrowing needed).
    struct Entry {
        std::uint32_t node;
        std::uint16_t first, last;
        std::uint8_t slot;
        bool entered;
    };

public:
    /// The traversal in one pair of modes (traverse_in_modes picks them).
    template <BoxMode BM, TriMode TM>
    void traverse() {
        const Node* nodes = nodes_;
        const Beam& beam = w_.beam;
        if constexpr (kAnyHit) {
            if (!first_.empty() && this->template intersect_first<TM>(first_)) return;
        }
        top_ = 0;
        push_children(0, w_.first_chunk, w_.last_chunk);
        while (top_ > 0) {
            const Entry e = stack_[--top_];
            int first = e.first, last = e.last;
            if constexpr (kAnyHit) {
                // Occluded rays are gone: trim chunks without active lanes from the range.
                while (first <= last && w_.chunk_bits[first] == 0) ++first;
                while (last >= first && w_.chunk_bits[last] == 0) --last;
                if (first > last) continue;
            }
            const Node& parent = nodes[e.node];
            const bvh::Aabb box = parent.box(e.slot);
            const bvh::WideSubtree below{parent.child[e.slot], parent.blocks[e.slot]};
            if constexpr (kCount) ++stats_->nodes_visited;
            if (below.blocks == 0) {
                if (!e.entered) {
                    const NodePlanes np(box, beam);
                    std::uint32_t first_bits = 0, last_bits = 0;
                    if (!this->template narrow<BM>(box, np, first, last, first_bits, last_bits)) continue;
                    if (last - first <= 1) {
                        const std::uint32_t lanes[2] = {first_bits, last != first ? last_bits : 0u};
                        if (std::popcount(lanes[0]) + std::popcount(lanes[1]) <= config_.single_ray_max) {
                            trace_lanes(below, first, lanes, 2);
                            if constexpr (kAnyHit) {
                                if (w_.active_lanes == 0) return;
                            }
                            continue;
                        }
                    }
                }
                push_children(below.child, first, last);
                continue;
            }
            // A leaf: its rays, lane by lane (stage ab), then its triangles.
            const NodePlanes np(box, beam);
            const int n = this->template select_leaf_lanes<BM>(box, np, first, last);
            if (n == 0) continue;
            const std::uint32_t slots = below.blocks * bvh::kBlockLanes;
            if (wide_.compact) {
                // The corners read through the source, kGatherBlocks blocks at a time as the
                // slots are asked for in order.
                constexpr std::uint32_t kPart = bvh::TriangleSource::kGatherMax;
                bvh::Triangle part[kPart];
                std::uint32_t part_read = ~0u;  // which kPart slots `part` holds
                const bvh::PrimBlock* blocks = wide_.prim_blocks.data() + below.child;
                this->template intersect_leaf<TM>(n, slots, [&](std::uint32_t k, bvh::Triangle& tri) {
                    const std::uint32_t prim = blocks[k / bvh::kBlockLanes].prim[k % bvh::kBlockLanes];
                    if (prim == bvh::kInvalidId) return prim;
                    if (k / kPart != part_read) {
                        part_read = k / kPart;
                        constexpr std::uint32_t kPartBlocks = bvh::WideBvh::kGatherBlocks;
                        const std::uint32_t first_block = part_read * kPartBlocks;
                        wide_.gather_leaf(below.child + first_block,
                                          std::min(kPartBlocks, below.blocks - first_block),
                                          [&](std::uint32_t j, const glm::vec3& v0, const glm::vec3& v1,
                                              const glm::vec3& v2) { part[j] = bvh::Triangle{v0, v1, v2}; });
                    }
                    tri = part[k % kPart];
                    return prim;
                });
            } else {
                const bvh::TriangleBlock* blocks = wide_.blocks.data() + below.child;
                this->template intersect_leaf<TM>(n, slots, [&](std::uint32_t k, bvh::Triangle& tri) {
                    const bvh::TriangleBlock& block = blocks[k / bvh::kBlockLanes];
                    const int lane = int(k % bvh::kBlockLanes);
                    tri = block.triangle(lane);
                    return block.prim[lane];
                });
            }
            if constexpr (kAnyHit) {
                if (w_.active_lanes == 0) return;  // every ray is occluded
            }
        }
    }

private:
    /// Tests the children of inner node `index` for the chunks [first, last] (early hit, then
    /// early miss) and pushes the ones to visit, nearest on top.
    void push_children(std::uint32_t index, int first, int last) {
        const Node& node = nodes_[index];
        std::uint32_t used = 0;
        for (int i = 0; i < N; ++i) used |= node.is_empty(i) ? 0u : 1u << i;
        // The child boxes, loaded (or decoded) once for every test below.
        CF lo[3], hi[3];
        bvh::child_box_lanes<CF>(node, lo, hi);
        // The range's first and last active rays: children both hit are entered with the
        // range as it is (it cannot narrow: its end chunks hit); children one of them hits are
        // visited, and narrowed when popped.
        const std::uint32_t first_bits = w_.chunk_bits[first], last_bits = w_.chunk_bits[last];
        const std::uint32_t hit_first =
            first_bits != 0 ? children_hit_by_lane(lo, hi, first * W + std::countr_zero(first_bits)) & used
                            : 0u;
        const int last_lane = last * W + 31 - std::countl_zero(last_bits);
        const std::uint32_t hit_last =
            last_bits == 0 ? 0u
            : last_lane == first * W + std::countr_zero(first_bits) ? hit_first
                                                                    : children_hit_by_lane(lo, hi, last_lane) & used;
        const std::uint32_t entered = hit_first & hit_last;
        std::uint32_t visit = used;
        const std::uint32_t undecided = used & ~(hit_first | hit_last);
        if (undecided != 0 && (last - first + 1) * W >= kBeamMinLanes) {
            const float tfar_hi = kAnyHit ? w_.beam.tmax_hi : this->range_tfar_max(first, last);
            const std::uint32_t missed = children_missed_by_beam(lo, hi, tfar_hi) & undecided;
            visit &= ~missed;
            if constexpr (kCount) stats_->early_misses += std::popcount(missed);
        }
        if constexpr (kCount) stats_->early_hits += std::popcount(entered);
        if (visit == 0) return;
        // Order along the packet's mean direction: the sum of a child's box corners projected
        // on it (twice the centre's projection), farthest pushed first.
        const float* mean = w_.beam.mean_dir;
        const CF key = (lo[0] + hi[0]) * C::splat(mean[0]) + (lo[1] + hi[1]) * C::splat(mean[1]) +
                       (lo[2] + hi[2]) * C::splat(mean[2]);
        // Any hit for rays that converge at their ends (Beam::ends_converge): the other way.
        const bool far_first = kAnyHit && w_.beam.ends_converge;
        int slots[N];
        int count = 0;
        for (std::uint32_t m = visit; m != 0; m &= m - 1) {
            const int i = std::countr_zero(m);
            int at = count++;
            while (at > 0 && (far_first ? key[slots[at - 1]] > key[i] : key[slots[at - 1]] < key[i])) {
                slots[at] = slots[at - 1];
                --at;
            }
            slots[at] = i;
        }
        for (int j = 0; j < count; ++j) {
            const int i = slots[j];
            prefetch_child(node, i);
            stack_[top_++] = Entry{index, std::uint16_t(first), std::uint16_t(last),
                                   std::uint8_t(i), ((entered >> i) & 1u) != 0};
        }
    }

    /// The children whose boxes (lo, hi: a node's, child_box_lanes) `lane` hits (its own Ize
    /// box test, lane_hits_boxes on N children at once; an early hit only enters a child, so it
    /// needs no exactness argument).
    std::uint32_t children_hit_by_lane(const CF (&lo)[3], const CF (&hi)[3], int lane) const {
        if constexpr (kCount) stats_->ray_box_tests += N;
        return C::bits(lane_hits_boxes<CF>(w_, lane, lo, hi));
    }

    /// The children no active ray can hit: beam_misses_boxes (packet_kernels.h) on N children
    /// at once, with each axis's near and far planes by its common sign.
    std::uint32_t children_missed_by_beam(const CF (&lo)[3], const CF (&hi)[3], float tfar_hi) const {
        const Beam& b = w_.beam;
        CF near[3], far[3];
        for (int a = 0; a < 3; ++a) {
            near[a] = b.negative[a] ? hi[a] : lo[a];
            far[a] = b.negative[a] ? lo[a] : hi[a];
        }
        return C::bits(beam_misses_boxes<CF>(b, near, far, tfar_hi));
    }

    /// The lanes in `lanes[j]` (bits of chunk first + j) continue one by one below `below`
    /// with the single-ray traversal, from their current hits.
    void trace_lanes(bvh::WideSubtree below, int first, const std::uint32_t* lanes, int chunks) {
        bvh::WideTraversalStats work;
        bvh::WideTraversalStats* counted = kCount ? &work : nullptr;
        for (int j = 0; j < chunks; ++j) {
            const int c = first + j;
            bool updated = false;
            for (std::uint32_t b = lanes[j]; b != 0; b &= b - 1) {
                const int lane = c * W + std::countr_zero(b);
                bvh::Ray ray = packet_.ray(lane);
                ray.tmax = w_.tfar[lane];
                if constexpr (kAnyHit) {
                    if (bvh::intersect_any(wide_, below, ray, counted)) this->terminate(lane);
                } else {
                    bvh::Hit hit;
                    if (w_.hit_prim[lane] != bvh::kInvalidId) {
                        hit = bvh::Hit{w_.tfar[lane], w_.hit_u[lane], w_.hit_v[lane], w_.hit_prim[lane]};
                    }
                    if (bvh::intersect_closest(wide_, below, ray, hit, counted)) {
                        w_.tfar[lane] = hit.t;
                        w_.hit_u[lane] = hit.u;
                        w_.hit_v[lane] = hit.v;
                        w_.hit_prim[lane] = hit.prim;
                        updated = true;
                    }
                }
            }
            if (updated) {
                using L = simd::Lanes<W>;
                w_.chunk_tfar_max[c] = L::reduce_max(L::load(w_.tfar + c * W));
            }
        }
        if constexpr (kCount) {
            stats_->nodes_visited += work.nodes_visited + work.leaves_visited;
            stats_->leaves_visited += work.leaves_visited;
            stats_->ray_box_tests += std::uint64_t(N) * work.nodes_visited;
            stats_->ray_triangle_tests += work.triangles_tested;
        }
    }

    /// Starts fetching what child i's visit reads: its node (four cache lines, two when
    /// quantised) or its blocks.
    void prefetch_child(const Node& node, int i) const {
        const char* p;
        int lines;
        if (node.is_leaf(i) && wide_.compact) {
            // A compact leaf's indices (its corners are read as they are tested).
            p = reinterpret_cast<const char*>(wide_.prim_blocks.data() + node.child[i]);
            lines = int(node.blocks[i] * sizeof(bvh::PrimBlock) + 63) / 64;
        } else if (node.is_leaf(i)) {
            p = reinterpret_cast<const char*>(wide_.blocks.data() + node.child[i]);
            lines = int(node.blocks[i] * sizeof(bvh::TriangleBlock) + 63) / 64;
            lines = lines < 10 ? lines : 10;
        } else {
            p = reinterpret_cast<const char*>(nodes_ + node.child[i]);
            lines = int(sizeof(Node) / 64);
        }
        for (int k = 0; k < lines; ++k) bvh::prefetch_line(p + 64 * k);
    }

    const bvh::WideBvh& wide_;
    const Node* nodes_;  ///< wide_'s nodes, of their kind
    const RayPacket& packet_;
    std::span<const PrimTriangle> first_;  ///< any hit: triangles tested before the traversal
    Entry stack_[kStackSize];
    int top_ = 0;
};

}  // namespace

template <int W>
void wide_closest(const bvh::WideBvh& wide, const RayPacket& packet, Work& w,
                  const PacketConfig& config, PacketStats* stats) {
    wide.visit_nodes([&](const auto* nodes) {
        using Node = std::remove_cvref_t<decltype(*nodes)>;
        if (stats) {
            WideTraversal<W, false, true, Node>(wide, nodes, packet, w, config, stats, nullptr).run();
        } else {
            WideTraversal<W, false, false, Node>(wide, nodes, packet, w, config, nullptr, nullptr).run();
        }
    });
}

template <int W>
void wide_any(const bvh::WideBvh& wide, const RayPacket& packet, Work& w,
              const PacketConfig& config, PacketStats* stats, LaneMask& occluded,
              std::span<const PrimTriangle> first) {
    wide.visit_nodes([&](const auto* nodes) {
        using Node = std::remove_cvref_t<decltype(*nodes)>;
        if (stats) {
            WideTraversal<W, true, true, Node>(wide, nodes, packet, w, config, stats, &occluded, first).run();
        } else {
            WideTraversal<W, true, false, Node>(wide, nodes, packet, w, config, nullptr, &occluded, first).run();
        }
    });
}

template void wide_closest<1>(const bvh::WideBvh&, const RayPacket&, Work&, const PacketConfig&,
                              PacketStats*);
template void wide_any<1>(const bvh::WideBvh&, const RayPacket&, Work&, const PacketConfig&,
                          PacketStats*, LaneMask&, std::span<const PrimTriangle>);
#if defined(__AVX512F__) || defined(__AVX2__) || defined(__SSE2__) || defined(__ARM_NEON)
// The native width, when it is not 1 (simd.h).
template void wide_closest<simd::kNativeLanes>(const bvh::WideBvh&, const RayPacket&, Work&,
                                               const PacketConfig&, PacketStats*);
template void wide_any<simd::kNativeLanes>(const bvh::WideBvh&, const RayPacket&, Work&,
                                           const PacketConfig&, PacketStats*, LaneMask&,
                                           std::span<const PrimTriangle>);
#endif

}  // namespace dynrt::packet::detail
