// Single-ray traversal of the wide tree: all N child boxes of a node in one SIMD pass (the
// conservative test of Ize 2013, "Robust BVH Ray Traversal", lane by lane as robust_box_test.h
// computes it), the children that are hit visited nearest first (closest hit) or in any order
// with an exit at the first hit (any hit), and leaves tested four triangles at a time
// (watertight_block.h). The stack keeps each pushed child with its entry distance, and a
// closest-hit query pops only those that can still hold a hit at or before the current one.

#include "dynrt/bvh/wide_bvh.h"
#include "dynrt/bvh/prefetch.h"

#include "robust_box_test.h"
#include "watertight_block.h"
#include "wide_simd.h"

#include <algorithm>

namespace dynrt::bvh {
namespace {

using detail::kFarScale;

/// One child reference: an inner node (blocks == 0) or a leaf's block range.
struct ChildRef {
    std::uint32_t child;
    std::uint32_t blocks;
};

template <int N>
struct BoxRayN {
    using F = typename detail::WideLanes<N>::F;
    F org_x, org_y, org_z, inv_x, inv_y, inv_z, far_scale;

    explicit BoxRayN(const detail::BoxRay& r)
        : org_x(detail::splat<N>(r.org.x)), org_y(detail::splat<N>(r.org.y)),
          org_z(detail::splat<N>(r.org.z)), inv_x(detail::splat<N>(r.inv_dir.x)),
          inv_y(detail::splat<N>(r.inv_dir.y)), inv_z(detail::splat<N>(r.inv_dir.z)),
          far_scale(detail::splat<N>(kFarScale)) {}
};

/// hit_box for the N children of `node` (a WideNode or a QuantizedWideNode) at once: returns
/// the mask of children met within [tmin, tmax] and their entry distances in `tnear`, bit for
/// bit hit_box's on the node's (decoded) boxes.
template <int N, int kOctant, class Node>
__attribute__((always_inline)) inline std::uint32_t hit_children(
    const Node& node, const BoxRayN<N>& r, typename detail::WideLanes<N>::F tmin,
    typename detail::WideLanes<N>::F far_limit, typename detail::WideLanes<N>::F& tnear) {
    using F = typename detail::WideLanes<N>::F;
    constexpr bool kNegX = (kOctant & 1) != 0;
    constexpr bool kNegY = (kOctant & 2) != 0;
    constexpr bool kNegZ = (kOctant & 4) != 0;
    F lo[3], hi[3];
    child_box_lanes<F>(node, lo, hi);
    const F t0x = ((kNegX ? hi[0] : lo[0]) - r.org_x) * r.inv_x;
    const F t1x = ((kNegX ? lo[0] : hi[0]) - r.org_x) * r.inv_x;
    const F t0y = ((kNegY ? hi[1] : lo[1]) - r.org_y) * r.inv_y;
    const F t1y = ((kNegY ? lo[1] : hi[1]) - r.org_y) * r.inv_y;
    const F t0z = ((kNegZ ? hi[2] : lo[2]) - r.org_z) * r.inv_z;
    const F t1z = ((kNegZ ? lo[2] : hi[2]) - r.org_z) * r.inv_z;
    F tn = tmin;
    F tf = far_limit;
    detail::clip_to_slabs(t0x, t1x, t0y, t1y, t0z, t1z, tn, tf);
    tnear = tn;
    return detail::lane_mask<N>(tn <= tf * r.far_scale) & used_slots_filter(node);
}

constexpr int kStackSize = 8 * static_cast<int>(kMaxDepth);

/// Starts fetching what a visit of `ref` reads first: an inner node's cache lines (four, two
/// when quantised), or a
/// leaf's first block (two and a half lines; a compact block's indices, one line). Issued for
/// every child of a node that the ray hits when there are several, so that their misses
/// overlap each other and the visit of the nearest one (Embree's traverser does the same); on
/// a million incoherent rays half of the time was the first read of a node or block.
template <int N, class Node>
__attribute__((always_inline)) inline void prefetch_child(const WideBvhOf<N>& wide,
                                                          const Node* nodes, ChildRef ref) {
    if (ref.blocks != 0 && wide.compact) {
        prefetch_line(wide.prim_blocks.data() + ref.child);
        return;
    }
    const char* p = ref.blocks == 0 ? reinterpret_cast<const char*>(nodes + ref.child)
                                    : reinterpret_cast<const char*>(wide.blocks.data() + ref.child);
    constexpr int kLines = int(sizeof(Node) / 64);
    static_assert(sizeof(TriangleBlock) <= 3 * 64);
    for (int k = 0; k < (ref.blocks == 0 ? kLines : 3); ++k) prefetch_line(p + 64 * k);
}

/// Traverses from `current`: the root node (`from_root`, which first tests the root box), or
/// a subtree whose box the caller knows the ray meets. Improves on `hit` (closest hit; ray.tmax
/// is its t while there is one); true when a hit was found below `current`. `nodes` is the
/// tree's node array, of either kind (WideBvhOf::visit_nodes).
template <int N, bool kAnyHit, bool kCount, int kOctant, class Node>
bool traverse(const WideBvhOf<N>& wide, const Node* nodes, ChildRef current, bool from_root,
              const Ray& ray, Hit& hit, WideTraversalStats* stats) {
    using F = typename detail::WideLanes<N>::F;
    const detail::BoxRay box_ray(ray);
    const BoxRayN<N> wide_ray(box_ray);
    const detail::BlockRay tri_ray{WatertightRay(ray)};
    const float tmin = ray.tmin;
    float tmax = ray.tmax;
    // Broadcast once; the tmax vectors change only when a hit shrinks the segment.
    using F4 = detail::WideLanes<kBlockLanes>::F;
    const F tmin_n = detail::splat<N>(tmin);
    const F4 tmin_4 = detail::splat<kBlockLanes>(tmin);
    F tmax_n = detail::splat<N>(tmax);
    F4 tmax_4 = detail::splat<kBlockLanes>(tmax);

    struct Entry {
        ChildRef ref;
        float tnear;
    };
    Entry stack[kStackSize];
    int top = 0;
    bool found = false;

    float root_near;
    if (from_root && !detail::hit_box<kOctant>(wide.root_box, box_ray, tmin, tmax, root_near)) {
        return false;
    }
    while (true) {
        if (current.blocks == 0) {
            const Node& node = nodes[current.child];
            if constexpr (kCount) ++stats->nodes_visited;
            F tnear;
            std::uint32_t mask = hit_children<N, kOctant>(node, wide_ray, tmin_n, tmax_n, tnear);
            if (mask != 0) {
                const int first = __builtin_ctz(mask);
                mask &= mask - 1;
                if (mask == 0) {
                    current = ChildRef{node.child[first], node.blocks[first]};
                    continue;
                }
                prefetch_child(wide, nodes, ChildRef{node.child[first], node.blocks[first]});
                for (std::uint32_t m = mask; m != 0; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    prefetch_child(wide, nodes, ChildRef{node.child[i], node.blocks[i]});
                }
                if constexpr (kAnyHit) {
                    // Any order finds an occluder; push the others as they come.
                    while (mask != 0) {
                        const int i = __builtin_ctz(mask);
                        mask &= mask - 1;
                        stack[top++] = Entry{ChildRef{node.child[i], node.blocks[i]}, tnear[i]};
                    }
                    current = ChildRef{node.child[first], node.blocks[first]};
                    continue;
                } else {
                    // Sort the hit children by entry distance, farthest first, onto the stack
                    // (insertion into the run of entries this node pushes), then visit the
                    // nearest.
                    const int base = top;
                    auto push_sorted = [&](int i) {
                        const Entry e{ChildRef{node.child[i], node.blocks[i]}, tnear[i]};
                        int at = top++;
                        while (at > base && stack[at - 1].tnear < e.tnear) {
                            stack[at] = stack[at - 1];
                            --at;
                        }
                        stack[at] = e;
                    };
                    push_sorted(first);
                    while (mask != 0) {
                        const int i = __builtin_ctz(mask);
                        mask &= mask - 1;
                        push_sorted(i);
                    }
                    current = stack[--top].ref;
                    continue;
                }
            }
        } else {
            if constexpr (kCount) ++stats->leaves_visited;
            // A compact leaf's blocks are gathered here, kGatherBlocks at a time, as they are
            // tested.
            TriangleBlock gathered[WideBvhOf<N>::kGatherBlocks];
            const std::uint32_t end = current.child + current.blocks;
            for (std::uint32_t b = current.child; b != end; ++b) {
                const TriangleBlock* block;
                if (wide.compact) {
                    const std::uint32_t part = (b - current.child) % WideBvhOf<N>::kGatherBlocks;
                    if (part == 0) wide.gather_blocks(b, std::min(WideBvhOf<N>::kGatherBlocks, end - b), gathered);
                    block = &gathered[part];
                } else {
                    block = &wide.blocks[b];
                }
                if constexpr (kCount) {
                    for (int lane = 0; lane < kBlockLanes; ++lane) {
                        stats->triangles_tested += block->prim[lane] != kInvalidId ? 1 : 0;
                    }
                }
                const detail::BlockHits hits = detail::watertight_block(tri_ray, *block, tmin_4, tmax_4);
                if (hits.mask == 0) continue;
                if constexpr (kAnyHit) {
                    return true;
                } else {
                    // Lane by lane, as the scalar loop takes triangles one after the other: a
                    // lane is kept if its t is within the current tmax and beats the hit so far
                    // (ties to the lower primitive index, so the answer does not depend on the
                    // order in which leaves or lanes are visited).
                    std::uint32_t mask = hits.mask;
                    while (mask != 0) {
                        const int lane = __builtin_ctz(mask);
                        mask &= mask - 1;
                        const float t = hits.t[lane];
                        const std::uint32_t prim = block->prim[lane];
                        if (t <= tmax && (t < tmax || prim < hit.prim)) {
                            hit.t = t;
                            hit.u = hits.bary_v[lane] / hits.det[lane];
                            hit.v = hits.bary_w[lane] / hits.det[lane];
                            hit.prim = prim;
                            tmax = t;
                            found = true;
                        }
                    }
                    tmax_n = detail::splat<N>(tmax);
                    tmax_4 = detail::splat<kBlockLanes>(tmax);
                }
            }
        }
        // Pop the next child that can still hold a hit at or before the current one.
        while (true) {
            if (top == 0) return found;
            const Entry e = stack[--top];
            if (kAnyHit || e.tnear <= tmax * kFarScale) {
                current = e.ref;
                break;
            }
        }
    }
}

template <int N, bool kAnyHit, bool kCount, class Node>
bool traverse_octant(const WideBvhOf<N>& wide, const Node* nodes, ChildRef start, bool from_root,
                     const Ray& ray, Hit& hit, WideTraversalStats* stats) {
    switch (detail::octant_of(ray.dir)) {
        case 0: return traverse<N, kAnyHit, kCount, 0>(wide, nodes, start, from_root, ray, hit, stats);
        case 1: return traverse<N, kAnyHit, kCount, 1>(wide, nodes, start, from_root, ray, hit, stats);
        case 2: return traverse<N, kAnyHit, kCount, 2>(wide, nodes, start, from_root, ray, hit, stats);
        case 3: return traverse<N, kAnyHit, kCount, 3>(wide, nodes, start, from_root, ray, hit, stats);
        case 4: return traverse<N, kAnyHit, kCount, 4>(wide, nodes, start, from_root, ray, hit, stats);
        case 5: return traverse<N, kAnyHit, kCount, 5>(wide, nodes, start, from_root, ray, hit, stats);
        case 6: return traverse<N, kAnyHit, kCount, 6>(wide, nodes, start, from_root, ray, hit, stats);
        default: return traverse<N, kAnyHit, kCount, 7>(wide, nodes, start, from_root, ray, hit, stats);
    }
}

/// traverse_octant on the tree's nodes of either kind, with counting when `stats` is given.
template <int N, bool kAnyHit>
bool traverse_counted(const WideBvhOf<N>& wide, ChildRef start, bool from_root, const Ray& ray,
                      Hit& hit, WideTraversalStats* stats) {
    return wide.visit_nodes([&](const auto* nodes) {
        if (stats) return traverse_octant<N, kAnyHit, true>(wide, nodes, start, from_root, ray, hit, stats);
        return traverse_octant<N, kAnyHit, false>(wide, nodes, start, from_root, ray, hit, nullptr);
    });
}

/// A query of the whole tree: none when the ray misses the root box.
template <int N, bool kAnyHit>
bool traverse_tree(const WideBvhOf<N>& wide, const Ray& ray, Hit& hit, WideTraversalStats* stats) {
    return !wide.empty() && traverse_counted<N, kAnyHit>(wide, ChildRef{0, 0}, true, ray, hit, stats);
}

/// A query below one subtree, for a ray that meets its box.
template <int N, bool kAnyHit>
bool traverse_subtree(const WideBvhOf<N>& wide, WideSubtree subtree, const Ray& ray, Hit& hit,
                      WideTraversalStats* stats) {
    return traverse_counted<N, kAnyHit>(wide, ChildRef{subtree.child, subtree.blocks}, false, ray,
                                        hit, stats);
}

}  // namespace

template <int N>
Hit intersect_closest(const WideBvhOf<N>& wide, const Ray& ray) {
    Hit hit;
    traverse_tree<N, false>(wide, ray, hit, nullptr);
    return hit;
}

template <int N>
Hit intersect_closest(const WideBvhOf<N>& wide, const Ray& ray, WideTraversalStats& stats) {
    Hit hit;
    traverse_tree<N, false>(wide, ray, hit, &stats);
    return hit;
}

template <int N>
bool intersect_any(const WideBvhOf<N>& wide, const Ray& ray) {
    Hit unused;
    return traverse_tree<N, true>(wide, ray, unused, nullptr);
}

template <int N>
bool intersect_any(const WideBvhOf<N>& wide, const Ray& ray, WideTraversalStats& stats) {
    Hit unused;
    return traverse_tree<N, true>(wide, ray, unused, &stats);
}

template <int N>
bool intersect_closest(const WideBvhOf<N>& wide, WideSubtree subtree, const Ray& ray, Hit& hit,
                       WideTraversalStats* stats) {
    return traverse_subtree<N, false>(wide, subtree, ray, hit, stats);
}

template <int N>
bool intersect_any(const WideBvhOf<N>& wide, WideSubtree subtree, const Ray& ray,
                   WideTraversalStats* stats) {
    Hit unused;
    return traverse_subtree<N, true>(wide, subtree, ray, unused, stats);
}

#define DYNRT_WIDE_TRAVERSAL(N)                                                                 \
    template Hit intersect_closest<N>(const WideBvhOf<N>&, const Ray&);                        \
    template Hit intersect_closest<N>(const WideBvhOf<N>&, const Ray&, WideTraversalStats&);   \
    template bool intersect_any<N>(const WideBvhOf<N>&, const Ray&);                           \
    template bool intersect_any<N>(const WideBvhOf<N>&, const Ray&, WideTraversalStats&);      \
    template bool intersect_closest<N>(const WideBvhOf<N>&, WideSubtree, const Ray&, Hit&,     \
                                       WideTraversalStats*);                                   \
    template bool intersect_any<N>(const WideBvhOf<N>&, WideSubtree, const Ray&,               \
                                   WideTraversalStats*);
DYNRT_WIDE_TRAVERSAL(4)
DYNRT_WIDE_TRAVERSAL(8)
#undef DYNRT_WIDE_TRAVERSAL

}  // namespace dynrt::bvh
