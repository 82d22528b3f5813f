// Bottom-up refit of a BVH whose primitives moved (Wald, Boulos and Shirley 2007, "Ray Tracing
// Deformable Scenes Using Dynamic Bounding Volume Hierarchies"). In parallel as Embree refits
// (subtrees as separate tasks, then the nodes above them), but split by subtree size rather
// than at a fixed depth, so an unbalanced tree still gives even tasks: a subtree large enough
// to pay for a task is split into two oneTBB tasks, a smaller one refitted serially, and each
// inner node is finished once both its children are. Every value a node gets is computed by
// one expression over its children's values, so the schedule cannot change a bit of the
// result.

#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/prefetch.h"

#include "sah_terms.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace dynrt::bvh {
namespace {

/// A subtree spanning at least this many primitives is refitted as two tasks (one per child).
/// A task costs about a microsecond; refitting this many primitives takes some tens, so the
/// overhead stays small while a million-triangle tree still gives hundreds of tasks.
constexpr std::size_t kTaskMinPrims = 4 * 1024;
/// Skipped ids checked per task when there are many of them.
constexpr std::size_t kSkippedGrain = 16 * 1024;
/// How many prim_ids positions ahead a leaf prefetches its primitives. Leaf order is a spatial
/// order, the caller's is usually another, so the gather misses the cache about once per
/// primitive (half the refit time in the profile without it, three quarters for a soup); the
/// leaves are visited in prim_ids order, so the addresses needed next are known ahead.
constexpr std::uint32_t kPrefetchAhead = 24;

using detail::half_area_d;

[[noreturn]] void malformed(std::uint32_t index, const char* what) {
    throw std::invalid_argument("refit: malformed tree: node " + std::to_string(index) + " " +
                                what);
}

/// Asks the cache for primitive `id`'s lines: a box (24 bytes) may straddle two.
inline void prefetch_prim(std::span<const Aabb> boxes, std::uint32_t id) {
    const char* p = reinterpret_cast<const char*>(boxes.data() + id);
    prefetch_line(p);
    prefetch_line(p + sizeof(Aabb) - 1);
}
/// A triangle's corners (an indexed source's triple was asked for further ahead).
inline void prefetch_prim(const TriangleSource& tris, std::uint32_t id) { tris.prefetch_corners(id); }

/// Calls `visit(k, prims[ids[k]])` for each position k of the leaf [first, first + count),
/// prefetching the primitive kPrefetchAhead positions on (and an indexed source's index triple
/// twice as far).
template <class Prims, class Visit>
inline void for_each_leaf_prim(const Prims& prims, std::span<const std::uint32_t> ids,
                               std::uint32_t first, std::uint32_t count, Visit&& visit) {
    for (std::uint32_t k = first; k < first + count; ++k) {
        if (k + kPrefetchAhead < ids.size() && ids[k + kPrefetchAhead] < prims.size()) {
            prefetch_prim(prims, ids[k + kPrefetchAhead]);
        }
        if constexpr (std::is_same_v<Prims, TriangleSource>) {
            if (prims.indexed() && k + 2 * kPrefetchAhead < ids.size() &&
                ids[k + 2 * kPrefetchAhead] < prims.size()) {
                prims.prefetch(ids[k + 2 * kPrefetchAhead]);
            }
        }
        const std::uint32_t id = ids[k];
        if (id >= prims.size()) {
            throw std::invalid_argument("refit: malformed tree: prim_ids[" + std::to_string(k) +
                                        "] = " + std::to_string(id) + " is out of range");
        }
        visit(k, prims[id]);
    }
}

/// Leaf boxes of a TriangleBvh: copies each leaf's triangles into leaf order while bounding
/// them, so every triangle is read once, and notes whether any differs from the copy it
/// replaces (bit for bit, as refit_wide compares a block).
struct TriangleLeaves {
    const TriangleSource& tris;
    std::span<const std::uint32_t> ids;
    Triangle* leaf_tris;
    std::atomic<bool>& moved;

    Aabb operator()(std::uint32_t first, std::uint32_t count) const {
        Aabb box;
        bool differs = false;
        for_each_leaf_prim(tris, ids, first, count, [&](std::uint32_t k, const Triangle& t) {
            differs |= std::memcmp(&leaf_tris[k], &t, sizeof t) != 0;
            leaf_tris[k] = t;
            box.extend(t.v0);
            box.extend(t.v1);
            box.extend(t.v2);
        });
        if (differs) moved.store(true, std::memory_order_relaxed);
        return box;
    }
};

/// Leaf boxes of a plain Bvh from the caller's per-primitive boxes.
struct BoxLeaves {
    std::span<const Aabb> boxes;
    std::span<const std::uint32_t> ids;

