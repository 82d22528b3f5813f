// Triangle BVH: build over the non-degenerate triangles, single-ray closest-hit and any-hit
// traversal. Box tests follow Ize 2013, "Robust BVH Ray Traversal" (JCGT 2(2)); triangles use
// the watertight test of Woop, Benthin and Wald 2013.

#include "dynrt/bvh/triangle_bvh.h"

#include "binned_sah_core.h"
#include "morton_core.h"
#include "float4.h"
#include "huge_pages.h"
#include "robust_box_test.h"
#include "tree_checks.h"
#include "watertight_kernel.h"
#include "wide_collapse.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dynrt::bvh {
namespace {

using detail::BoxRay;
using detail::hit_box;
using detail::kFarScale;
using detail::octant_of;

/// Triangles per block of the parallel passes that filter degenerates and fill references.
constexpr std::size_t kBlock = 16 * 1024;
/// Largest leaf of the wide Morton build (BuildMethod::morton with the wide tree), in
/// triangles: two blocks. Against leaves of one block, on sphere:1000000 and soup:1000000: the
/// build 30% faster (21 and 23 ms against 31 and 35), 64 and 60 bytes per triangle against 83
/// and 88, and the frame's rays 1-2% slower (benchmarks/README.md, issue 38's section).
constexpr std::uint32_t kWideMortonLeafPrims = 8;

// The robust box test (BoxRay, octant_of, hit_box, kFarScale) lives in robust_box_test.h,
// shared with the two-level BVH's top level.

/// Per-ray constants of the two-box test: lanes 0 and 1 compute entry distances of the left and
/// right child, lanes 2 and 3 the negated exit distances (the reciprocal direction negated,
/// which is exact), so one NaN-ignoring `x > acc ? x : acc` chain yields both the largest entry
/// and the smallest exit distance of both boxes, bit for bit as hit_box does.
struct PairRay {
    detail::Float4 org_x, org_y, org_z;
    detail::Float4 inv_x, inv_y, inv_z;

