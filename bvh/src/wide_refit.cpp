// Refitting the wide tree in place (Wald, Boulos and Shirley 2007, as refit.cpp does for the
// binary tree): every block re-reads its triangles, every slot box is recomputed bottom-up, the
// topology stays. A node's inner children are refitted first (as parallel tasks near the
// root), then its leaves, whose leaf-order positions follow from the triangle counts of the
// slots before them; every box is one expression over its children's, so the schedule changes
// no bit. The triangles come either from the caller's array by index (refit_wide) or from the
// leaf-ordered copy, read front to back (refit_wide_leaf_order).

#include "dynrt/bvh/wide_bvh.h"

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <stdexcept>
#include <string>

namespace dynrt::bvh {
namespace {

/// Wide levels whose inner children are refitted as parallel tasks (8^2 or 4^3 subtrees).
template <int N>
constexpr std::uint32_t kParallelLevels = N == 8 ? 2 : 3;

/// How many blocks ahead a leaf prefetches the caller's triangles it will read.
constexpr std::uint32_t kPrefetchBlocks = 6;

/// The caller's triangles by index. Blocks are in leaf order, and the leaves are refitted in
/// block order, so the triangles a later block reads are known ahead: the caller's order is
/// usually another, and without the prefetch nearly every triangle is a cache miss.
struct CallerOrder {
    static constexpr const char* kName = "refit_wide";
    std::span<const Triangle> tris;
    std::span<const TriangleBlock> blocks;

    const Triangle& operator()(std::uint32_t prim, std::uint32_t) const {
        if (prim >= tris.size()) {
            throw std::invalid_argument("refit_wide: primitive " + std::to_string(prim) +
                                        " is out of range (" + std::to_string(tris.size()) +
                                        " triangles)");
        }
        return tris[prim];
    }

    void prefetch(std::uint32_t block) const {
        if (block + kPrefetchBlocks >= blocks.size()) return;
        for (std::uint32_t prim : blocks[block + kPrefetchBlocks].prim) {
            if (prim < tris.size()) {
                const char* p = reinterpret_cast<const char*>(tris.data() + prim);
                __builtin_prefetch(p);
                __builtin_prefetch(p + sizeof(Triangle) - 1);
            }
        }
    }
};

/// The triangles in leaf order, by position: a sequential read.
struct LeafOrder {
    static constexpr const char* kName = "refit_wide_leaf_order";
    std::span<const Triangle> leaf_tris;

    const Triangle& operator()(std::uint32_t, std::uint32_t position) const {
        if (position >= leaf_tris.size()) {
            throw std::invalid_argument("refit_wide_leaf_order: the tree has more than the " +
                                        std::to_string(leaf_tris.size()) + " triangles given");
        }
        return leaf_tris[position];
    }

    void prefetch(std::uint32_t) const {}
};

template <int N, class Source>
class WideRefitter {
public:
    WideRefitter(WideBvhOf<N>& wide, const Source& source) : wide_(wide), source_(source) {}

    /// Refits the tree; returns the number of triangles in it.
    std::size_t run() {
        if (wide_.nodes.empty()) return 0;
        if (wide_.nodes[0].first_position != 0) malformed(0, "does not start at position 0");
        const Subtree root = refit_node(0, 1);
        wide_.root_box = root.box;
        return root.prims;
    }

private:
    struct Subtree {
        Aabb box;
        std::uint32_t prims = 0;
    };

    [[noreturn]] static void malformed(std::uint32_t index, const std::string& what) {
        throw std::invalid_argument(std::string(Source::kName) + ": malformed tree: node " +
                                    std::to_string(index) + " " + what);
    }

    Subtree refit_node(std::uint32_t index, std::uint32_t depth) {
        if (depth > kMaxDepth) malformed(index, "is deeper than kMaxDepth");
        WideNode<N>& node = wide_.nodes[index];
        std::array<Subtree, N> below;
        auto refit_inner = [&](int i) {
            if (node.is_empty(i) || node.is_leaf(i)) return;
            if (node.child[i] <= index || node.child[i] >= wide_.nodes.size()) {
                malformed(index, "has a child index out of range");
            }
            below[i] = refit_node(node.child[i], depth + 1);
        };
        if (depth <= kParallelLevels<N>) {
            tbb::parallel_for(0, N, refit_inner);
        } else {
            for (int i = 0; i < N; ++i) refit_inner(i);
        }
        std::uint32_t position = node.first_position;
        Subtree total;
        for (int i = 0; i < N; ++i) {
            if (node.is_empty(i)) continue;
            if (node.is_leaf(i)) {
                below[i] = refit_leaf(index, node.child[i], node.blocks[i], position);
            } else if (wide_.nodes[node.child[i]].first_position != position) {
                malformed(index, "has a child whose triangles do not follow its earlier slots'");
            }
            position += below[i].prims;
            node.set_box(i, below[i].box);
            total.box.extend(below[i].box);
            total.prims += below[i].prims;
        }
        return total;
    }

    Subtree refit_leaf(std::uint32_t index, std::uint32_t first, std::uint32_t count,
                       std::uint32_t position) {
        if (first > wide_.blocks.size() || count > wide_.blocks.size() - first) {
            malformed(index, "has a leaf range outside the blocks");
        }
        Subtree leaf;
        for (std::uint32_t b = first; b < first + count; ++b) {
            source_.prefetch(b);
            TriangleBlock& block = wide_.blocks[b];
            for (int lane = 0; lane < kBlockLanes; ++lane) {
                const std::uint32_t prim = block.prim[lane];
                // Unused lanes repeat lane 0, which comes before them.
                const Triangle t = prim == kInvalidId ? block.triangle(0) : source_(prim, position++);
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
        }
        return leaf;
    }

    WideBvhOf<N>& wide_;
    Source source_;
};

}  // namespace

template <int N>
void refit_wide(WideBvhOf<N>& wide, std::span<const Triangle> tris) {
    WideRefitter<N, CallerOrder>(wide, CallerOrder{tris, wide.blocks}).run();
}

template <int N>
void refit_wide_leaf_order(WideBvhOf<N>& wide, std::span<const Triangle> leaf_tris) {
    const std::size_t count = WideRefitter<N, LeafOrder>(wide, LeafOrder{leaf_tris}).run();
    if (count != leaf_tris.size()) {
        throw std::invalid_argument("refit_wide_leaf_order: the tree holds " +
                                    std::to_string(count) + " triangles, " +
                                    std::to_string(leaf_tris.size()) + " given");
    }
}

template void refit_wide<4>(WideBvhOf<4>&, std::span<const Triangle>);
template void refit_wide<8>(WideBvhOf<8>&, std::span<const Triangle>);
template void refit_wide_leaf_order<4>(WideBvhOf<4>&, std::span<const Triangle>);
template void refit_wide_leaf_order<8>(WideBvhOf<8>&, std::span<const Triangle>);

}  // namespace dynrt::bvh
