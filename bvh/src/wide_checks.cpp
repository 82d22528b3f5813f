// validate, compute_stats and sah_cost for the wide tree.

#include "dynrt/bvh/wide_bvh.h"

#include "sah_terms.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace dynrt::bvh {
namespace {

/// The used lanes of a leaf.
template <int N, class Node>
std::uint32_t leaf_prims(const WideBvhOf<N>& wide, const Node& node, int slot) {
    // Only the last block of a leaf may have unused lanes.
    const std::size_t last = node.child[slot] + node.blocks[slot] - 1;
    std::uint32_t used = 0;
    for (int lane = 0; lane < kBlockLanes; ++lane) used += wide.prim(last, lane) != kInvalidId ? 1 : 0;
    return (node.blocks[slot] - 1u) * kBlockLanes + used;
}

/// Figures of the subtree below node `index`, summed in slot order.
struct WideFigures {
    detail::WideSahSum sah;
    std::size_t leaves = 0;
    std::size_t leaf_prims = 0;
    std::uint32_t leaf_prims_max = 0;
    std::uint32_t depth = 0;
};

/// Walks a valid tree (as built or refitted) below node `index` at `depth`; `nodes` is its
/// node array of either kind (the SAH of a quantised tree is that of its decoded boxes).
template <int N, class Node>
WideFigures walk(const WideBvhOf<N>& wide, const Node* nodes, std::uint32_t index,
                 std::uint32_t depth, const SahCosts& costs) {
    const Node& node = nodes[index];
    WideFigures f;
    f.depth = depth;
    for (int i = 0; i < N; ++i) {
        if (node.is_empty(i)) continue;
        if (node.is_leaf(i)) {
            const std::uint32_t prims = leaf_prims(wide, node, i);
            detail::add_wide_slot(f.sah, node.box(i), true, prims, {}, costs);
            ++f.leaves;
            f.leaf_prims += prims;
            f.leaf_prims_max = std::max(f.leaf_prims_max, prims);
            continue;
        }
        const WideFigures below = walk(wide, nodes, node.child[i], depth + 1, costs);
        detail::add_wide_slot(f.sah, node.box(i), false, 0, below.sah, costs);
        f.leaves += below.leaves;
        f.leaf_prims += below.leaf_prims;
        f.leaf_prims_max = std::max(f.leaf_prims_max, below.leaf_prims_max);
        f.depth = std::max(f.depth, below.depth);
    }
    return f;
}

/// validate on the tree's node array of either kind. A float node's child boxes nest in their
/// parent's; a quantised node's need not (quantized_node.h), so there each triangle is checked
/// against every box on its path instead.
template <int N, class Node>
std::string validate_nodes(const WideBvhOf<N>& wide, const Node* nodes,
                           std::span<const Triangle> tris, std::span<const std::uint32_t> prims) {
    constexpr bool kQuantized = !std::is_same_v<Node, WideNode<N>>;
    if (wide.empty()) {
        if (wide.block_count() != 0) return "empty tree but " + std::to_string(wide.block_count()) + " blocks";
        if (!prims.empty()) return "empty tree for " + std::to_string(prims.size()) + " primitives";
        if (wide.triangle_count != 0) return "empty tree of triangle_count " + std::to_string(wide.triangle_count);
        return {};
    }
    std::vector<std::uint8_t> expected(tris.size(), 0);
    for (std::uint32_t id : prims) {
        if (id >= tris.size()) return "expected primitive " + std::to_string(id) + " is out of range";
        if (expected[id]) return "expected primitive " + std::to_string(id) + " is listed twice";
        expected[id] = 1;
    }
    std::vector<std::uint8_t> seen_prim(tris.size(), 0);
    const std::size_t node_count = wide.node_count();
    std::vector<std::uint8_t> seen_node(node_count, 0);
    if (wide.quantized ? !wide.nodes.empty() : !wide.quantized_nodes.empty()) {
        return "nodes of the other kind than the tree's";
    }
    if (wide.compact ? !wide.blocks.empty() : !wide.prim_blocks.empty()) {
        return "blocks of the other kind than the tree's leaves";
    }
    if (wide.compact && wide.source.size() != tris.size()) {
        return "compact leaves over " + std::to_string(wide.source.size()) + " triangles, " +
               std::to_string(tris.size()) + " given";
    }
    const std::size_t block_count = wide.block_count();
    std::vector<std::uint8_t> seen_block(block_count, 0);
    std::size_t prims_found = 0;

    struct Entry {
        std::uint32_t node, depth;
        // The parent's slot box (the root box for the root); quantised, the intersection of
        // every slot box on the path.
        Aabb bound;
    };
    std::vector<Entry> stack{{0, 1, wide.root_box}};
    while (!stack.empty()) {
        const Entry e = stack.back();
        stack.pop_back();
        const std::string where = "node " + std::to_string(e.node);
        if (e.node >= node_count) return where + " is out of range";
        if (seen_node[e.node]) return where + " is reached twice";
        seen_node[e.node] = 1;
        if (e.depth > kMaxDepth) return where + " is deeper than kMaxDepth";
        const Node& node = nodes[e.node];
        bool ended = false;
        int used = 0;
        for (int i = 0; i < N; ++i) {
            const std::string slot = where + " slot " + std::to_string(i);
            if (node.is_empty(i)) {
                ended = true;
                const Aabb b = node.box(i);
                if (!b.is_empty()) return slot + " is empty but has a non-empty box";
                continue;
            }
            if (ended) return slot + " is used after an empty slot";
            ++used;
            Aabb box = node.box(i);
            if (box.is_empty()) return slot + " has an empty box";
            if constexpr (kQuantized) {
                box = Aabb{glm::max(box.lo, e.bound.lo), glm::min(box.hi, e.bound.hi)};
            } else if (!e.bound.contains(box)) {
                return slot + "'s box is not inside its parent's";
            }
            if (!node.is_leaf(i)) {
                if (node.child[i] <= e.node) return slot + " points back to node " + std::to_string(node.child[i]);
                stack.push_back(Entry{node.child[i], e.depth + 1, box});
                continue;
            }
            const std::size_t first = node.child[i];
            if (first > block_count || node.blocks[i] > block_count - first) {
                return slot + " has blocks outside the block array";
            }
            for (std::size_t b = first; b < first + node.blocks[i]; ++b) {
                const std::string block_name = "block " + std::to_string(b);
                if (seen_block[b]) return block_name + " is in two leaves";
                seen_block[b] = 1;
                int lanes = 0;
                for (int lane = 0; lane < kBlockLanes; ++lane) {
                    const std::uint32_t prim = wide.prim(b, lane);
                    if (prim == kInvalidId) continue;
                    ++lanes;
                    const std::string lane_name = block_name + " lane " + std::to_string(lane);
                    if (prim >= tris.size()) return lane_name + " has primitive " + std::to_string(prim) + " out of range";
                    if (!expected[prim]) return lane_name + " has primitive " + std::to_string(prim) + " that should not be in the tree";
                    if (seen_prim[prim]) return "primitive " + std::to_string(prim) + " is in two lanes";
                    seen_prim[prim] = 1;
                    ++prims_found;
                    // A compact lane reads its corners from the source: checked the same way.
                    const Triangle t = wide.triangle(b, lane);
                    if (std::memcmp(&t, &tris[prim], sizeof(Triangle)) != 0) {
                        return lane_name + " is not triangle " + std::to_string(prim);
                    }
                    if (!box.contains(t.bounds())) {
                        return lane_name + "'s triangle is outside its leaf box" +
                               (kQuantized ? " or a box above it" : "");
                    }
                }
                if (lanes == 0) return block_name + " has no triangle";
            }
        }
        if (used == 0) return where + " has no children";
    }
    for (std::size_t i = 0; i < node_count; ++i) {
        if (!seen_node[i]) return "node " + std::to_string(i) + " is not reached from the root";
    }
    for (std::size_t b = 0; b < block_count; ++b) {
        if (!seen_block[b]) return "block " + std::to_string(b) + " is in no leaf";
    }
    std::size_t expected_count = 0;
    for (std::uint8_t x : expected) expected_count += x;
    if (prims_found != expected_count) {
        return std::to_string(prims_found) + " primitives in the blocks, " +
               std::to_string(expected_count) + " expected";
    }
    if (wide.triangle_count != prims_found) {
        return "triangle_count is " + std::to_string(wide.triangle_count) + " for " +
               std::to_string(prims_found) + " triangles in the blocks";
    }
    return {};
}

}  // namespace