    Aabb operator()(std::uint32_t first, std::uint32_t count) const {
        Aabb box;
        for_each_leaf_prim(boxes, ids, first, count,
                           [&](std::uint32_t, const Aabb& b) { box.extend(b); });
        return box;
    }
};

/// The recursion shared by both refits. Each call refits one subtree and returns its
/// unnormalised SAH sum: sum over its nodes of half_area * traversal (inner) or
/// half_area * count * intersection (leaf); dividing by the root's half area gives sah_cost.
template <class LeafBox>
class Refitter {
public:
    Refitter(Bvh& bvh, const LeafBox& leaf_box, const SahCosts& costs)
        : nodes_(bvh.nodes.data()), node_count_(bvh.nodes.size()),
          prim_count_(bvh.prim_ids.size()), leaf_box_(leaf_box), costs_(costs) {}

    /// Refits the whole tree and returns its SAH cost.
    double run() const {
        if (node_count_ == 0) return 0.0;
        const double sum = refit_parallel(0, 1);
        const double root_area = half_area_d(nodes_[0].box);
        if (root_area > 0.0) return sum / root_area;
        // A flat or point-like root: sah_cost weighs every node 1 (the limit of inflating all
        // boxes uniformly). A valid tree of n nodes has (n - 1) / 2 inner ones.
        const double inner = static_cast<double>((node_count_ - 1) / 2);
        return inner * costs_.traversal + static_cast<double>(prim_count_) * costs_.intersection;
    }

private:
    /// Refits the subtree at `index` on this thread. `depth` counts nodes from the root (1).
    double refit_serial(std::uint32_t index, std::uint32_t depth) const {
        BvhNode& node = nodes_[index];
        if (node.is_leaf()) return refit_leaf(node, index);
        check_inner(node, index, depth);
        const double left = refit_serial(node.first, depth + 1);
        const double right = refit_serial(node.first + 1, depth + 1);
        return finish_inner(node, left, right);
    }

    /// Refits the subtree at `index`, its two halves as separate tasks while it spans at least
    /// kTaskMinPrims primitives.
    double refit_parallel(std::uint32_t index, std::uint32_t depth) const {
        BvhNode& node = nodes_[index];
        if (node.is_leaf() || span_estimate(index) < kTaskMinPrims) {
            return refit_serial(index, depth);
        }
        check_inner(node, index, depth);
        double left = 0.0, right = 0.0;
        tbb::parallel_invoke([&] { left = refit_parallel(node.first, depth + 1); },
                             [&] { right = refit_parallel(node.first + 1, depth + 1); });
        return finish_inner(node, left, right);
    }

    double refit_leaf(BvhNode& node, std::uint32_t index) const {
        if (node.first > prim_count_ || node.count > prim_count_ - node.first) {
            malformed(index, "has a leaf range outside prim_ids");
        }
        node.box = leaf_box_(node.first, node.count);
        return half_area_d(node.box) * node.count * costs_.intersection;
    }

    void check_inner(const BvhNode& node, std::uint32_t index, std::uint32_t depth) const {
        if (node.first == 0 || node.first >= node_count_ - 1) {
            malformed(index, "has a child index out of range");
        }
        if (depth >= kMaxDepth) malformed(index, "has children deeper than kMaxDepth");
    }

    /// The one place an inner node's values are computed: serial and parallel refits both end
    /// here with the same operands, hence the same bits.
    double finish_inner(BvhNode& node, double left, double right) const {
        Aabb box = nodes_[node.first].box;
        box.extend(nodes_[node.first + 1].box);
        node.box = box;
        return half_area_d(box) * costs_.traversal + left + right;
    }

