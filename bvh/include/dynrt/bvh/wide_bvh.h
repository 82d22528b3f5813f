#pragma once
// The wide BVH: a 4- or 8-ary tree collapsed from the binary binned-SAH tree (or, for the
// fast rebuild, made directly from Morton-sorted triangles: bvh/src/wide_morton_builder.cpp),
// with child boxes in SoA layout (one SIMD pass tests a ray against every child) and
// triangles pre-gathered per leaf into SoA blocks of four (one SIMD pass runs the watertight
// test on four triangles). Single rays trace it nearest child first (closest hit) or stop at
// the first hit (any hit).
//
// The collapse follows Ylitie, Karras and Laine 2017, "Efficient Incoherent Ray Traversal on
// GPUs Through Compressed Wide BVHs" (section 4.1): a dynamic program over the binary tree picks,
// for every wide node, which binary descendants become its children and which subtrees become
// one leaf, minimising the SAH cost of the wide tree. No box is recomputed: each wide child's
// box is the box of a binary node, so the wide tree culls exactly where the binary one does,
// and hits are the very same (the same watertight arithmetic and the same tie rule: smallest
// t, then smallest primitive index).
//
// Memory: one node is 128 bytes (N = 4) or 256 bytes (N = 8), or half that with quantised
// child boxes (QuantizedWideNode, quantized_node.h); one block 160 bytes for up to four
// triangles (vertices and the caller's index), or 16 with compact leaves (the index only,
// PrimBlock). bytes() reports them.

#include "dynrt/bvh/aabb.h"
#include "dynrt/bvh/bvh.h"
#include "dynrt/bvh/quantized_node.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_source.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace dynrt::bvh {

/// Triangles per leaf block: the SIMD width of the triangle test.
inline constexpr int kBlockLanes = 4;

/// Up to four triangles, structure of arrays: `v0[axis][lane]` is vertex 0's coordinate on that
/// axis of the lane's triangle. Unused lanes repeat lane 0's vertices and have prim kInvalidId;
/// the test masks them out.
struct alignas(16) TriangleBlock {
    float v0[3][kBlockLanes];
    float v1[3][kBlockLanes];
    float v2[3][kBlockLanes];
    /// The caller's triangle index of each lane (the index given to build_triangle_bvh).
    std::uint32_t prim[kBlockLanes];

    Triangle triangle(int lane) const {
        return Triangle{{v0[0][lane], v0[1][lane], v0[2][lane]},
                        {v1[0][lane], v1[1][lane], v1[2][lane]},
                        {v2[0][lane], v2[1][lane], v2[2][lane]}};
    }
};
static_assert(sizeof(TriangleBlock) == 160);

/// A compact leaf block (BuildConfig::compact_leaves): only each lane's caller index
/// (kInvalidId for an unused lane). The trace reads the corners from the triangles the tree was
/// built from (WideBvhOf::source) as it reaches the block: 16 bytes for up to four triangles
/// instead of 160, for two dependent reads per lane (an index triple, then its vertices).
/// Embree's compact mode makes the same trade (RTC_SCENE_FLAG_COMPACT, triangles read through
/// the application's index buffer).
struct alignas(16) PrimBlock {
    std::uint32_t prim[kBlockLanes];
};
static_assert(sizeof(PrimBlock) == 16);

/// The largest binary leaf the wide tree can hold: a leaf slot counts its blocks in 16 bits.
inline constexpr std::uint32_t kWideLeafSizeMax = 0xffffu * kBlockLanes;

/// One node of an N-wide tree. Child slot i is
///   - empty when blocks[i] == 0 and child[i] == kInvalidId (its box is the empty box, which no
///     ray meets); empty slots come after every used slot;
///   - an inner node when blocks[i] == 0: child[i] indexes WideBvhOf::nodes;
///   - a leaf when blocks[i] > 0: triangle blocks [child[i], child[i] + blocks[i]).
template <int N>
struct alignas(64) WideNode {
    static_assert(N == 4 || N == 8, "wide nodes are 4 or 8 wide");
    float lo_x[N], lo_y[N], lo_z[N];
    float hi_x[N], hi_y[N], hi_z[N];
    std::uint32_t child[N];
    std::uint16_t blocks[N];