    explicit PairRay(const BoxRay& r)
        : org_x(detail::splat4(r.org.x)), org_y(detail::splat4(r.org.y)),
          org_z(detail::splat4(r.org.z)),
          inv_x(detail::Float4{r.inv_dir.x, r.inv_dir.x, -r.inv_dir.x, -r.inv_dir.x}),
          inv_y(detail::Float4{r.inv_dir.y, r.inv_dir.y, -r.inv_dir.y, -r.inv_dir.y}),
          inv_z(detail::Float4{r.inv_dir.z, r.inv_dir.z, -r.inv_dir.z, -r.inv_dir.z}) {}
};

/// hit_box for the two children at `pair[0]`, `pair[1]` at once. `bounds` is
/// {tmin, tmin, -tmax, -tmax}. Returns bit 0 for the left child, bit 1 for the right one.
template <int kOctant>
inline unsigned hit_pair(const BvhNode* pair, const PairRay& r, detail::Float4 bounds,
                         float& t_left, float& t_right) {
    constexpr bool kNegX = (kOctant & 1) != 0;
    constexpr bool kNegY = (kOctant & 2) != 0;
    constexpr bool kNegZ = (kOctant & 4) != 0;
    const Aabb& a = pair[0].box;
    const Aabb& b = pair[1].box;
    using detail::Float4;
    const Float4 px{kNegX ? a.hi.x : a.lo.x, kNegX ? b.hi.x : b.lo.x, kNegX ? a.lo.x : a.hi.x,
                    kNegX ? b.lo.x : b.hi.x};
    const Float4 py{kNegY ? a.hi.y : a.lo.y, kNegY ? b.hi.y : b.lo.y, kNegY ? a.lo.y : a.hi.y,
                    kNegY ? b.lo.y : b.hi.y};
    const Float4 pz{kNegZ ? a.hi.z : a.lo.z, kNegZ ? b.hi.z : b.lo.z, kNegZ ? a.lo.z : a.hi.z,
                    kNegZ ? b.lo.z : b.hi.z};
    const Float4 tx = (px - r.org_x) * r.inv_x;
    const Float4 ty = (py - r.org_y) * r.inv_y;
    const Float4 tz = (pz - r.org_z) * r.inv_z;
    Float4 acc = bounds;
    acc = tx > acc ? tx : acc;
    acc = ty > acc ? ty : acc;
    acc = tz > acc ? tz : acc;
    t_left = acc[0];
    t_right = acc[1];
    const unsigned hit_left = acc[0] <= -acc[2] * kFarScale ? 1u : 0u;
    const unsigned hit_right = acc[1] <= -acc[3] * kFarScale ? 2u : 0u;
    return hit_left | hit_right;
}

// ---- Traversal ------------------------------------------------------------------------------

constexpr int kStackSize = 2 * static_cast<int>(kMaxDepth);

/// Front-to-back stack traversal. The nearer child is visited next and the farther one pushed
/// with its entry distance, so a closest-hit query pops it only if it can still beat the hit or
/// tie with it (entry distance <= tmax, never <, since a tie may still win on the primitive
/// index). The stack holds at most one entry per level of the current path (depth <= kMaxDepth).
template <bool kAnyHit, bool kCount, int kOctant>
bool traverse(const TriangleBvh& accel, const Ray& ray, Hit& hit, TraversalStats* stats) {
    if (accel.bvh.nodes.empty()) return false;
    const BvhNode* nodes = accel.bvh.nodes.data();
    const BoxRay box_ray(ray);
    const PairRay pair_ray(box_ray);
    const WatertightRay tri_ray(ray);
    const float tmin = ray.tmin;
    float tmax = ray.tmax;
    detail::Float4 bounds{tmin, tmin, -tmax, -tmax};

    struct Entry {
        std::uint32_t node;
        float tnear;
    };
    Entry stack[kStackSize];
    int top = 0;
    bool found = false;

    float tnear;
    if (!hit_box<kOctant>(nodes[0].box, box_ray, tmin, tmax, tnear)) return false;
    std::uint32_t index = 0;
    while (true) {
        const BvhNode& node = nodes[index];
        if constexpr (kCount) ++stats->nodes_visited;
        if (!node.is_leaf()) {
            const std::uint32_t left = node.first;
            float t_left, t_right;
            const unsigned hits = hit_pair<kOctant>(nodes + left, pair_ray, bounds, t_left, t_right);
            if (hits == 3u) {
                // Nearer child next, the other pushed; selects rather than branches, as which
                // child is nearer is close to a coin flip.
                const bool right_first = t_right < t_left;
                stack[top++] = Entry{right_first ? left : left + 1, right_first ? t_left : t_right};
                index = right_first ? left + 1 : left;
                continue;
            }
            if (hits != 0u) {
                index = left + (hits >> 1);
                continue;
            }
        } else {
            const Triangle* tris = accel.tris.data();
            const std::uint32_t end = node.first + node.count;
            if constexpr (kCount) stats->triangles_tested += node.count;
            for (std::uint32_t k = node.first; k < end; ++k) {
                Hit candidate;
                if (detail::watertight_test(tri_ray, tris[k], tmin, tmax, candidate)) {
                    if constexpr (kAnyHit) {
                        return true;
                    } else {
                        // candidate.t <= tmax here. On a tie (shared edges and vertices) the
                        // lower primitive index wins, so the answer does not depend on the
                        // order leaves are visited in, and packet traversal, which visits them
                        // in another order, finds the very same hit. Before the first hit,
                        // hit.prim is kInvalidId and anything wins.
                        const std::uint32_t prim = accel.bvh.prim_ids[k];
                        if (candidate.t < tmax || prim < hit.prim) {
                            hit = candidate;
                            hit.prim = prim;
                            tmax = candidate.t;
                            bounds = detail::Float4{tmin, tmin, -tmax, -tmax};
                            found = true;
                        }
                    }
                }
            }
        }
        // Pop the next subtree that can still contain a hit closer than the current one; the
        // comparison is the box test's own with the current tmax.
        while (true) {
            if (top == 0) return found;
            const Entry e = stack[--top];
            if (e.tnear <= tmax * kFarScale) {
                index = e.node;
                break;
            }
        }
    }
}

template <bool kAnyHit, bool kCount>
bool traverse_octant(const TriangleBvh& accel, const Ray& ray, Hit& hit, TraversalStats* stats) {
    switch (octant_of(ray.dir)) {
        case 0: return traverse<kAnyHit, kCount, 0>(accel, ray, hit, stats);
        case 1: return traverse<kAnyHit, kCount, 1>(accel, ray, hit, stats);
        case 2: return traverse<kAnyHit, kCount, 2>(accel, ray, hit, stats);
        case 3: return traverse<kAnyHit, kCount, 3>(accel, ray, hit, stats);
        case 4: return traverse<kAnyHit, kCount, 4>(accel, ray, hit, stats);
        case 5: return traverse<kAnyHit, kCount, 5>(accel, ray, hit, stats);
        case 6: return traverse<kAnyHit, kCount, 6>(accel, ray, hit, stats);
        default: return traverse<kAnyHit, kCount, 7>(accel, ray, hit, stats);
    }
}

}  // namespace

