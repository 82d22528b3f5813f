#pragma once
// Parallel top-down builder choosing splits with the binned surface area heuristic
// (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies").

#include "dynrt/bvh/bvh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace dynrt::bvh {

/// How a tree is built. The binned SAH gives the cheapest trees to trace; the Morton builder
/// (morton_builder.h) builds several times faster and traces somewhat slower, for objects
/// rebuilt every frame.
enum class BuildMethod { binned_sah, morton };

/// "sah" or "morton".
const char* build_method_name(BuildMethod method);

struct BuildConfig {
    /// Cost of intersecting one primitive in units of one traversal step (the SAH's
    /// C_isect / C_trav). Small values make leaves cheap: 0.1 gives big shallow leaves,
    /// 1.0 small deep ones. Must be > 0.
    float cost_ratio = 1.0f;
    /// Hard upper bound on primitives per leaf; a node above it is always split, by the best
    /// binned split or, when no bin separates the primitives, by the median. Must be >= 1.
    std::uint32_t leaf_size_max = 8;
    /// Binned SAH only: a node of at most this many primitives (and at most leaf_size_max) is
    /// a leaf, no split tried. The default 1 leaves it to the SAH; 4 makes about half the
    /// nodes (32 bytes each, held at the build's peak) for a coarser binary tree, which the
    /// wide collapse regroups into its blocks of four anyway (the engine's compact static
    /// group, UpdatePolicy::compact_static_group). Must be >= 1.
    std::uint32_t leaf_size_min = 1;
    /// Number of bins per axis for large nodes. Must be >= 2; values above 64 act as 64. A node
    /// of n primitives uses min(bin_count, 4 + n/20) bins (Embree's rule: fewer bins where
    /// clearing and sweeping them would cost more than binning), and nodes of at most four
    /// primitives try every split exactly instead.
    std::uint32_t bin_count = 16;
    /// build_triangle_bvh only: also collapse the tree into the wide tree (wide_bvh.h) that
    /// packets and single rays trace. Off, they trace the binary tree, for comparisons (`dynrt
    /// bench --bvh binary`); the hits are the same either way. The wide tree is also left out when
    /// leaf_size_max exceeds kWideLeafSizeMax (wide_bvh.h).
    bool wide = true;
    /// build_triangle_bvh only: the builder. BuildMethod::morton ignores cost_ratio and
    /// bin_count (its leaves hold at most min(8, leaf_size_max) primitives).
    BuildMethod method = BuildMethod::binned_sah;
    /// build_triangle_bvh with the wide tree only: compact leaves (WideBvhOf::compact), which
    /// hold the triangles' indices and read their corners from the build's TriangleSource at
    /// the trace. That source, and what it views, must then outlive the tree unchanged (or
    /// until a refit hands the tree new triangles, which it views from then on). About 40
    /// bytes a triangle fewer; the same hits bit for bit. Asked for memory first, so a Morton
    /// build keeps no scratch between builds either (TriangleBvh::morton_scratch: 16 bytes a
    /// triangle).
    bool compact_leaves = false;
    /// build_triangle_bvh with the wide tree only: quantised nodes (quantize_nodes,
    /// quantized_node.h), 128 bytes instead of 256 for the same tree, whose boxes hold the exact
    /// ones; the same hits bit for bit. A tree whose root box is not finite or spans more than
    /// 2^126 (about 8.5e37) on an axis keeps float nodes (can_quantize). A quantised tree
    /// cannot be refitted.
    bool quantized_nodes = false;

    SahCosts sah_costs() const { return SahCosts{1.0f, cost_ratio}; }
};

/// Builds a tree over `boxes.size()` primitives; `centers[i]` is the point used to bin
/// primitive i (usually its box centre or centroid) and must lie inside `boxes[i]`. Boxes must
/// be non-empty and finite. Both spans are borrowed for the duration of the call only.
/// Runs in parallel on the calling thread's oneTBB arena. The result satisfies `validate`, its
/// depth is at most kMaxDepth whatever the input (median splits take over where the SAH would
/// go deeper), and its prim_ids and tree shape do not depend on thread timing (the order of
/// nodes in the array may). An empty input gives an empty tree. Throws std::invalid_argument
/// for a bad config or spans of different sizes, std::length_error for 2^31 or more primitives.
Bvh build_binned_sah(std::span<const Aabb> boxes, std::span<const glm::vec3> centers,
                     const BuildConfig& config);

}  // namespace dynrt::bvh
