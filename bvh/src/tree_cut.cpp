// A coarse cover of a tree's triangles: a cut through the tree made best first, splitting the
// part of largest surface area until the next split would give more parts than asked for.

#include "dynrt/bvh/triangle_bvh.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace dynrt::bvh {
namespace {

/// One part of the cut: a box and what it holds, an inner node to split or a leaf.
struct Part {
    Aabb box;
    std::uint32_t node = kInvalidId;  ///< kInvalidId for a leaf

    bool splittable() const { return node != kInvalidId; }
};

/// Splits parts, the largest first, while the parts they become fit within max_parts: when the
/// largest would give too many, the next largest that fits is split instead.
/// `children(node, out)` appends a node's child parts.
template <class Children>
void cut_best_first(std::vector<Part>& cut, std::size_t max_parts, Children&& children) {
    std::vector<Part> below;
    std::vector<std::size_t> order;
    while (true) {
        order.clear();
        for (std::size_t k = 0; k < cut.size(); ++k) {
            if (cut[k].splittable()) order.push_back(k);
        }
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return cut[a].box.half_area() > cut[b].box.half_area();
        });
        bool split = false;
        for (const std::size_t k : order) {
            below.clear();
            children(cut[k].node, below);
            if (cut.size() - 1 + below.size() > max_parts) continue;
            cut[k] = below[0];
            cut.insert(cut.end(), below.begin() + 1, below.end());
            split = true;
            break;
        }
        if (!split) return;
    }
}

}  // namespace

void cover_boxes(const TriangleBvh& accel, std::size_t max_parts, std::vector<Aabb>& out) {
    if (accel.empty() || max_parts == 0) return;
    std::vector<Part> cut;
    if (!accel.wide.empty()) {
        cut.push_back(Part{accel.wide.root_box, 0});
        // A quantised node's decoded boxes hold the exact ones: the cover stays a cover.
        accel.wide.visit_nodes([&](const auto* nodes) {
            cut_best_first(cut, max_parts, [&](std::uint32_t index, std::vector<Part>& below) {
                const auto& node = nodes[index];
                for (int i = 0; i < kWideWidth; ++i) {
                    if (node.is_empty(i)) continue;
                    below.push_back(Part{node.box(i), node.is_leaf(i) ? kInvalidId : node.child[i]});
                }
            });
        });
    } else {
        const auto& nodes = accel.bvh.nodes;
        const auto part_of = [&](std::uint32_t n) {
            return Part{nodes[n].box, nodes[n].is_leaf() ? kInvalidId : n};
        };
        cut.push_back(part_of(0));
        cut_best_first(cut, max_parts, [&](std::uint32_t index, std::vector<Part>& below) {
            below.push_back(part_of(nodes[index].first));
            below.push_back(part_of(nodes[index].first + 1));
        });
    }
    for (const Part& part : cut) {
        if (!part.box.is_empty()) out.push_back(part.box);
    }
}

}  // namespace dynrt::bvh
