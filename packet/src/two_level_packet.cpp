// Packet traversal of a two-level BVH. The top level holds a handful of instances, so it is
// traversed once per packet with a lane mask per node (no ranges, no beams); each instance
// reached is traced by the packet tracer on a packet of just the lanes that reach it.
//
// Why this equals the single-ray two-level tracer bit for bit although it visits instances in
// another order and with other intermediate tmax values: an instance's tree traced with
// tmax = T returns the lexicographically smallest (t, prim) among its hits with t <= T (that is
// bvh::intersect_closest's contract, and packet::intersect_closest equals it lane by lane for
// the same ray, which to_object_space makes bit-identical in both tracers). Both tracers keep
// the running minimum of (t, object, prim) and pass its t as T, so an instance holding the
// overall minimum always returns it (T is never below it) and no instance returns anything
// smaller: both end at the overall minimum, whatever the order. The top-level box tests only
// skip instances that cannot hit within T (they are the single-ray test's arithmetic, with the
// same padding), so they never change the answer either.

#include "dynrt/packet/two_level_packet.h"

#include "dynrt/bvh/box_test_scale.h"

#include "dynrt/packet/simd.h"

#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace dynrt::packet {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The single-ray box test's growth of far distances (dynrt/bvh/box_test_scale.h, Ize 2013).
using bvh::kFarScale;

constexpr int kStackSize = 2 * static_cast<int>(bvh::kMaxDepth);

/// The packet's reciprocal directions, computed once and used at every top-level node.
struct alignas(64) InverseDirs {
    alignas(64) float x[kPacketRays];
    alignas(64) float y[kPacketRays];
    alignas(64) float z[kPacketRays];

    explicit InverseDirs(const RayPacket& p) {
        for (int i = 0; i < kPacketRays; ++i) {
            x[i] = 1.0f / p.dir_x[i];
            y[i] = 1.0f / p.dir_y[i];
            z[i] = 1.0f / p.dir_z[i];
        }
    }
};

/// The lanes of `lanes` whose segment [tmin, tmax[lane]] may meet `box`: bvh's robust single-ray
/// test (robust_box_test.h) lane by lane, with the near plane chosen by the sign bit of the
/// reciprocal direction (the octant) and the same NaN-ignoring operand order, hence the same
/// verdicts. `tnear_min` gets the smallest entry distance of the hitting lanes (+inf if none),
/// to visit nearer subtrees first.
template <int W>
LaneMask hit_box_lanes(const bvh::Aabb& box, const RayPacket& p, const InverseDirs& inv,
                       const float* tmax, const LaneMask& lanes, float& tnear_min) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    LaneMask out;
    F nearest = L::splat(kInf);
    const I zero = L::splat(std::int32_t{0});
    for (int first = 0; first < kPacketRays; first += W) {
        const std::uint32_t wanted = lanes.extract(first, W);
        if (wanted == 0) continue;
        auto slab = [&](const float* org, const float* inv_dir, float lo, float hi, F& t0, F& t1) {
            const F o = L::load(org + first);
            const F r = L::load(inv_dir + first);
            const I negative = L::bits_of(r) < zero;
            t0 = (L::select(negative, L::splat(hi), L::splat(lo)) - o) * r;
            t1 = (L::select(negative, L::splat(lo), L::splat(hi)) - o) * r;
        };
        F t0x, t1x, t0y, t1y, t0z, t1z;
        slab(p.org_x, inv.x, box.lo.x, box.hi.x, t0x, t1x);
        slab(p.org_y, inv.y, box.lo.y, box.hi.y, t0y, t1y);
        slab(p.org_z, inv.z, box.lo.z, box.hi.z, t0z, t1z);
        F tn = L::load(p.tmin + first);
        F tf = L::load(tmax + first);
        tn = L::max_into(t0x, tn);
        tn = L::max_into(t0y, tn);
        tn = L::max_into(t0z, tn);
        tf = L::min_into(t1x, tf);
        tf = L::min_into(t1y, tf);
        tf = L::min_into(t1z, tf);
        const std::uint32_t hit = L::bits(tn <= tf * L::splat(kFarScale)) & wanted;
        if (hit == 0) continue;
        out.words[first >> 6] |= std::uint64_t{hit} << (first & 63);
        nearest = L::min_into(L::select(L::from_bits(hit), tn, L::splat(kInf)), nearest);
    }
    tnear_min = L::reduce_min(nearest);
    return out;
}

