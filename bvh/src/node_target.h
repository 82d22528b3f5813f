#pragma once
// Where a wide builder writes its nodes: as floats, or quantised as each is written
// (WideBvhOf::quantized), so that a quantised tree's float nodes are never all held at once
// (half the nodes' bytes off the build's peak; quantize_nodes is the pass for a finished tree).

#include "dynrt/bvh/wide_bvh.h"

#include "huge_pages.h"

#include <cstdint>
#include <stdexcept>

namespace dynrt::bvh::detail {

template <int N>
struct NodeTarget {
    WideNode<N>* floats = nullptr;
    QuantizedWideNode<N>* quantized = nullptr;

    /// Writes `node` at `at`, quantised when the target is (its boxes lie in a root box that
    /// can_quantize accepted, so quantize_node cannot refuse them).
    void store(std::size_t at, const WideNode<N>& node) const {
        if (floats != nullptr) {
            floats[at] = node;
        } else if (!quantize_node(node, quantized[at])) {
            throw std::logic_error("wide build: a node inside a quantisable root box was refused");
        }
    }
    /// Slot i of the node written at `at`: its child, and its blocks (0 for an inner node).
    std::uint32_t child(std::size_t at, int i) const {
        return floats != nullptr ? floats[at].child[i] : quantized[at].child[i];
    }
    std::uint32_t blocks(std::size_t at, int i) const {
        return floats != nullptr ? floats[at].blocks[i] : quantized[at].blocks[i];
    }
};

/// Sizes `wide`'s node array to `count` nodes, quantised when `quantize` (then
/// wide.quantized is set), and returns where they are written.
template <int N>
NodeTarget<N> allocate_nodes(WideBvhOf<N>& wide, std::size_t count, bool quantize) {
    wide.quantized = quantize;
    if (quantize) {
        decltype(wide.nodes)().swap(wide.nodes);
        resize_with_huge_pages(wide.quantized_nodes, count);
        return NodeTarget<N>{nullptr, wide.quantized_nodes.data()};
    }
    decltype(wide.quantized_nodes)().swap(wide.quantized_nodes);
    resize_with_huge_pages(wide.nodes, count);
    return NodeTarget<N>{wide.nodes.data(), nullptr};
}

}  // namespace dynrt::bvh::detail
