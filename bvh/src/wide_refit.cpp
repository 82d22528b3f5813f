// Refitting the wide tree in place (Wald, Boulos and Shirley 2007, "Ray Tracing Deformable
// Scenes Using Dynamic Bounding Volume Hierarchies"): every block re-reads its triangles from
// the caller's source (a copy of its triangles, a soup's vertices, or vertices through index
// triples), noting whether any corner differs from what the block held (a compact leaf, which
// holds none, reads them for its box and then views the new source); every slot box is
// recomputed bottom-up; the topology stays. A node's slots are refitted in slot order (as
// parallel tasks near the root), then its boxes and sums are made in slot order; every box and
// every partial SAH sum is one expression over its children's, so the schedule changes no bit.
// The tree's SAH cost is summed on the way (sah_terms.h), as sah_cost sums it.

#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/wide_bvh.h"

#include "sah_terms.h"

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

namespace dynrt::bvh {
namespace {

/// Wide levels whose inner children are refitted as parallel tasks (8^2 or 4^3 subtrees).
template <int N>
constexpr std::uint32_t kParallelLevels = N == 8 ? 2 : 3;

/// How many blocks ahead a leaf prefetches the caller's triangles it will read. Blocks are in
/// leaf order and the leaves are refitted in block order, so the triangles a later block reads
/// are known ahead: the caller's order is usually another, and without the prefetch nearly
/// every triangle is a cache miss. An indexed source is read in two steps (the index triple,
/// then the vertices it names), so its triples are asked for twice as far ahead.
constexpr std::uint32_t kPrefetchBlocks = 8;

/// A block's corners, v0, v1 and v2 one after another.
constexpr std::size_t kCornerFloats = 3 * 3 * kBlockLanes;
static_assert(offsetof(TriangleBlock, v2) + sizeof(TriangleBlock::v2) ==
              offsetof(TriangleBlock, v0) + kCornerFloats * sizeof(float));

template <int N>
class WideRefitter {
public:
    WideRefitter(WideBvhOf<N>& wide, const TriangleSource& tris, const SahCosts& costs)
        : wide_(wide), tris_(tris), costs_(costs) {}

    /// Refits the tree; returns its SAH cost and whether any corner moved.
    WideRefit run() {
        if (wide_.empty()) return {};
        if (wide_.quantized) {
            // Its boxes were rounded against the exact ones it no longer holds.
            throw std::invalid_argument("refit_wide: a tree with quantised nodes cannot be refitted");
        }
        const Subtree root = refit_node(0, 1);
        if (root.prims != wide_.triangle_count) {
            throw std::invalid_argument("refit_wide: the blocks hold " +
                                        std::to_string(root.prims) + " triangles, the tree " +
                                        std::to_string(wide_.triangle_count));
        }
        wide_.root_box = root.box;
        // Compact leaves read the triangles refitted to from now on (the caller keeps them).
        if (wide_.compact) wide_.source = tris_;
        return WideRefit{detail::wide_sah_total(root.sah, root.box, costs_), root.moved};
    }

private:
    struct Subtree {
        Aabb box;
        std::uint32_t prims = 0;
        detail::WideSahSum sah;
        /// Some corner below differs from what its block held.
        bool moved = false;
    };

    [[noreturn]] static void malformed(std::uint32_t index, const std::string& what) {
        throw std::invalid_argument("refit_wide: malformed tree: node " + std::to_string(index) +
                                    " " + what);
    }

    Subtree refit_node(std::uint32_t index, std::uint32_t depth) {
        if (depth > kMaxDepth) malformed(index, "is deeper than kMaxDepth");
        WideNode<N>& node = wide_.nodes[index];
        std::array<Subtree, N> below;
        auto refit_slot = [&](int i) {
            if (node.is_empty(i)) return;
            if (node.is_leaf(i)) {
                below[i] = refit_leaf(index, node.child[i], node.blocks[i]);
                return;
            }
            if (node.child[i] <= index || node.child[i] >= wide_.nodes.size()) {
                malformed(index, "has a child index out of range");
            }
            below[i] = refit_node(node.child[i], depth + 1);
        };
        // Slot order is block order (the blocks of a subtree follow those of the slots before
        // it), so the prefetch a few blocks ahead fetches what is read next.
        if (depth <= kParallelLevels<N>) {
            tbb::parallel_for(0, N, refit_slot);
        } else {
            for (int i = 0; i < N; ++i) refit_slot(i);
        }
        Subtree total;
        for (int i = 0; i < N; ++i) {
            if (node.is_empty(i)) continue;
            const bool leaf = node.is_leaf(i);
            node.set_box(i, below[i].box);
            total.box.extend(below[i].box);
            total.prims += below[i].prims;
            total.moved |= below[i].moved;
            detail::add_wide_slot(total.sah, below[i].box, leaf, below[i].prims, below[i].sah,
                                  costs_);
        }
        return total;
    }