/// The largest top-level padding over the active lanes' origins (bvh::top_level_pad): one
/// padded box per node for the whole packet, larger than each lane needs, so still conservative.
/// The padding grows with the origin's largest |coordinate| alone, so the largest one over the
/// lanes gives it in one call (a call per lane was a twentieth of a BART robots frame).
template <int W>
float packet_pad(const bvh::TwoLevelBvh& tlas, const RayPacket& packet) {
    if (tlas.origin_pad_rel == 0.0f) return 0.0f;
    using L = simd::Lanes<W>;
    using F = typename L::F;
    F largest = L::splat(0.0f);
    for (int first = 0; first < kPacketRays; first += W) {
        const std::uint32_t active = packet.active.extract(first, W);
        if (active == 0) continue;
        const F m = L::max_into(L::abs(L::load(packet.org_x + first)),
                                L::max_into(L::abs(L::load(packet.org_y + first)), L::abs(L::load(packet.org_z + first))));
        largest = L::max_into(L::select(L::from_bits(active), m, L::splat(0.0f)), largest);
    }
    return bvh::top_level_pad(tlas, glm::vec3(L::reduce_max(largest), 0.0f, 0.0f));
}

/// Fills `local` with the lanes `lanes` of `packet` in `instance`'s object space, tmax[lane]
/// taken from `tmax`: bvh::to_object_space's arithmetic, term for term and in its order, W lanes
/// at a time (the same bits: no fused multiply-adds in this module). Lanes of a chunk outside
/// `lanes` are transformed too and left inactive, as a cleared packet's are left as they were
/// (lane by lane, with the merge below, this was a fifth of BART robots' camera rays).
template <int W>
void make_local_packet(const bvh::Instance& instance, const RayPacket& packet, const LaneMask& lanes,
                       const float* tmax, RayPacket& local) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    local.active = lanes;
    const glm::mat4& m = instance.world_to_object;
    for (int first = 0; first < kPacketRays; first += W) {
        if (lanes.extract(first, W) == 0) continue;
        const F ox = L::load(packet.org_x + first), oy = L::load(packet.org_y + first),
                oz = L::load(packet.org_z + first);
        const F dx = L::load(packet.dir_x + first), dy = L::load(packet.dir_y + first),
                dz = L::load(packet.dir_z + first);
        if (instance.identity) {
            L::store(local.org_x + first, ox);
            L::store(local.org_y + first, oy);
            L::store(local.org_z + first, oz);
            L::store(local.dir_x + first, dx);
            L::store(local.dir_y + first, dy);
            L::store(local.dir_z + first, dz);
        } else {
            const auto row = [&](int r, F x, F y, F z) {
                return L::splat(m[0][r]) * x + L::splat(m[1][r]) * y + L::splat(m[2][r]) * z;
            };
            L::store(local.org_x + first, row(0, ox, oy, oz) + L::splat(m[3][0]));
            L::store(local.org_y + first, row(1, ox, oy, oz) + L::splat(m[3][1]));
            L::store(local.org_z + first, row(2, ox, oy, oz) + L::splat(m[3][2]));
            L::store(local.dir_x + first, row(0, dx, dy, dz));
            L::store(local.dir_y + first, row(1, dx, dy, dz));
            L::store(local.dir_z + first, row(2, dx, dy, dz));
        }
        L::store(local.tmin + first, L::load(packet.tmin + first));
        L::store(local.tmax + first, L::load(tmax + first));
    }
}

