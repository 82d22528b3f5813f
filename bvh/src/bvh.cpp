// Tree-wide figures and invariant checks. SAH cost after MacDonald and Booth 1990, "Heuristics
// for ray tracing using space subdivision".

#include "sah_terms.h"
#include "tree_checks.h"

#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace dynrt::bvh {
namespace {

using detail::half_area_d;

std::string box_text(const Aabb& b) {
    return "[(" + std::to_string(b.lo.x) + ", " + std::to_string(b.lo.y) + ", " +
           std::to_string(b.lo.z) + "), (" + std::to_string(b.hi.x) + ", " +
           std::to_string(b.hi.y) + ", " + std::to_string(b.hi.z) + ")]";
}

}  // namespace

namespace {

/// What one walk over a tree gathers for sah_cost and compute_stats.
struct TreeFigures {
    double cost = 0.0;
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    std::size_t leaf_prims = 0;
    std::uint32_t leaf_prims_max = 0;
    std::uint32_t depth = 0;
};

/// Subtrees above this depth are walked as parallel tasks (a million-triangle tree is walked
/// after every build, for its SAH cost and shape; serially that took 10-20 ms a walk).
constexpr std::uint32_t kParallelDepth = 8;

/// Walks the subtree at `index` (at depth `depth`, the root being 1). `budget` bounds the
/// nodes visited, so a malformed tree (a cycle) ends the walk: each serial subtree (and the
/// parallel top) gets the node count, a counter of its own (a shared atomic counter's cache
/// line, moving between the cores at every node, made the walk several times slower). The
/// sums are made children first, left before right, so the result does not depend on thread
/// timing.
TreeFigures walk(const Bvh& bvh, std::uint32_t index, std::uint32_t depth, double root_area,
                 const SahCosts& costs, std::int64_t& budget) {
    TreeFigures f;
    if (--budget < 0) return f;
    const BvhNode& node = bvh.nodes[index];
    // A flat or point-like root makes every area ratio 0/0; its limit when the boxes are
    // inflated uniformly is 1, so every node then counts with weight 1.
    const double weight = root_area > 0.0 ? half_area_d(node.box) / root_area : 1.0;
    f.nodes = 1;
    f.depth = depth;
    if (node.is_leaf()) {
        f.cost = weight * node.count * costs.intersection;
        f.leaves = 1;
        f.leaf_prims = node.count;
        f.leaf_prims_max = node.count;
        return f;
    }
    f.cost = weight * costs.traversal;
    if (node.first + 1 >= bvh.nodes.size()) return f;
    TreeFigures left, right;
    if (depth < kParallelDepth) {
        const std::int64_t subtree_budget = static_cast<std::int64_t>(bvh.nodes.size());
        tbb::parallel_invoke(
            [&] {
                std::int64_t own = subtree_budget;
                left = walk(bvh, node.first, depth + 1, root_area, costs, own);
            },
            [&] {
                std::int64_t own = subtree_budget;
                right = walk(bvh, node.first + 1, depth + 1, root_area, costs, own);
            });
    } else {
        left = walk(bvh, node.first, depth + 1, root_area, costs, budget);
        right = walk(bvh, node.first + 1, depth + 1, root_area, costs, budget);
    }
    f.cost += left.cost + right.cost;
    f.nodes += left.nodes + right.nodes;
    f.leaves = left.leaves + right.leaves;
    f.leaf_prims = left.leaf_prims + right.leaf_prims;
    f.leaf_prims_max = std::max(left.leaf_prims_max, right.leaf_prims_max);
    f.depth = std::max(left.depth, right.depth);
    return f;
}

TreeFigures walk_tree(const Bvh& bvh, const SahCosts& costs) {
    if (bvh.empty()) return {};
    std::int64_t budget = static_cast<std::int64_t>(bvh.nodes.size());
    return walk(bvh, 0, 1, half_area_d(bvh.nodes[0].box), costs, budget);
}

}  // namespace

double sah_cost(const Bvh& bvh, const SahCosts& costs) { return walk_tree(bvh, costs).cost; }

BvhStats compute_stats(const Bvh& bvh) {
    const TreeFigures f = walk_tree(bvh, SahCosts{});
    BvhStats stats;
    stats.nodes = f.nodes;
    stats.leaves = f.leaves;
    stats.leaf_prims_max = f.leaf_prims_max;
    stats.depth = f.depth;
    stats.leaf_prims_mean =
        f.leaves != 0 ? static_cast<double>(f.leaf_prims) / static_cast<double>(f.leaves) : 0.0;
    return stats;
}