    /// A node with every slot empty (its padding zeroed, so equal trees are equal bytes).
    static WideNode empty() {
        WideNode node;
        std::memset(static_cast<void*>(&node), 0, sizeof node);
        for (int i = 0; i < N; ++i) {
            node.set_box(i, Aabb{});
            node.child[i] = kInvalidId;
            node.blocks[i] = 0;
        }
        return node;
    }

    bool is_empty(int i) const { return blocks[i] == 0 && child[i] == kInvalidId; }
    bool is_leaf(int i) const { return blocks[i] != 0; }
    Aabb box(int i) const {
        return Aabb{{lo_x[i], lo_y[i], lo_z[i]}, {hi_x[i], hi_y[i], hi_z[i]}};
    }
    void set_box(int i, const Aabb& b) {
        lo_x[i] = b.lo.x; lo_y[i] = b.lo.y; lo_z[i] = b.lo.z;
        hi_x[i] = b.hi.x; hi_y[i] = b.hi.y; hi_z[i] = b.hi.z;
    }
};
static_assert(sizeof(WideNode<4>) == 128 && sizeof(WideNode<8>) == 256);

/// The allocator of the wide tree's arrays: like std::allocator, except that growing a vector
/// leaves the new elements uninitialised instead of zeroing them, since the collapse writes
/// every one of them right after (zeroing 60 MB for a million triangles took a tenth of the
/// collapse).
template <class T>
struct UninitializedAllocator : std::allocator<T> {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) {}

    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0) {
            ::new (static_cast<void*>(p)) U;
        } else {
            ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
        }
    }
};

/// An N-wide tree over triangles. `nodes[0]` is the root (an inner node, even over a single
/// leaf) when the tree is non-empty; nodes are in depth-first order, every child after its
/// parent.
template <int N>
struct WideBvhOf {
    std::vector<WideNode<N>, UninitializedAllocator<WideNode<N>>> nodes;
    /// ... or, with quantised nodes (quantize_nodes), the same nodes with their child boxes
    /// quantised, and `nodes` empty. visit_nodes hands either to a generic reader.
    std::vector<QuantizedWideNode<N>, UninitializedAllocator<QuantizedWideNode<N>>> quantized_nodes;
    /// Whether the nodes are quantized_nodes rather than nodes.
    bool quantized = false;
    /// The leaves' blocks (a leaf slot's child indexes this array)...
    std::vector<TriangleBlock, UninitializedAllocator<TriangleBlock>> blocks;
    /// ... or, with compact leaves, theirs (the same indices, one PrimBlock per block).
    std::vector<PrimBlock, UninitializedAllocator<PrimBlock>> prim_blocks;
    /// Whether the leaves are compact (prim_blocks and source) rather than full blocks.
    bool compact = false;
    /// With compact leaves, the triangles the tree was built or last refitted from, viewed:
    /// whoever holds the tree keeps them alive and unchanged while it is traced (a tree over
    /// moving triangles views the new ones at each refit, refit_wide).
    TriangleSource source;
    /// The root's box (the union of its children's), for callers that cull whole trees.
    Aabb root_box;
    /// Triangles in the tree (the used lanes of the blocks).
    std::size_t triangle_count = 0;