/// Merges an instance's hits `h` on `lanes` into `out` by the single-ray tracer's tie rule, W
/// lanes at a time: the smallest (t, object, prim) wins; before a lane's first hit its object is
/// kInvalidId and best_t its tmax. A winning lane's best_t becomes its t; `found_any` is set and
/// `shortened` counts the lanes shortened (traverse_top's hits()).
template <int W>
void merge_closest(const PacketHits& h, std::uint32_t object, const LaneMask& lanes, float* best_t,
                   InstanceHits& out, bool& found_any, std::uint32_t& shortened) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    using U = typename L::U;
    const U instance_object = L::splat(object);
    for (int first = 0; first < kPacketRays; first += W) {
        const std::uint32_t wanted = lanes.extract(first, W);
        if (wanted == 0) continue;
        const F t = L::load(h.t + first);
        const F best = L::load(best_t + first);
        const U prim = L::load(h.prim + first);
        const U out_prim = L::load(out.hits.prim + first);
        const U out_object = L::load(out.object + first);
        const I wins_tie = L::select(I(instance_object != out_object), I(instance_object < out_object),
                                     I(prim < out_prim));
        const I wins = I(prim != L::splat(bvh::kInvalidId)) &
                       L::select(I(t != best), I(t < best), wins_tie);
        const std::uint32_t won = L::bits(wins) & wanted;
        if (won == 0) continue;
        const I take = L::from_bits(won);
        L::store(out.hits.t + first, L::select(take, t, L::load(out.hits.t + first)));
        L::store(out.hits.u + first, L::select(take, L::load(h.u + first), L::load(out.hits.u + first)));
        L::store(out.hits.v + first, L::select(take, L::load(h.v + first), L::load(out.hits.v + first)));
        L::store(out.hits.prim + first, L::select(take, prim, out_prim));
        L::store(out.object + first, L::select(take, instance_object, out_object));
        L::store(best_t + first, L::select(take, t, best));
        found_any = true;
        shortened += static_cast<std::uint32_t>(std::popcount(won));
    }
}

/// Scratch of one trace: the bottom-level packets (kept off the caller's hot data).
struct Scratch {
    RayPacket local;
    PacketHits local_hits;
};

/// Visits the top level front to back: a stack of (node, lanes that hit its box when it was
/// pushed), the child with the nearer entry distance visited first. A popped node is tested
/// again only if a lane's tmax shrank since its push (`hits()`, the number of times a closest
/// hit shortened a lane, changed): a closer hit may rule it out; otherwise its lanes are the
/// ones that hit it then. `visit_leaf` traces the instances of a leaf for the given lanes.
/// `tmax` is read live (closest hit shrinks it); `live` returns the lanes still worth tracing
/// (any hit drops occluded lanes, and never shortens one).
template <int W, class Live, class Hits, class VisitLeaf>
void traverse_top(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, const float* tmax,
                  Live&& live, Hits&& hits, VisitLeaf&& visit_leaf) {
    const InverseDirs inv(packet);
    const float pad = packet_pad<W>(tlas, packet);
    const bvh::BvhNode* nodes = tlas.top.nodes.data();
    struct Entry {
        std::uint32_t node;
        /// hits() when the lanes were tested against the node's box (the root: never).
        std::uint32_t tested_at;
        bool tested;
        LaneMask lanes;
    };
    Entry stack[kStackSize];
    int top = 0;
    stack[top++] = Entry{0, 0, false, packet.active};
    while (top > 0) {
        const Entry e = stack[--top];
        const LaneMask candidates = e.lanes & live();
        if (!candidates.any()) continue;
        const bvh::BvhNode& node = nodes[e.node];
        LaneMask lanes = candidates;
        if (!e.tested || e.tested_at != hits()) {
            float tnear;
            lanes = hit_box_lanes<W>(bvh::grow_box(node.box, pad), packet, inv, tmax, candidates, tnear);
            if (!lanes.any()) continue;
        }
        if (node.is_leaf()) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                visit_leaf(tlas.instances[tlas.top.prim_ids[k]], lanes & live());
            }
            continue;
        }
        float t_left, t_right;
        const LaneMask left =
            hit_box_lanes<W>(bvh::grow_box(nodes[node.first].box, pad), packet, inv, tmax, lanes, t_left);
        const LaneMask right = hit_box_lanes<W>(bvh::grow_box(nodes[node.first + 1].box, pad), packet,
                                                inv, tmax, lanes, t_right);
        // Pushed far first, so the nearer child is popped next.
        const bool right_first = t_right < t_left;
        const std::uint32_t now = hits();
        const Entry far{right_first ? node.first : node.first + 1, now, true, right_first ? left : right};
        const Entry near{right_first ? node.first + 1 : node.first, now, true, right_first ? right : left};
        if (far.lanes.any()) stack[top++] = far;
        if (near.lanes.any()) stack[top++] = near;
    }
}