namespace detail {

std::string check_tree(const Bvh& bvh, std::span<const Aabb> prim_boxes,
                       std::uint32_t leaf_size_max, bool allow_missing,
                       std::vector<std::uint8_t>& in_tree) {
    const std::size_t prim_count = prim_boxes.size();
    in_tree.assign(prim_count, 0);
    if (bvh.empty()) {
        if (!bvh.prim_ids.empty()) {
            return "empty tree but " + std::to_string(bvh.prim_ids.size()) + " primitive ids";
        }
        if (prim_count != 0 && !allow_missing) {
            return "empty tree for " + std::to_string(prim_count) + " primitives";
        }
        return {};
    }
    if (!allow_missing && bvh.prim_ids.size() != prim_count) {
        return std::to_string(bvh.prim_ids.size()) + " primitive ids for " +
               std::to_string(prim_count) + " primitives";
    }
    // Each id must be valid and unique.
    for (std::size_t pos = 0; pos < bvh.prim_ids.size(); ++pos) {
        const std::uint32_t id = bvh.prim_ids[pos];
        if (id >= prim_count) {
            return "prim_ids[" + std::to_string(pos) + "] = " + std::to_string(id) +
                   " is out of range";
        }
        if (in_tree[id]) return "primitive " + std::to_string(id) + " appears twice in prim_ids";
        in_tree[id] = 1;
    }

    // Depth-first walk: each node reached once, leaf ranges covering every position once.
    const std::size_t node_count = bvh.nodes.size();
    std::vector<std::uint8_t> node_seen(node_count, 0);
    std::vector<std::uint8_t> position_seen(bvh.prim_ids.size(), 0);
    std::size_t positions_covered = 0;
    std::size_t nodes_reached = 0;
    struct Entry {
        std::uint32_t node, depth;
    };
    std::vector<Entry> stack{{0, 1}};
    while (!stack.empty()) {
        const Entry e = stack.back();
        stack.pop_back();
        auto where = [&] { return "node " + std::to_string(e.node); };
        if (e.node >= node_count) return where() + " is out of range";
        if (node_seen[e.node]) return where() + " is reached twice";
        node_seen[e.node] = 1;
        ++nodes_reached;
        if (e.depth > kMaxDepth) {
            return where() + " is at depth " + std::to_string(e.depth) + " > kMaxDepth";
        }
        const BvhNode& node = bvh.nodes[e.node];
        if (node.is_leaf()) {
            if (node.count > leaf_size_max) {
                return where() + " is a leaf of " + std::to_string(node.count) +
                       " primitives > leaf_size_max " + std::to_string(leaf_size_max);
            }
            if (node.first > bvh.prim_ids.size() ||
                node.count > bvh.prim_ids.size() - node.first) {
                return where() + " has leaf range [" + std::to_string(node.first) + ", +" +
                       std::to_string(node.count) + ") outside prim_ids";
            }
            for (std::uint32_t k = 0; k < node.count; ++k) {
                const std::uint32_t pos = node.first + k;
                if (position_seen[pos]) {
                    return where() + ": prim_ids position " + std::to_string(pos) +
                           " belongs to two leaves";
                }
                position_seen[pos] = 1;
                ++positions_covered;
                const std::uint32_t id = bvh.prim_ids[pos];
                if (!node.box.contains(prim_boxes[id])) {
                    return where() + ": box " + box_text(node.box) + " does not contain primitive " +
                           std::to_string(id) + "'s box " + box_text(prim_boxes[id]);
                }
            }
        } else {
            if (node.first == 0 || node.first >= node_count - 1) {
                return where() + " has child index " + std::to_string(node.first) +
                       " out of range";
            }
            for (std::uint32_t c = node.first; c <= node.first + 1; ++c) {
                if (!node.box.contains(bvh.nodes[c].box)) {
                    return where() + ": box " + box_text(node.box) + " does not contain child " +
                           std::to_string(c) + "'s box " + box_text(bvh.nodes[c].box);
                }
                stack.push_back({c, e.depth + 1});
            }
        }
    }
    if (positions_covered != bvh.prim_ids.size()) {
        return std::to_string(bvh.prim_ids.size() - positions_covered) +
               " prim_ids positions are in no leaf";
    }
    if (nodes_reached != node_count) {
        return std::to_string(node_count - nodes_reached) + " nodes are unreachable from the root";
    }
    return {};
}

}  // namespace detail

std::string validate(const Bvh& bvh, std::span<const Aabb> prim_boxes, std::uint32_t leaf_size_max) {
    std::vector<std::uint8_t> in_tree;
    return detail::check_tree(bvh, prim_boxes, leaf_size_max, false, in_tree);
}

}  // namespace dynrt::bvh