    bool empty() const { return node_count() == 0; }
    std::size_t node_count() const { return quantized ? quantized_nodes.size() : nodes.size(); }
    std::size_t bytes() const {
        return nodes.size() * sizeof(WideNode<N>) +
               quantized_nodes.size() * sizeof(QuantizedWideNode<N>) +
               blocks.size() * sizeof(TriangleBlock) + prim_blocks.size() * sizeof(PrimBlock) +
               source.bytes();
    }
    /// Calls f(nodes) with the node array the tree is traced by, as a pointer to its first
    /// element: const WideNode<N>* or const QuantizedWideNode<N>* (the one code path of a
    /// reader, instantiated for each).
    template <class F>
    decltype(auto) visit_nodes(F&& f) const {
        if (quantized) return f(static_cast<const QuantizedWideNode<N>*>(quantized_nodes.data()));
        return f(static_cast<const WideNode<N>*>(nodes.data()));
    }
    /// The number of leaf blocks, full or compact.
    std::size_t block_count() const { return compact ? prim_blocks.size() : blocks.size(); }
    /// The caller index of block `b`'s lane (kInvalidId for an unused lane).
    std::uint32_t prim(std::size_t b, int lane) const {
        return compact ? prim_blocks[b].prim[lane] : blocks[b].prim[lane];
    }
    /// Most blocks of a compact leaf gathered at once (gather_leaf, gather_blocks).
    static constexpr std::uint32_t kGatherBlocks = TriangleSource::kGatherMax / kBlockLanes;
    /// With compact leaves, the triangles of blocks [first, first + count) (count <=
    /// kGatherBlocks) read through the source, block first + b's lane l handed to
    /// `corners(b * kBlockLanes + l, v0, v1, v2)` (unused lanes are passed over). The source
    /// reads them in stages (TriangleSource::gather), so the misses of a leaf overlap
    /// (soup:4000000 at 512x512, whose triangles lie in random order: primary rays 77 -> 66 ms
    /// when that was first done, by prefetching), and finds each triangle's mesh once.
    template <class Corners>
    void gather_leaf(std::uint32_t first, std::uint32_t count, Corners&& corners) const {
        std::uint32_t ids[TriangleSource::kGatherMax];
        for (std::uint32_t b = 0; b < count; ++b) {
            for (int lane = 0; lane < kBlockLanes; ++lane) {
                ids[b * kBlockLanes + lane] = prim_blocks[first + b].prim[lane];
            }
        }
        source.gather(ids, int(count * kBlockLanes), corners);
    }
    /// gather_leaf into blocks as the triangle test reads them: block first + b into out[b],
    /// its prims with it, an unused lane repeating lane 0's corners as a full block's does (the
    /// same floats as full blocks', so the same hits bit for bit).
    void gather_blocks(std::uint32_t first, std::uint32_t count, TriangleBlock* out) const {
        gather_leaf(first, count, [&](std::uint32_t k, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2) {
            TriangleBlock& block = out[k / kBlockLanes];
            const std::uint32_t lane = k % kBlockLanes;
            for (int axis = 0; axis < 3; ++axis) {
                block.v0[axis][lane] = v0[axis];
                block.v1[axis][lane] = v1[axis];
                block.v2[axis][lane] = v2[axis];
            }
        });
        for (std::uint32_t b = 0; b < count; ++b) {
            TriangleBlock& block = out[b];
            for (int lane = 0; lane < kBlockLanes; ++lane) {
                block.prim[lane] = prim_blocks[first + b].prim[lane];
                if (block.prim[lane] != kInvalidId) continue;
                for (int axis = 0; axis < 3; ++axis) {
                    block.v0[axis][lane] = block.v0[axis][0];
                    block.v1[axis][lane] = block.v1[axis][0];
                    block.v2[axis][lane] = block.v2[axis][0];
                }
            }
        }
    }
    /// Lane `lane`'s triangle of block `b` (a used lane).
    Triangle triangle(std::size_t b, int lane) const {
        return compact ? source[prim_blocks[b].prim[lane]] : blocks[b].triangle(lane);
    }
};

/// The width the engine uses. Both widths are built and tested; 8 was measured faster on the
/// AVX2 development machine (benchmarks/README.md, "Wide trees").
inline constexpr int kWideWidth = 8;
using WideBvh = WideBvhOf<kWideWidth>;

/// Whether every node of a tree inside `root` can be quantised (quantize_node): `root` is
/// finite and at most 2^126 across on each axis (half the widest grid, 255 * 2^119, so that
/// no rounding of the planes can fall short).
bool can_quantize(const Aabb& root);

/// Quantises `node`'s child boxes into `out` (quantized_node.h): every decoded box contains
/// the exact one. False, with `out` unspecified, when a box is not finite or spans more than
/// 255 * 2^119 on an axis (no 8-bit grid covers it).
template <int N>
bool quantize_node(const WideNode<N>& node, QuantizedWideNode<N>& out);

