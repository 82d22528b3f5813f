// The encoder of quantised wide nodes (quantized_node.h): per axis, the node box's lower
// corner as origin and the smallest power-of-two step whose 255th plane reaches the box's upper
// corner; then per child the highest plane at or below its lower bound and the lowest at or
// above its upper bound, each checked with the very float the traversal decodes (so the check,
// not the estimate from double division, decides).

#include "dynrt/bvh/wide_bvh.h"

#include "node_target.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace dynrt::bvh {
namespace {

/// The float the traversal decodes plane q to, with step 2^e from `origin`
/// (QuantizedWideNode::plane).
float decoded(float origin, int e, int q) {
    return origin + static_cast<float>(q) * quantized_step(e);
}

/// The exponent of the smallest step whose plane 255 reaches `hi` from `origin`, or
/// kQuantizedExponentMax + 1 when none does.
int step_exponent(float origin, float hi) {
    const double extent = static_cast<double>(hi) - static_cast<double>(origin);
    int e = kQuantizedExponentMin;
    if (extent > 0.0) {
        int exp2 = 0;
        std::frexp(extent / 255.0, &exp2);  // extent / 255 < 2^exp2
        e = std::max(kQuantizedExponentMin, exp2 - 1);
    }
    while (e <= kQuantizedExponentMax && decoded(origin, e, 255) < hi) ++e;
    return e;
}

}  // namespace

bool can_quantize(const Aabb& root) {
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(root.lo[a]) || !std::isfinite(root.hi[a])) return false;
        if (double(root.hi[a]) - double(root.lo[a]) > std::ldexp(1.0, 126)) return false;
    }
    return true;
}

template <int N>
bool quantize_node(const WideNode<N>& node, QuantizedWideNode<N>& out) {
    std::memset(static_cast<void*>(&out), 0, sizeof out);
    Aabb all;
    for (int i = 0; i < N; ++i) {
        out.child[i] = node.child[i];
        out.blocks[i] = node.blocks[i];
        if (node.is_empty(i)) continue;
        out.used = static_cast<std::uint8_t>(out.used | (1u << i));
        all.extend(node.box(i));
    }
    if (out.used == 0) return true;
    for (int a = 0; a < 3; ++a) {
        const float origin = all.lo[a], top = all.hi[a];
        if (!std::isfinite(origin) || !std::isfinite(top)) return false;
        const int e = step_exponent(origin, top);
        if (e > kQuantizedExponentMax) return false;
        out.origin[a] = origin;
        out.exponent[a] = static_cast<std::int8_t>(e);
        const double step = std::ldexp(1.0, e);
        for (int i = 0; i < N; ++i) {
            if (node.is_empty(i)) continue;
            const Aabb box = node.box(i);
            const float lo = box.lo[a], hi = box.hi[a];
            // The estimates from exact division, then moved until the decoded floats hold the
            // box (plane 0 is the origin, at or below every lo; plane 255 reaches every hi).
            int q_lo = static_cast<int>(
                std::clamp(std::floor((double(lo) - origin) / step), 0.0, 255.0));
            while (q_lo > 0 && decoded(origin, e, q_lo) > lo) --q_lo;
            while (q_lo < 255 && decoded(origin, e, q_lo + 1) <= lo) ++q_lo;
            int q_hi = static_cast<int>(
                std::clamp(std::ceil((double(hi) - origin) / step), 0.0, 255.0));
            while (q_hi < 255 && decoded(origin, e, q_hi) < hi) ++q_hi;
            while (q_hi > 0 && decoded(origin, e, q_hi - 1) >= hi) --q_hi;
            out.axis[a].lo[i] = static_cast<std::uint8_t>(q_lo);
            out.axis[a].hi[i] = static_cast<std::uint8_t>(q_hi);
        }
    }
    return true;
}

template <int N>
bool quantize_nodes(WideBvhOf<N>& wide) {
    if (wide.quantized) return true;
    if (!can_quantize(wide.root_box)) return false;
    const std::size_t count = wide.nodes.size();
    decltype(wide.quantized_nodes) quantized(count);
    // Every node lies in the root box can_quantize accepted: the collapse's writer quantises
    // each (and would throw on a refusal, which that check rules out).
    const detail::NodeTarget<N> target{nullptr, quantized.data()};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              target.store(i, wide.nodes[i]);
                          }
                      });
    wide.quantized_nodes = std::move(quantized);
    wide.quantized = true;
    decltype(wide.nodes)().swap(wide.nodes);  // the float nodes' memory goes back
    return true;
}

template bool quantize_node<4>(const WideNode<4>&, QuantizedWideNode<4>&);
template bool quantize_node<8>(const WideNode<8>&, QuantizedWideNode<8>&);
template bool quantize_nodes<4>(WideBvhOf<4>&);
template bool quantize_nodes<8>(WideBvhOf<8>&);

}  // namespace dynrt::bvh
