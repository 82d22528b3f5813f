// Refitting the wide tree in place (Wald, Boulos and Shirley 2007, "Ray Tracing Deformable
// Scenes Using Dynamic Bounding Volume Hierarchies"): every block re-reads its triangles from
// the caller's array, every slot box is recomputed bottom-up, the topology stays. A node's
// slots are refitted in slot order (as parallel tasks near the root), then its boxes and sums
// are made in slot order; every box and every partial SAH sum is one expression over its
// children's, so the schedule changes no bit. The tree's SAH cost is summed on the way (sah_terms.h), as sah_cost sums it.

#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/wide_bvh.h"

#include "sah_terms.h"

#include <oneapi/tbb/parallel_for.h>

#include <array>
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
/// every triangle is a cache miss.
constexpr std::uint32_t kPrefetchBlocks = 8;

template <int N>
class WideRefitter {
public:
    WideRefitter(WideBvhOf<N>& wide, std::span<const Triangle> tris, const SahCosts& costs)
        : wide_(wide), tris_(tris), costs_(costs) {}

    /// Refits the tree; returns its SAH cost.
    double run() {
        if (wide_.empty()) return 0.0;
        if (wide_.compact) {
            // Its leaves read the triangles it was built from, which must not move.
            throw std::invalid_argument("refit_wide: a tree with compact leaves cannot be refitted");
        }
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
        return detail::wide_sah_total(root.sah, root.box, costs_);
    }

private:
    struct Subtree {
        Aabb box;
        std::uint32_t prims = 0;
        detail::WideSahSum sah;
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
            detail::add_wide_slot(total.sah, below[i].box, leaf, below[i].prims, below[i].sah,
                                  costs_);
        }
        return total;
    }

    Subtree refit_leaf(std::uint32_t index, std::uint32_t first, std::uint32_t count) {
        if (first > wide_.blocks.size() || count > wide_.blocks.size() - first) {
            malformed(index, "has a leaf range outside the blocks");
        }
        Subtree leaf;
        for (std::uint32_t b = first; b < first + count; ++b) {
            prefetch(b + kPrefetchBlocks);
            TriangleBlock& block = wide_.blocks[b];
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
        }
        return leaf;
    }

    const Triangle& triangle(std::uint32_t prim) const {
        if (prim >= tris_.size()) {
            throw std::invalid_argument("refit_wide: primitive " + std::to_string(prim) +
                                        " is out of range (" + std::to_string(tris_.size()) +
                                        " triangles)");
        }
        return tris_[prim];
    }

    void prefetch(std::uint32_t block) const {
        if (block >= wide_.blocks.size()) return;
        for (std::uint32_t prim : wide_.blocks[block].prim) {
            if (prim < tris_.size()) {
                const char* p = reinterpret_cast<const char*>(tris_.data() + prim);
                prefetch_line(p);
                prefetch_line(p + sizeof(Triangle) - 1);
            }
        }
    }

    WideBvhOf<N>& wide_;
    std::span<const Triangle> tris_;
    SahCosts costs_;
};

}  // namespace

template <int N>
double refit_wide(WideBvhOf<N>& wide, std::span<const Triangle> tris, const SahCosts& costs) {
    return WideRefitter<N>(wide, tris, costs).run();
}

template double refit_wide<4>(WideBvhOf<4>&, std::span<const Triangle>, const SahCosts&);
template double refit_wide<8>(WideBvhOf<8>&, std::span<const Triangle>, const SahCosts&);

}  // namespace dynrt::bvh