/// Replaces `wide`'s float nodes with quantised ones (WideBvhOf::quantized), in parallel. When
/// the root box cannot be quantised (can_quantize) the tree keeps its float nodes and this
/// returns false. A tree with quantised nodes cannot be refitted (refit_wide refuses it). The
/// collapse writes quantised nodes itself when the tree it is handed is marked quantized
/// (build_triangle_bvh with BuildConfig::quantized_nodes), without the float nodes at all.
template <int N>
bool quantize_nodes(WideBvhOf<N>& wide);

/// Relative costs of the collapse's SAH, in units of one wide node test. A block of four
/// triangles costs a little more than a node test (more arithmetic, same one SIMD pass).
struct WideCosts {
    float node = 1.0f;
    float block = 1.25f;
    /// Largest leaf the collapse may form by merging binary leaves, in triangles. A binary
    /// leaf larger than this stays one leaf.
    std::uint32_t leaf_prims_max = 16;
};

/// Collapses the binary tree `bvh` (made by build_binned_sah or build_triangle_bvh; its leaves
/// refer to `prim_ids`) into an N-wide tree. `leaf_tris[k]` is the triangle of leaf position k
/// (TriangleBvh::tris); blocks record the caller's index `bvh.prim_ids[k]`. Runs in parallel on
/// the calling thread's oneTBB arena; the result does not depend on thread timing. An empty
/// tree gives an empty wide tree. Throws std::length_error when a binary leaf needs more than
/// 65535 blocks (leaf_size_max above 262,140). `recycled`, a wide tree no longer needed, lends
/// its storage (a tree rebuilt every frame then writes memory that is already faulted in), and
/// says the kind of tree to make: `compact` leaves over its `source`, `quantized` nodes
/// (written quantised as they are made, when can_quantize accepts the root box).
template <int N>
WideBvhOf<N> collapse_to_wide(const Bvh& bvh, std::span<const Triangle> leaf_tris,
                              const WideCosts& costs = {}, WideBvhOf<N>&& recycled = {});

/// collapse_to_wide from the caller's triangles as they are: `tris[i]` is the caller's
/// triangle i, so leaf position k's is tris[bvh.prim_ids[k]]. The same tree bit for bit,
/// without a leaf-order copy of the triangles (36 bytes per triangle at a build's peak).
/// Throws std::invalid_argument for a primitive id past `tris`.
template <int N>
WideBvhOf<N> collapse_to_wide_by_id(const Bvh& bvh, const TriangleSource& tris,
                                    const WideCosts& costs = {}, WideBvhOf<N>&& recycled = {});

/// What refit_wide did.
struct WideRefit {
    /// The refitted tree's SAH cost, as sah_cost computes it (bit for bit: the same sums in the
    /// same order), gathered during the refit.
    double sah_cost = 0.0;
    /// Whether any corner read differs from what its block held, bit for bit: false means the
    /// tree came out as it was. Always true for compact leaves, which hold no corners to
    /// compare with.
    bool moved = false;
};

/// Refits the wide tree in place to `tris`, the caller's triangles after a move (indexed as
/// TriangleBlock::prim; a copy of the triangles, a soup's vertices, or vertices read through
/// index triples): every block's vertices are re-read, every child box recomputed bottom-up
/// (a leaf's as the union of its triangles' boxes, an inner node's as the union of its
/// children's). The topology stays, and so does every triangle's block and lane
/// (BlockTriangles still reads them). Compact leaves hold no vertices: their boxes are made
/// from `tris`, which the tree views from then on (WideBvhOf::source; the caller keeps it
/// alive and unchanged while the tree is traced). Parallel and deterministic. Throws
/// std::invalid_argument for a prim index out of range or a malformed tree, or a tree with
/// quantised nodes.
template <int N>
WideRefit refit_wide(WideBvhOf<N>& wide, const TriangleSource& tris, const SahCosts& costs);