TriangleBvh build_triangle_bvh(const TriangleSource& tris, const BuildConfig& config) {
    return build_triangle_bvh(tris, config, TriangleBvh{});
}

TriangleBvh build_triangle_bvh(const TriangleSource& tris, const BuildConfig& config,
                               TriangleBvh&& recycled) {
    detail::check_config(config);
    // The result takes over the recycled vectors, emptied: their capacity is what is reused.
    TriangleBvh accel = std::move(recycled);
    accel.tris.clear();
    accel.skipped_ids.clear();
    accel.degenerate_skipped = 0;
    Bvh recycled_tree = std::move(accel.bvh);
    accel.bvh = Bvh{};
    WideBvh recycled_wide = std::move(accel.wide);
    accel.wide = WideBvh{};
    // The wide builders write the kind of blocks the tree they are handed says.
    recycled_wide.compact = config.compact_leaves;
    recycled_wide.source = config.compact_leaves ? tris : TriangleSource{};
    // ... and the collapse the kind of nodes (the Morton builder writes float nodes, which
    // quantize_nodes replaces at the end).
    recycled_wide.quantized = config.quantized_nodes;
    const std::size_t n = tris.size();
    if (n == 0) return accel;
    if (n >= (std::size_t{1} << 31)) {
        throw std::length_error("build_triangle_bvh: more than 2^31 - 1 triangles");
    }

    // Pass 1: mark non-degenerate triangles and count them per block. Fixed blocks and an
    // ordered prefix sum keep the reference order, hence the tree, deterministic.
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    auto keep = std::make_unique_for_overwrite<std::uint8_t[]>(n);
    std::vector<std::size_t> block_offset(blocks + 1, 0);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        const std::size_t end = std::min(n, (b + 1) * kBlock);
        std::size_t kept = 0;
        for (std::size_t i = b * kBlock; i < end; ++i) {
            keep[i] = is_degenerate(tris[i]) ? 0 : 1;
            kept += keep[i];
        }
        block_offset[b + 1] = kept;
    });
    for (std::size_t b = 0; b < blocks; ++b) block_offset[b + 1] += block_offset[b];
    const std::size_t count = block_offset[blocks];
    accel.degenerate_skipped = n - count;
    accel.skipped_ids.resize(n - count);
    if (count == 0) {
        for (std::size_t i = 0; i < n; ++i) accel.skipped_ids[i] = static_cast<std::uint32_t>(i);
        return accel;
    }

    // Pass 2: references, the skipped ids (block b's start after the b * kBlock - kept ones of
    // the blocks before it) and per-block bounds. The wide Morton build makes no references:
    // its sort keys are made from the triangles themselves (pass 3), 32 bytes a triangle
    // fewer at its peak and between its builds.
    const bool morton = config.method == BuildMethod::morton;
    const bool wide = config.wide && config.leaf_size_max <= kWideLeafSizeMax;
    const bool wide_morton = morton && wide;
    // A copy of a tree shares its scratch: the copy being rebuilt gets its own.
    if (morton && (!accel.morton_scratch || accel.morton_scratch.use_count() > 1)) {
        accel.morton_scratch = std::make_shared<detail::MortonScratch>();
    }
    if (!morton) accel.morton_scratch.reset();
    std::unique_ptr<detail::BoxCenterRef[]> own_refs;
    if (!morton) own_refs = detail::make_uninitialized_buffer<detail::BoxCenterRef>(count);
    detail::BoxCenterRef* const refs =
        wide_morton ? nullptr : morton ? accel.morton_scratch->reserve_refs(count) : own_refs.get();
    struct BlockBounds {
        Aabb box, centers;
    };
    std::vector<BlockBounds> block_bounds(blocks);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        const std::size_t end = std::min(n, (b + 1) * kBlock);
        std::size_t out = block_offset[b];
        std::size_t skipped_out = b * kBlock - block_offset[b];
        BlockBounds bounds;
        for (std::size_t i = b * kBlock; i < end; ++i) {
            if (!keep[i]) {
                accel.skipped_ids[skipped_out++] = static_cast<std::uint32_t>(i);
                continue;
            }
            const Triangle t = tris[i];
            const glm::vec3 lo = glm::min(glm::min(t.v0, t.v1), t.v2);
            const glm::vec3 hi = glm::max(glm::max(t.v0, t.v1), t.v2);
            if (refs) refs[out++] = detail::BoxCenterRef{lo, static_cast<std::uint32_t>(i), hi, 0};
            bounds.box.extend(lo);
            bounds.box.extend(hi);
            bounds.centers.extend(detail::box_center(lo, hi));
        }
        block_bounds[b] = bounds;
    });
    Aabb root_box, root_centers;
    for (const BlockBounds& b : block_bounds) {
        root_box.extend(b.box);
        root_centers.extend(b.centers);
    }

    if (wide_morton) {
        // Pass 3: each kept triangle's key, `code << 32 | index`, in index order (the order
        // of the references it replaces, so the sort and the tree are theirs bit for bit).
        detail::MortonKeys& keys = accel.morton_scratch->buffers.keys;
        keys.reserve(count);
        const MortonGrid grid(root_centers);
        tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
            const std::size_t end = std::min(n, (b + 1) * kBlock);
            std::uint64_t* out = keys.keys.get() + block_offset[b];
            for (std::size_t i = b * kBlock; i < end; ++i) {
                if (!keep[i]) continue;
                const Triangle t = tris[i];
                const glm::vec3 center = detail::box_center(glm::min(glm::min(t.v0, t.v1), t.v2),
                                                            glm::max(glm::max(t.v0, t.v1), t.v2));
                *out++ = std::uint64_t{grid.code(center)} << 32 | i;
            }
        });
        keep.reset();
        // A tree with compact leaves was asked for memory first: its scratch is freed as the
        // build goes, and not kept for the next build (whose fresh pages then cost faults).
        accel.wide = detail::build_wide_morton(
            tris, detail::sort_morton_keys(keys, count), keys, count,
            std::min(kWideMortonLeafPrims, config.leaf_size_max), config.compact_leaves,
            std::move(recycled_wide));
        if (config.compact_leaves) accel.morton_scratch.reset();
        if (config.quantized_nodes) quantize_nodes(accel.wide);
        return accel;
    }
    // The binary tree: the result itself without the wide tree (with its triangles copied in
    // leaf order), else the collapse's input, dropped after it (the collapse reads the
    // caller's triangles through the tree's ids: no leaf-order copy at the build's peak).
    Bvh binary_storage;
    Bvh& binary = wide ? binary_storage : accel.bvh;
    std::vector<Triangle>& leaf_tris = accel.tris;
    if (!wide) binary = std::move(recycled_tree);
    leaf_tris.clear();
    // Copy the triangles in leaf order while the builder makes its hierarchy: three serial
    // fills (triangles, nodes, ids) of fresh memory share the threads.
    const auto gather_leaf_order = [&](auto id_of) {
        if (wide) return;
        detail::resize_with_huge_pages(leaf_tris, count);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kBlock),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i < r.end(); ++i) {
                                  leaf_tris[i] = tris[id_of(i)];
                              }
                          });
    };
    if (morton) {
        binary = detail::build_morton_from_prim_refs(
            refs, count, root_centers, config,
            [&](std::span<const std::uint32_t> ids) {
                gather_leaf_order([ids](std::size_t i) { return ids[i]; });
            },
            accel.morton_scratch->buffers, std::move(binary));
    } else {
        // The references are handed back as the builder finishes with them, and freed before
        // it lays out its nodes (32 bytes a triangle off the build's peak).
        binary = detail::build_from_prim_refs(
            refs, count, root_box, root_centers, config,
            [&](std::span<const std::uint32_t> ids) {
                gather_leaf_order([ids](std::size_t i) { return ids[i]; });
            },
            std::move(binary), [&] { own_refs.reset(); });
    }
    if (wide) {
        accel.wide = collapse_to_wide_consuming<kWideWidth>(std::move(binary), tris, WideCosts{}, std::move(recycled_wide));
    }
    return accel;
}