    Subtree refit_leaf(std::uint32_t index, std::uint32_t first, std::uint32_t count) {
        if (first > wide_.block_count() || count > wide_.block_count() - first) {
            malformed(index, "has a leaf range outside the blocks");
        }
        if (wide_.compact) return refit_compact_leaf(first, count);
        Subtree leaf;
        for (std::uint32_t b = first; b < first + count; ++b) {
            prefetch(b + kPrefetchBlocks);
            if (tris_.indexed()) prefetch_triples(b + 2 * kPrefetchBlocks);
            TriangleBlock& block = wide_.blocks[b];
            // The corners as they were, compared with what the lanes get as one block (the
            // lane-by-lane compare cost a fifth of a refit from a copy).
            float before[kCornerFloats];
            std::memcpy(before, block.v0, sizeof before);
            for (int lane = 0; lane < kBlockLanes; ++lane) {
                const std::uint32_t prim = block.prim[lane];
                // Unused lanes repeat lane 0, which comes before them.
                const Triangle t = prim == kInvalidId ? block.triangle(0) : triangle(prim);
                for (int axis = 0; axis < 3; ++axis) {
                    block.v0[axis][lane] = t.v0[axis];
                    block.v1[axis][lane] = t.v1[axis];
                    block.v2[axis][lane] = t.v2[axis];
                }
                if (prim == kInvalidId) continue;
                leaf.box.extend(t.v0);
                leaf.box.extend(t.v1);
                leaf.box.extend(t.v2);
                ++leaf.prims;
            }
            leaf.moved |= std::memcmp(before, block.v0, sizeof before) != 0;
        }
        return leaf;
    }

    /// A compact leaf holds no corners: its box is made from the new triangles alone, and it
    /// counts as moved, having nothing to compare them with (the triangles it read before may
    /// be the very memory the caller rewrote).
    Subtree refit_compact_leaf(std::uint32_t first, std::uint32_t count) {
        Subtree leaf;
        leaf.moved = true;
        for (std::uint32_t b = first; b < first + count; ++b) {
            prefetch(b + kPrefetchBlocks);
            if (tris_.indexed()) prefetch_triples(b + 2 * kPrefetchBlocks);
            for (const std::uint32_t prim : wide_.prim_blocks[b].prim) {
                if (prim == kInvalidId) continue;
                const Triangle t = triangle(prim);
                leaf.box.extend(t.v0);
                leaf.box.extend(t.v1);
                leaf.box.extend(t.v2);
                ++leaf.prims;
            }
        }
        return leaf;
    }

    Triangle triangle(std::uint32_t prim) const {
        if (prim >= tris_.size()) {
            throw std::invalid_argument("refit_wide: primitive " + std::to_string(prim) +
                                        " is out of range (" + std::to_string(tris_.size()) +
                                        " triangles)");
        }
        return tris_[prim];
    }

    /// Asks for the corners the block's lanes read (an indexed source's triples were asked
    /// for earlier, prefetch_triples).
    void prefetch(std::uint32_t block) const {
        if (block >= wide_.block_count()) return;
        for (int lane = 0; lane < kBlockLanes; ++lane) {
            const std::uint32_t prim = wide_.prim(block, lane);
            if (prim < tris_.size()) tris_.prefetch_corners(prim);
        }
    }
    void prefetch_triples(std::uint32_t block) const {
        if (block >= wide_.block_count()) return;
        for (int lane = 0; lane < kBlockLanes; ++lane) {
            const std::uint32_t prim = wide_.prim(block, lane);
            if (prim < tris_.size()) tris_.prefetch(prim);
        }
    }

    WideBvhOf<N>& wide_;
    const TriangleSource& tris_;
    SahCosts costs_;
};

}  // namespace

template <int N>
WideRefit refit_wide(WideBvhOf<N>& wide, const TriangleSource& tris, const SahCosts& costs) {
    return WideRefitter<N>(wide, tris, costs).run();
}

template WideRefit refit_wide<4>(WideBvhOf<4>&, const TriangleSource&, const SahCosts&);
template WideRefit refit_wide<8>(WideBvhOf<8>&, const TriangleSource&, const SahCosts&);

}  // namespace dynrt::bvh
