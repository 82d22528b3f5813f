// validate and compute_stats for the wide tree.

#include "dynrt/bvh/wide_bvh.h"

#include <cstring>
#include <string>
#include <vector>

namespace dynrt::bvh {
namespace {

/// The used lanes under `index` in depth-first slot order against `expected` (leaf order) from
/// `position` on, and each node's first_position. Called on a tree whose structure is valid.
template <int N>
std::string check_leaf_order(const WideBvhOf<N>& wide, std::uint32_t index,
                             std::span<const std::uint32_t> expected, std::size_t& position) {
    const WideNode<N>& node = wide.nodes[index];
    if (node.first_position != position) {
        return "node " + std::to_string(index) + " has first_position " +
               std::to_string(node.first_position) + ", its triangles start at " +
               std::to_string(position);
    }
    for (int i = 0; i < N; ++i) {
        if (node.is_empty(i)) continue;
        if (!node.is_leaf(i)) {
            std::string error = check_leaf_order(wide, node.child[i], expected, position);
            if (!error.empty()) return error;
            continue;
        }
        for (std::uint32_t b = node.child[i]; b < node.child[i] + node.blocks[i]; ++b) {
            for (int lane = 0; lane < kBlockLanes; ++lane) {
                const std::uint32_t prim = wide.blocks[b].prim[lane];
                if (prim == kInvalidId) continue;
                if (position >= expected.size() || expected[position] != prim) {
                    return "block " + std::to_string(b) + " lane " + std::to_string(lane) +
                           " is not the triangle at leaf position " + std::to_string(position);
                }
                ++position;
            }
        }
    }
    return {};
}

}  // namespace

template <int N>
std::string validate(const WideBvhOf<N>& wide, std::span<const Triangle> tris,
                     std::span<const std::uint32_t> expected_prims) {
    if (wide.empty()) {
        if (!wide.blocks.empty()) return "empty tree but " + std::to_string(wide.blocks.size()) + " blocks";
        if (!expected_prims.empty()) {
            return "empty tree for " + std::to_string(expected_prims.size()) + " primitives";
        }
        return {};
    }
    std::vector<std::uint8_t> expected(tris.size(), 0);
    for (std::uint32_t id : expected_prims) {
        if (id >= tris.size()) return "expected primitive " + std::to_string(id) + " is out of range";
        expected[id] = 1;
    }
    std::vector<std::uint8_t> seen_prim(tris.size(), 0);
    std::vector<std::uint8_t> seen_node(wide.nodes.size(), 0);
    std::vector<std::uint8_t> seen_block(wide.blocks.size(), 0);
    std::size_t prims_found = 0;

    struct Entry {
        std::uint32_t node, depth;
        Aabb bound;  // the parent's slot box (the root box for the root)
    };
    std::vector<Entry> stack{{0, 1, wide.root_box}};
    while (!stack.empty()) {
        const Entry e = stack.back();
        stack.pop_back();
        const std::string where = "node " + std::to_string(e.node);
        if (e.node >= wide.nodes.size()) return where + " is out of range";
        if (seen_node[e.node]) return where + " is reached twice";
        seen_node[e.node] = 1;
        if (e.depth > kMaxDepth) return where + " is deeper than kMaxDepth";
        const WideNode<N>& node = wide.nodes[e.node];
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
            const Aabb box = node.box(i);
            if (box.is_empty()) return slot + " has an empty box";
            if (!e.bound.contains(box)) return slot + "'s box is not inside its parent's";
            if (!node.is_leaf(i)) {
                if (node.child[i] <= e.node) return slot + " points back to node " + std::to_string(node.child[i]);
                stack.push_back(Entry{node.child[i], e.depth + 1, box});
                continue;
            }
            const std::size_t first = node.child[i];
            if (first > wide.blocks.size() || node.blocks[i] > wide.blocks.size() - first) {
                return slot + " has blocks outside the block array";
            }
            for (std::size_t b = first; b < first + node.blocks[i]; ++b) {
                const std::string block_name = "block " + std::to_string(b);
                if (seen_block[b]) return block_name + " is in two leaves";
                seen_block[b] = 1;
                const TriangleBlock& block = wide.blocks[b];
                int lanes = 0;
                for (int lane = 0; lane < kBlockLanes; ++lane) {
                    const std::uint32_t prim = block.prim[lane];
                    if (prim == kInvalidId) continue;
                    ++lanes;
                    const std::string lane_name = block_name + " lane " + std::to_string(lane);
                    if (prim >= tris.size()) return lane_name + " has primitive " + std::to_string(prim) + " out of range";
                    if (!expected[prim]) return lane_name + " has primitive " + std::to_string(prim) + " that should not be in the tree";
                    if (seen_prim[prim]) return "primitive " + std::to_string(prim) + " is in two lanes";
                    seen_prim[prim] = 1;
                    ++prims_found;
                    const Triangle t = block.triangle(lane);
                    if (std::memcmp(&t, &tris[prim], sizeof(Triangle)) != 0) {
                        return lane_name + " is not a copy of triangle " + std::to_string(prim);
                    }
                    if (!box.contains(t.bounds())) return lane_name + "'s triangle is outside its leaf box";
                }
                if (lanes == 0) return block_name + " has no triangle";
            }
        }
        if (used == 0) return where + " has no children";
    }
    for (std::size_t i = 0; i < wide.nodes.size(); ++i) {
        if (!seen_node[i]) return "node " + std::to_string(i) + " is not reached from the root";
    }
    for (std::size_t b = 0; b < wide.blocks.size(); ++b) {
        if (!seen_block[b]) return "block " + std::to_string(b) + " is in no leaf";
    }
    std::size_t expected_count = 0;
    for (std::uint8_t x : expected) expected_count += x;
    if (prims_found != expected_count) {
        return std::to_string(prims_found) + " primitives in the blocks, " +
               std::to_string(expected_count) + " expected";
    }
    std::size_t position = 0;
    return check_leaf_order(wide, 0, expected_prims, position);
}

template <int N>
WideStats compute_stats(const WideBvhOf<N>& wide) {
    WideStats s;
    s.nodes = wide.nodes.size();
    s.blocks = wide.blocks.size();
    s.bytes = wide.bytes();
    std::size_t slots = 0;
    for (const WideNode<N>& node : wide.nodes) {
        for (int i = 0; i < N; ++i) {
            if (node.is_empty(i)) continue;
            ++slots;
            if (node.is_leaf(i)) ++s.leaves;
        }
    }
    std::size_t lanes = 0;
    for (const TriangleBlock& block : wide.blocks) {
        for (int lane = 0; lane < kBlockLanes; ++lane) lanes += block.prim[lane] != kInvalidId ? 1 : 0;
    }
    s.block_fill = s.blocks ? static_cast<double>(lanes) / static_cast<double>(s.blocks * kBlockLanes) : 0.0;
    s.children_mean = s.nodes ? static_cast<double>(slots) / static_cast<double>(s.nodes) : 0.0;
    return s;
}

template std::string validate<4>(const WideBvhOf<4>&, std::span<const Triangle>, std::span<const std::uint32_t>);
template std::string validate<8>(const WideBvhOf<8>&, std::span<const Triangle>, std::span<const std::uint32_t>);
template WideStats compute_stats<4>(const WideBvhOf<4>&);
template WideStats compute_stats<8>(const WideBvhOf<8>&);

}  // namespace dynrt::bvh