Aabb TriangleBvh::root_box() const {
    if (!wide.empty()) return wide.root_box;
    return bvh.empty() ? Aabb{} : bvh.nodes[0].box;
}

double sah_cost(const TriangleBvh& accel, const SahCosts& costs) {
    return accel.wide.empty() ? sah_cost(accel.bvh, costs) : sah_cost(accel.wide, costs);
}

BvhStats compute_stats(const TriangleBvh& accel) {
    if (accel.wide.empty()) return compute_stats(accel.bvh);
    const WideStats wide = compute_stats(accel.wide);
    BvhStats stats;
    stats.nodes = wide.nodes;
    stats.leaves = wide.leaves;
    stats.leaf_prims_mean = wide.leaf_prims_mean;
    stats.leaf_prims_max = wide.leaf_prims_max;
    stats.depth = wide.depth;
    return stats;
}

namespace {

Hit intersect_closest_binary(const TriangleBvh& accel, const Ray& ray) {
    Hit hit;
    traverse_octant<false, false>(accel, ray, hit, nullptr);
    return hit;
}

bool intersect_any_binary(const TriangleBvh& accel, const Ray& ray) {
    Hit unused;
    return traverse_octant<true, false>(accel, ray, unused, nullptr);
}

}  // namespace

Hit intersect_closest(const TriangleBvh& accel, const Ray& ray) {
    if (!accel.wide.empty()) return intersect_closest(accel.wide, ray);
    return intersect_closest_binary(accel, ray);
}