/// The SAH cost of the wide tree (MacDonald and Booth 1990, over wide nodes): the sum over
/// inner nodes of A(n)/A(root) * traversal plus over leaves of A(leaf)/A(root) * triangles *
/// intersection, where a node's box is its parent's slot box (the root's, root_box). A wide
/// node costs one traversal step whatever its number of children, so the figure is lower than
/// the binary tree's; compare it only with other wide trees' (the refit judge compares a
/// tree's cost after a refit with the same tree's at its build). A point-like or flat root
/// (zero area) weighs every node 1. 0 for an empty tree.
template <int N>
double sah_cost(const WideBvhOf<N>& wide, const SahCosts& costs);

/// Work done by a traversal, for benchmarks (counted only by the overloads that take it).
struct WideTraversalStats {
    /// Inner nodes whose children were box-tested.
    std::uint64_t nodes_visited = 0;
    /// Leaves whose blocks were tested.
    std::uint64_t leaves_visited = 0;
    /// Triangle lanes tested (used lanes only).
    std::uint64_t triangles_tested = 0;
};

/// Closest hit within [ray.tmin, ray.tmax]: the smallest t, ties to the smallest caller index,
/// exactly as intersect_closest on the binary tree. Thread-safe on a shared tree.
template <int N>
Hit intersect_closest(const WideBvhOf<N>& wide, const Ray& ray);
template <int N>
Hit intersect_closest(const WideBvhOf<N>& wide, const Ray& ray, WideTraversalStats& stats);

/// True when any triangle is hit within [ray.tmin, ray.tmax]. Thread-safe.
template <int N>
bool intersect_any(const WideBvhOf<N>& wide, const Ray& ray);
template <int N>
bool intersect_any(const WideBvhOf<N>& wide, const Ray& ray, WideTraversalStats& stats);

/// A subtree of a wide tree as a node's child slot names it: inner node `child` when blocks
/// is 0, else the leaf of blocks [child, child + blocks).
struct WideSubtree {
    std::uint32_t child = 0;
    std::uint32_t blocks = 0;
};

/// Continues a closest-hit query below `subtree`, for a ray known to meet its box (a packet
/// tracer handing its last few rays to single-ray traversal): `hit` is the ray's closest hit so
/// far (a default Hit for none) and ray.tmax its t when there is one. A closer hit below, by
/// intersect_closest's rules (ties to the smaller caller index), replaces it; returns whether
/// one did. `stats`, when given, receives the work (added).
template <int N>
bool intersect_closest(const WideBvhOf<N>& wide, WideSubtree subtree, const Ray& ray, Hit& hit,
                       WideTraversalStats* stats = nullptr);
/// Whether any triangle below `subtree` is hit within [ray.tmin, ray.tmax]; as above.
template <int N>
bool intersect_any(const WideBvhOf<N>& wide, WideSubtree subtree, const Ray& ray,
                   WideTraversalStats* stats = nullptr);

/// Shape figures of a wide tree.
struct WideStats {
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    std::size_t blocks = 0;
    /// Used lanes / all lanes of the blocks.
    double block_fill = 0.0;
    /// Mean used child slots per node.
    double children_mean = 0.0;
    /// Mean and largest triangle count of a leaf.
    double leaf_prims_mean = 0.0;
    std::uint32_t leaf_prims_max = 0;
    /// Wide nodes on the longest path from the root, the leaf not counted (a root over leaves
    /// only has depth 1).
    std::uint32_t depth = 0;
    std::size_t bytes = 0;
};
template <int N>
WideStats compute_stats(const WideBvhOf<N>& wide);

/// Checks the wide tree against `tris` (the caller's triangles, indexed as
/// TriangleBlock::prim): every node reached once from the root, depth within kMaxDepth, used
/// slots before empty ones, every child box inside its parent's slot box, every block's used
/// lanes inside their leaf's box and bit-equal to `tris[prim]`, unused lanes marked, and the
/// tree holding exactly the caller indices `prims` (in any order; each once), triangle_count
/// their number. Returns "" when valid, else the first violation. For tests and
/// debug checks after every build and refit.
template <int N>
std::string validate(const WideBvhOf<N>& wide, std::span<const Triangle> tris,
                     std::span<const std::uint32_t> prims);

}  // namespace dynrt::bvh
