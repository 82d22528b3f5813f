#pragma once
// The plain tree produced by every builder: nodes plus a permutation of primitive ids.
// It knows nothing about triangles or scenes; see triangle_bvh.h for the traceable pairing.

#include "dynrt/bvh/aabb.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dynrt::bvh {

/// 32-byte node. Children of an inner node are stored next to each other, so one index is
/// enough: left = first, right = first + 1.
struct BvhNode {
    Aabb box;
    /// Inner node: index of the left child. Leaf: first position in `Bvh::prim_ids`.
    std::uint32_t first = 0;
    /// 0 for an inner node, the number of primitives (>= 1) for a leaf.
    std::uint32_t count = 0;

    bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BvhNode) == 32, "BvhNode must stay 32 bytes (two per cache line)");

/// Deepest tree any builder may produce; traversal stacks are sized from it.
inline constexpr std::uint32_t kMaxDepth = 64;

/// A bounding volume hierarchy over `prim_ids.size()` primitives. `nodes[0]` is the root when
/// the tree is non-empty. Leaves refer to ranges of `prim_ids`, which maps leaf order back to
/// the caller's primitive indices.
struct Bvh {
    std::vector<BvhNode> nodes;
    std::vector<std::uint32_t> prim_ids;

    bool empty() const { return nodes.empty(); }
};

/// Costs of the surface area heuristic, in units of one node traversal.
struct SahCosts {
    float traversal = 1.0f;
    /// Cost of one primitive intersection relative to one traversal step.
    float intersection = 1.0f;
};

/// Expected cost of a random ray through the tree under the SAH (MacDonald and Booth 1990):
/// sum over inner nodes of A(n)/A(root) * traversal + sum over leaves of
/// A(n)/A(root) * count * intersection. 0 for an empty tree.
double sah_cost(const Bvh& bvh, const SahCosts& costs);

/// Shape figures reported with every build.
struct BvhStats {
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    double leaf_prims_mean = 0.0;
    std::uint32_t leaf_prims_max = 0;
    /// Number of nodes on the longest root-to-leaf path (a single leaf has depth 1).
    std::uint32_t depth = 0;
};
BvhStats compute_stats(const Bvh& bvh);

/// Checks the tree's invariants against the primitive boxes it was built from: every primitive
/// in exactly one leaf, every child box inside its parent's, every primitive box inside its
/// leaf's, leaves no larger than `leaf_size_max`, depth within kMaxDepth, no cycles or
/// out-of-range indices. Returns an empty string when valid, else a description of the first
/// violation found. Meant for tests and debug checks after every build and refit.
std::string validate(const Bvh& bvh, std::span<const Aabb> prim_boxes, std::uint32_t leaf_size_max);

}  // namespace dynrt::bvh