bool intersect_any(const TriangleBvh& accel, const Ray& ray) {
    if (!accel.wide.empty()) return intersect_any(accel.wide, ray);
    return intersect_any_binary(accel, ray);
}

namespace {
void add_wide_work(TraversalStats& stats, const WideTraversalStats& wide) {
    stats.nodes_visited += wide.nodes_visited + wide.leaves_visited;
    stats.triangles_tested += wide.triangles_tested;
}
}  // namespace

Hit intersect_closest(const TriangleBvh& accel, const Ray& ray, TraversalStats& stats) {
    if (!accel.wide.empty()) {
        WideTraversalStats wide;
        const Hit hit = intersect_closest(accel.wide, ray, wide);
        add_wide_work(stats, wide);
        return hit;
    }
    Hit hit;
    traverse_octant<false, true>(accel, ray, hit, &stats);
    return hit;
}

bool intersect_any(const TriangleBvh& accel, const Ray& ray, TraversalStats& stats) {
    if (!accel.wide.empty()) {
        WideTraversalStats wide;
        const bool hit = intersect_any(accel.wide, ray, wide);
        add_wide_work(stats, wide);
        return hit;
    }
    Hit unused;
    return traverse_octant<true, true>(accel, ray, unused, &stats);
}

namespace {

/// validate for a TriangleBvh that holds the wide tree.
std::string validate_wide(const TriangleBvh& accel, std::span<const Triangle> tris) {
    if (accel.skipped_ids.size() != accel.degenerate_skipped) {
        return std::to_string(accel.skipped_ids.size()) + " skipped ids for degenerate_skipped " +
               std::to_string(accel.degenerate_skipped);
    }
    std::vector<std::uint8_t> skipped(tris.size(), 0);
    for (std::size_t k = 0; k < accel.skipped_ids.size(); ++k) {
        const std::uint32_t id = accel.skipped_ids[k];
        if (id >= tris.size()) return "skipped id " + std::to_string(id) + " is out of range";
        if (k > 0 && id <= accel.skipped_ids[k - 1]) return "skipped ids are not ascending";
        if (!is_degenerate(tris[id])) {
            return "triangle " + std::to_string(id) + " is not degenerate but not in the tree";
        }
        skipped[id] = 1;
    }
    std::vector<std::uint32_t> in_tree;
    in_tree.reserve(tris.size() - accel.skipped_ids.size());
    for (std::size_t i = 0; i < tris.size(); ++i) {
        if (!skipped[i]) in_tree.push_back(static_cast<std::uint32_t>(i));
    }
    const std::string error = validate(accel.wide, tris, in_tree);
    return error.empty() ? error : "wide tree: " + error;
}

}  // namespace