void check_lanes(int lanes) {
    if (lanes != simd::kNativeLanes && lanes != 1) {
        throw std::invalid_argument("packet tracer: lanes must be " +
                                    std::to_string(simd::kNativeLanes) + " or 1, not " +
                                    std::to_string(lanes));
    }
}

template <int W>
void closest_lanes(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, InstanceHits& out,
                   const PacketConfig& config, PacketStats* stats) {
    alignas(64) float best_t[kPacketRays];
    for (int i = 0; i < kPacketRays; ++i) best_t[i] = packet.tmax[i];
    bool found_any = false;
    std::uint32_t shortened = 0;  // lanes whose best_t a hit lowered, for traverse_top
    Scratch scratch;
    auto visit = [&](const bvh::Instance& instance, const LaneMask& lanes) {
        if (!lanes.any()) return;
        // A packet no instance has shortened yet, reaching an identity instance whole, is traced
        // as it is: the common case of one static object, where copying would be pure cost.
        const bool as_is = instance.identity && !found_any && lanes == packet.active;
        if (!as_is) make_local_packet<W>(instance, packet, lanes, best_t, scratch.local);
        intersect_closest(*instance.blas, as_is ? packet : scratch.local, scratch.local_hits, config,
                          stats);
        merge_closest<W>(scratch.local_hits, instance.object, lanes, best_t, out, found_any, shortened);
    };
    const LaneMask all = packet.active;
    traverse_top<W>(tlas, packet, best_t, [&] { return all; }, [&] { return shortened; }, visit);
}

/// Most instances whose triangles an any-hit trace tests first (InstanceOccluderSearch); the
/// triangles of any others are left out, which only forgoes their head start.
constexpr int kFirstInstancesMax = 4;
/// Most triangles tested first in one instance.
constexpr int kFirstTrianglesMax = 16;

/// The triangles of `search` grouped by instance, at most kFirstInstancesMax instances of at
/// most kFirstTrianglesMax triangles, in order of first appearance.
struct FirstByInstance {
    std::uint32_t instance[kFirstInstancesMax];
    PrimTriangle tris[kFirstInstancesMax][kFirstTrianglesMax];
    int count[kFirstInstancesMax] = {};
    int instances = 0;

    FirstByInstance(std::span<const InstanceTriangle> first, std::size_t instance_count) {
        for (const InstanceTriangle& t : first) {
            if (t.instance >= instance_count) continue;
            int i = 0;
            while (i < instances && instance[i] != t.instance) ++i;
            if (i == instances) {
                if (instances == kFirstInstancesMax) continue;
                instance[instances++] = t.instance;
            }
            if (count[i] < kFirstTrianglesMax) tris[i][count[i]++] = t.tri;
        }
    }
    std::span<const PrimTriangle> of(int i) const { return {tris[i], std::size_t(count[i])}; }
    bool holds(std::uint32_t index) const {
        for (int i = 0; i < instances; ++i) {
            if (instance[i] == index) return true;
        }
        return false;
    }
};