    /// The number of prim_ids positions between the subtree's leftmost and rightmost leaves:
    /// exactly its primitive count for the builder's trees, whose subtrees cover contiguous
    /// ranges. Only the task split depends on it, never a result, so a tree without that
    /// property is refitted correctly, just less evenly in parallel. Descends two paths.
    std::size_t span_estimate(std::uint32_t index) const {
        std::uint32_t left = index, right = index;
        for (std::uint32_t step = 0; step < kMaxDepth; ++step) {
            const bool left_done = nodes_[left].is_leaf();
            const bool right_done = nodes_[right].is_leaf();
            if (left_done && right_done) {
                const std::size_t begin = nodes_[left].first;
                const std::size_t end = std::size_t{nodes_[right].first} + nodes_[right].count;
                return end > begin ? end - begin : 0;
            }
            // Stop on a bad index; refit_serial then reports it.
            if ((!left_done && nodes_[left].first + 1 >= node_count_) ||
                (!right_done && nodes_[right].first + 1 >= node_count_)) {
                return 0;
            }
            if (!left_done) left = nodes_[left].first;
            if (!right_done) right = nodes_[right].first + 1;
        }
        return 0;
    }

    BvhNode* nodes_;
    std::size_t node_count_;
    std::size_t prim_count_;
    const LeafBox& leaf_box_;
    SahCosts costs_;
};

/// The lowest caller index among `ids` whose triangle is not degenerate, or kInvalidId.
std::uint32_t first_with_area(std::span<const std::uint32_t> ids, const TriangleSource& tris) {
    auto scan = [&](std::size_t begin, std::size_t end, std::uint32_t found) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::uint32_t id = ids[k];
            if (id >= tris.size()) {
                throw std::invalid_argument("refit: skipped id " + std::to_string(id) +
                                            " is out of range");
            }
            if (id < found && !is_degenerate(tris[id])) found = id;
        }
        return found;
    };
    if (ids.size() < kSkippedGrain) return scan(0, ids.size(), kInvalidId);
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, ids.size(), kSkippedGrain), kInvalidId,
        [&](const tbb::blocked_range<std::size_t>& r, std::uint32_t found) {
            return scan(r.begin(), r.end(), found);
        },
        [](std::uint32_t a, std::uint32_t b) { return std::min(a, b); });
}

}  // namespace

RefitResult refit(TriangleBvh& accel, const TriangleSource& tris, const SahCosts& costs) {
    const std::size_t built_count = accel.triangle_count() + accel.degenerate_skipped;
    if (tris.size() != built_count) {
        throw std::invalid_argument("refit: " + std::to_string(tris.size()) +
                                    " triangles for a tree built over " +
                                    std::to_string(built_count));
    }
    if (accel.skipped_ids.size() != accel.degenerate_skipped) {
        throw std::invalid_argument("refit: " + std::to_string(accel.skipped_ids.size()) +
                                    " skipped ids for degenerate_skipped " +
                                    std::to_string(accel.degenerate_skipped) +
                                    " (not a tree from build_triangle_bvh)");
    }
    if (accel.wide.empty() && accel.tris.size() != accel.bvh.prim_ids.size()) {
        throw std::invalid_argument("refit: " + std::to_string(accel.tris.size()) +
                                    " triangles in leaf order for " +
                                    std::to_string(accel.bvh.prim_ids.size()) + " primitive ids");
    }

    RefitResult result;
    // Checked before anything changes, so a refused refit leaves a tree that still matches the
    // previous triangles.
    result.triangle_with_area = first_with_area(accel.skipped_ids, tris);
    if (result.triangle_with_area != kInvalidId) {
        result.status = RefitStatus::skipped_triangle_has_area;
        return result;
    }
    if (!accel.wide.empty()) {
        const WideRefit wide = refit_wide(accel.wide, tris, costs);
        result.sah_cost = wide.sah_cost;
        result.moved = wide.moved;
        return result;
    }
    std::atomic<bool> moved{false};
    const TriangleLeaves leaves{tris, accel.bvh.prim_ids, accel.tris.data(), moved};
    result.sah_cost = Refitter<TriangleLeaves>(accel.bvh, leaves, costs).run();
    result.moved = moved.load();
    return result;
}

RefitResult refit(Bvh& bvh, std::span<const Aabb> boxes, const SahCosts& costs) {
    if (boxes.size() != bvh.prim_ids.size()) {
        throw std::invalid_argument("refit: " + std::to_string(boxes.size()) +
                                    " boxes for a tree over " +
                                    std::to_string(bvh.prim_ids.size()) + " primitives");
    }
    const BoxLeaves leaves{boxes, bvh.prim_ids};
    RefitResult result;
    result.sah_cost = Refitter<BoxLeaves>(bvh, leaves, costs).run();
    return result;
}

}  // namespace dynrt::bvh
