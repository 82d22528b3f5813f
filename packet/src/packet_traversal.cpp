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
// The per-lane kernels and why the results equal the single-ray tracer's bit for bit:
// packet_kernels.h. The range and leaf machinery shared with the wide tree's packet
// traversal (wide_packet_traversal.cpp): range_tracer.h.

#include "dynrt/packet/packet_traversal.h"

#include "dynrt/bvh/prefetch.h"

#include "packet_kernels.h"
#include "packet_work.h"
#include "range_tracer.h"
#include "wide_packet_traversal.h"

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

int native_simd_lanes() { return simd::kNativeLanes; }

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

using namespace detail;

constexpr int kStackSize = 2 * static_cast<int>(bvh::kMaxDepth) + 2;

/// Packet traversal of the binary tree.
template <int W, bool kAnyHit, bool kCount>
class Traversal : RangeTracer<W, kAnyHit, kCount> {
    using Base = RangeTracer<W, kAnyHit, kCount>;
    using typename Base::L;
    using Base::w_;
    using Base::config_;
    using Base::stats_;

public:
    Traversal(const bvh::TriangleBvh& accel, Work& w, const PacketConfig& config,
              PacketStats* stats, LaneMask* occluded, std::span<const PrimTriangle> first = {})
        : Base(w, config, stats, occluded), accel_(accel), first_(first) {}

    void run() {
        if (accel_.bvh.nodes.empty() || w_.first_chunk > w_.last_chunk) return;
        traverse_in_modes(w_.beam, *this);
    }

private:
    struct Entry {
        std::uint32_t node;
        std::uint16_t first, last;
    };

public:
    /// The traversal in one pair of modes (traverse_in_modes picks them).
    template <BoxMode BM, TriMode TM>
    void traverse() {
        const bvh::BvhNode* nodes = accel_.bvh.nodes.data();
        const Beam& beam = w_.beam;
        if constexpr (kAnyHit) {
            if (!first_.empty() && this->template intersect_first<TM>(first_)) return;
        }
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
                    if (this->beam_rules_out(np, first, last)) {
                        if constexpr (kCount) ++stats_->early_misses;
                        continue;
                    }
                    std::uint32_t first_bits = 0, last_bits = 0;
                    if (!this->template narrow<BM>(node.box, np, first, last, first_bits, last_bits)) continue;
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
                // Nearer child (along the packet's mean direction) on top of the stack; for
                // any hit of rays that converge at their ends (Beam::ends_converge), the one
                // nearer their ends.
                const bvh::Aabb& l = nodes[node.first].box;
                const bvh::Aabb& r = nodes[node.first + 1].box;
                float along = 0.0f;
                for (int a = 0; a < 3; ++a) {
                    along += ((r.lo[a] + r.hi[a]) - (l.lo[a] + l.hi[a])) * beam.mean_dir[a];
                }
                const bool right_first = kAnyHit && beam.ends_converge ? along > 0.0f : along < 0.0f;
                const std::uint32_t near = right_first ? node.first + 1 : node.first;
                const std::uint32_t far = right_first ? node.first : node.first + 1;
                // What the children will read next (their children's boxes, or a leaf's
                // triangles) is far apart in memory: start fetching it now.
                prefetch_below(nodes[far]);
                prefetch_below(nodes[near]);
                stack[top++] = Entry{far, std::uint16_t(first), std::uint16_t(last)};
                stack[top++] = Entry{near, std::uint16_t(first), std::uint16_t(last)};
                continue;
            }
            const NodePlanes np(node.box, beam);
            if (this->beam_rules_out(np, first, last)) {
                if constexpr (kCount) ++stats_->early_misses;
                continue;
            }
            const int n = this->template select_leaf_lanes<BM>(node.box, np, first, last);
            if (n == 0) continue;
            const bvh::Triangle* tris = accel_.tris.data() + node.first;
            const std::uint32_t* prims = accel_.bvh.prim_ids.data() + node.first;
            this->template intersect_leaf<TM>(n, node.count, [&](std::uint32_t k, bvh::Triangle& tri) {
                tri = tris[k];
                return prims[k];
            });
            if constexpr (kAnyHit) {
                if (w_.active_lanes == 0) return;  // every ray is occluded
            }
        }
    }

private:
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
                        this->terminate(lane);
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
            for (const char* p = first; p < end; p += 64) bvh::prefetch_line(p);
            bvh::prefetch_line(end - 1);
            bvh::prefetch_line(accel_.bvh.prim_ids.data() + node.first);
        } else {
            // A child pair is 64 bytes but need not start on a cache line.
            bvh::prefetch_line(accel_.bvh.nodes.data() + node.first);
            bvh::prefetch_line(accel_.bvh.nodes.data() + node.first + 1);
        }
    }

    const bvh::TriangleBvh& accel_;
    std::span<const PrimTriangle> first_;  ///< any hit: triangles tested before the traversal
};

template <int W>
void closest_with(const bvh::TriangleBvh& accel, const RayPacket& packet, PacketHits& hits,
                  const PacketConfig& config, PacketStats* stats) {
    Work w;
    detail::prepare<W, false>(packet, w);
    if (stats) ++stats->packets;
    if (!accel.wide.empty()) {
        wide_closest<W>(accel.wide, packet, w, config, stats);
    } else if (stats) {
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
              const PacketConfig& config, PacketStats* stats, OccluderSearch* search) {
    Work w;
    detail::prepare<W, true>(packet, w);
    occluded = LaneMask{};
    if (stats) ++stats->packets;
    const std::span<const PrimTriangle> first = search ? search->test_first : std::span<const PrimTriangle>{};
    if (!accel.wide.empty()) {
        wide_any<W>(accel.wide, packet, w, config, stats, occluded, first);
    } else if (stats) {
        Traversal<W, true, true>(accel, w, config, stats, &occluded, first).run();
    } else {
        Traversal<W, true, false>(accel, w, config, nullptr, &occluded, first).run();
    }
    if (search == nullptr) return;
    // The first triangles' lanes: those whose occluder is one of them (a lane blocked there
    // is never tested again).
    search->blocked_first = LaneMask{};
    if (search->occluder != nullptr) std::memcpy(search->occluder, w.hit_prim, sizeof w.hit_prim);
    if (first.empty()) return;
    occluded.for_each([&](int lane) {
        const std::uint32_t prim = w.hit_prim[lane];
        for (const PrimTriangle& t : first) {
            if (t.prim == prim) {
                search->blocked_first.set(lane);
                break;
            }
        }
    });
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
                   const PacketConfig& config, PacketStats* stats, OccluderSearch* search) {
    check_lanes(config.lanes);
    if (config.lanes == 1) {
        any_with<1>(accel, packet, occluded, config, stats, search);
    } else {
        any_with<simd::kNativeLanes>(accel, packet, occluded, config, stats, search);
    }
}

}  // namespace dynrt::packet