template <int W>
void any_lanes(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, LaneMask& occluded,
               const PacketConfig& config, PacketStats* stats, InstanceOccluderSearch* search) {
    Scratch scratch;
    LaneMask local_occluded;
    alignas(64) std::uint32_t local_occluder[kPacketRays];
    const auto index_of = [&](const bvh::Instance& instance) {
        return std::uint32_t(&instance - tlas.instances.data());
    };
    // Traces `lanes` through `instance`'s tree, its triangles `first` first.
    auto trace = [&](const bvh::Instance& instance, const LaneMask& lanes, std::span<const PrimTriangle> first) {
        const bool as_is = instance.identity && lanes == packet.active;
        if (!as_is) make_local_packet<W>(instance, packet, lanes, packet.tmax, scratch.local);
        OccluderSearch blas_search{first, local_occluder, {}};
        intersect_any(*instance.blas, as_is ? packet : scratch.local, local_occluded, config, stats,
                      search ? &blas_search : nullptr);
        occluded |= local_occluded;
        if (search == nullptr) return;
        search->blocked_first |= blas_search.blocked_first;
        if (search->occluder_instance == nullptr) return;
        const std::uint32_t index = index_of(instance);
        local_occluded.for_each([&](int lane) {
            const bool known = local_occluder[lane] != bvh::kInvalidId;
            search->occluder_instance[lane] = known ? index : bvh::kInvalidId;
            search->occluder_prim[lane] = local_occluder[lane];
        });
    };
    // The instances of the triangles to test first go first, each traced whole for the lanes
    // not yet occluded (which is the answer the top level would have had from it), and are
    // then passed over by the top level.
    const FirstByInstance first(search ? search->test_first : std::span<const InstanceTriangle>{},
                                tlas.instances.size());
    if (const bvh::Instance* sole = bvh::sole_identity_instance(tlas)) {
        // No top level to walk and no lanes to copy (see sole_identity_instance).
        trace(*sole, packet.active, first.instances > 0 ? first.of(0) : std::span<const PrimTriangle>{});
        return;
    }
    for (int i = 0; i < first.instances; ++i) {
        const LaneMask lanes = packet.active & ~occluded;
        if (lanes.any()) trace(tlas.instances[first.instance[i]], lanes, first.of(i));
    }
    auto visit = [&](const bvh::Instance& instance, const LaneMask& lanes) {
        if (!lanes.any() || (first.instances > 0 && first.holds(index_of(instance)))) return;
        trace(instance, lanes, {});
    };
    traverse_top<W>(tlas, packet, packet.tmax, [&] { return packet.active & ~occluded; },
                    [] { return std::uint32_t{0}; }, visit);
}

}  // namespace

void intersect_closest(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, InstanceHits& hits,
                       const PacketConfig& config, PacketStats* stats) {
    check_lanes(config.lanes);
    if (const bvh::Instance* sole = bvh::sole_identity_instance(tlas)) {
        // No top level to walk and no lanes to copy (see sole_identity_instance).
        intersect_closest(*sole->blas, packet, hits.hits, config, stats);
        for (int i = 0; i < kPacketRays; ++i) {
            hits.object[i] = hits.hits.prim[i] != bvh::kInvalidId ? sole->object : bvh::kInvalidId;
        }
        return;
    }
    for (int i = 0; i < kPacketRays; ++i) {
        hits.hits.t[i] = kInf;
        hits.hits.u[i] = 0.0f;
        hits.hits.v[i] = 0.0f;
        hits.hits.prim[i] = bvh::kInvalidId;
        hits.object[i] = bvh::kInvalidId;
    }
    if (tlas.top.empty() || !packet.active.any()) return;
    if (config.lanes == 1) {
        closest_lanes<1>(tlas, packet, hits, config, stats);
    } else {
        closest_lanes<simd::kNativeLanes>(tlas, packet, hits, config, stats);
    }
}

void intersect_any(const bvh::TwoLevelBvh& tlas, const RayPacket& packet, LaneMask& occluded,
                   const PacketConfig& config, PacketStats* stats, InstanceOccluderSearch* search) {
    check_lanes(config.lanes);
    if (search != nullptr) search->blocked_first = LaneMask{};
    occluded = LaneMask{};
    if (tlas.top.empty() || !packet.active.any()) return;
    if (config.lanes == 1) {
        any_lanes<1>(tlas, packet, occluded, config, stats, search);
    } else {
        any_lanes<simd::kNativeLanes>(tlas, packet, occluded, config, stats, search);
    }
}

}  // namespace dynrt::packet