std::string validate(const TriangleBvh& accel, std::span<const Triangle> tris,
                     std::uint32_t leaf_size_max) {
    if (!accel.wide.empty()) {
        if (!accel.bvh.empty() || !accel.tris.empty()) {
            return "holds both the wide and the binary tree";
        }
        return validate_wide(accel, tris);
    }
    std::vector<Aabb> boxes(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i) boxes[i] = tris[i].bounds();
    std::vector<std::uint8_t> in_tree;
    std::string error = detail::check_tree(accel.bvh, boxes, leaf_size_max, true, in_tree);
    if (!error.empty()) return error;

    std::size_t missing = 0;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        if (in_tree[i]) continue;
        if (!is_degenerate(tris[i])) {
            return "triangle " + std::to_string(i) + " is not degenerate but not in the tree";
        }
        if (missing >= accel.skipped_ids.size() || accel.skipped_ids[missing] != i) {
            return "triangle " + std::to_string(i) + " is absent but not skipped_ids[" +
                   std::to_string(missing) + "]";
        }
        ++missing;
    }
    if (missing != accel.degenerate_skipped) {
        return "degenerate_skipped is " + std::to_string(accel.degenerate_skipped) + " but " +
               std::to_string(missing) + " triangles are absent";
    }
    if (accel.skipped_ids.size() != missing) {
        return std::to_string(accel.skipped_ids.size()) + " skipped ids for " +
               std::to_string(missing) + " absent triangles";
    }
    if (accel.tris.size() != accel.bvh.prim_ids.size()) {
        return std::to_string(accel.tris.size()) + " triangles for " +
               std::to_string(accel.bvh.prim_ids.size()) + " primitive ids";
    }
    for (std::size_t k = 0; k < accel.tris.size(); ++k) {
        if (std::memcmp(&accel.tris[k], &tris[accel.bvh.prim_ids[k]], sizeof(Triangle)) != 0) {
            return "tris[" + std::to_string(k) + "] is not a copy of triangle " +
                   std::to_string(accel.bvh.prim_ids[k]);
        }
    }
    return {};
}

}  // namespace dynrt::bvh