template <int N>
std::string validate(const WideBvhOf<N>& wide, std::span<const Triangle> tris,
                     std::span<const std::uint32_t> prims) {
    return wide.visit_nodes(
        [&](const auto* nodes) { return validate_nodes(wide, nodes, tris, prims); });
}

template <int N>
WideStats compute_stats(const WideBvhOf<N>& wide) {
    WideStats s;
    s.nodes = wide.node_count();
    s.blocks = wide.block_count();
    s.bytes = wide.bytes();
    std::size_t slots = 0;
    wide.visit_nodes([&](const auto* nodes) {
        for (std::size_t n = 0; n < s.nodes; ++n) {
            for (int i = 0; i < N; ++i) {
                if (nodes[n].is_empty(i)) continue;
                ++slots;
                if (nodes[n].is_leaf(i)) ++s.leaves;
            }
        }
    });
    std::size_t lanes = 0;
    for (std::size_t b = 0; b < s.blocks; ++b) {
        for (int lane = 0; lane < kBlockLanes; ++lane) lanes += wide.prim(b, lane) != kInvalidId ? 1 : 0;
    }
    s.block_fill = s.blocks ? static_cast<double>(lanes) / static_cast<double>(s.blocks * kBlockLanes) : 0.0;
    s.children_mean = s.nodes ? static_cast<double>(slots) / static_cast<double>(s.nodes) : 0.0;
    if (!wide.empty()) {
        const WideFigures f =
            wide.visit_nodes([&](const auto* nodes) { return walk(wide, nodes, 0, 1, SahCosts{}); });
        s.leaf_prims_max = f.leaf_prims_max;
        s.leaf_prims_mean = f.leaves ? static_cast<double>(f.leaf_prims) / static_cast<double>(f.leaves) : 0.0;
        s.depth = f.depth;
    }
    return s;
}

template <int N>
double sah_cost(const WideBvhOf<N>& wide, const SahCosts& costs) {
    if (wide.empty()) return 0.0;
    const WideFigures f =
        wide.visit_nodes([&](const auto* nodes) { return walk(wide, nodes, 0, 1, costs); });
    return detail::wide_sah_total(f.sah, wide.root_box, costs);
}

template std::string validate<4>(const WideBvhOf<4>&, std::span<const Triangle>, std::span<const std::uint32_t>);
template std::string validate<8>(const WideBvhOf<8>&, std::span<const Triangle>, std::span<const std::uint32_t>);
template WideStats compute_stats<4>(const WideBvhOf<4>&);
template WideStats compute_stats<8>(const WideBvhOf<8>&);
template double sah_cost<4>(const WideBvhOf<4>&, const SahCosts&);
template double sah_cost<8>(const WideBvhOf<8>&, const SahCosts&);

}  // namespace dynrt::bvh
