// The fast rebuild's tree: the 8-wide tree made directly from triangles sorted along a Morton
// curve, with no binary tree and no collapse, as Embree's Morton builder makes its BVH8 (Wald,
// Woop, Benthin, Johnson and Ernst 2014, "Embree: A Kernel Framework for Efficient CPU Ray
// Tracing", section 5.2). The split rule is the binary Morton builder's (morton_split: where the
// sorted codes' highest differing bit changes, Karras 2012): a node's range is split, the child
// of most triangles first, until the node has N children or every child is small enough to be
// a leaf. Leaves hold at most `leaf_prims` triangles in blocks of four, gathered from the
// caller's triangles in Morton order (one pass over them, prefetched ahead). No SAH is
// evaluated, so the tree costs more to trace than the binned SAH tree's collapse.
//
// Layout: depth first, each node before its children, a node's leaves' blocks and child
// subtrees in slot order (the collapse's layout). The top levels are made in parallel: they
// are planned first, their children's subtrees counted (a dry run of the same splits on the
// codes alone), which places every subtree before any is made; below, one task fills a whole
// subtree in order. Either way each subtree lands in the same place, so the tree does not depend on the
// thread count.

#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/wide_bvh.h"

#include "block_writer.h"
#include "huge_pages.h"
#include "morton_core.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace dynrt::bvh::detail {
namespace {

constexpr int N = kWideWidth;
using Node = WideNode<N>;
/// Nodes at depths up to this are planned and make their children as parallel tasks (up to
/// N^2 of them).
constexpr std::uint32_t kParallelDepth = 2;
/// How many sorted positions ahead a leaf prefetches the caller's triangle it will read.
constexpr std::uint32_t kPrefetchAhead = 16;

/// Sorted positions [begin, end).
struct Range {
    std::uint32_t begin = 0, end = 0;
    std::uint32_t size() const { return end - begin; }
};

/// Nodes and blocks of a subtree.
struct Size {
    std::uint32_t nodes = 0, blocks = 0;

    Size& operator+=(const Size& other) {
        nodes += other.nodes;
        blocks += other.blocks;
        return *this;
    }
};

/// A node's children: ranges in Morton order.
struct Children {
    std::array<Range, N> range;
    int count = 0;
};

class WideMortonBuilder {
public:
    /// `keys` sorted, `codes` room for their codes.
    WideMortonBuilder(const TriangleSource& tris, const std::uint64_t* keys,
                      std::uint32_t* codes, std::uint32_t count, std::uint32_t leaf_prims)
        : tris_(tris), keys_(keys), codes_(codes), count_(count), leaf_prims_(leaf_prims) {}

    WideBvh run(WideBvh&& recycled) {
        WideBvh wide = std::move(recycled);
        wide.nodes.clear();
        wide.quantized = false;  // the builder writes float nodes (quantize_nodes may follow)
        wide.quantized_nodes.clear();
        // The codes on their own, half the bytes for the splits' searches to read.
        tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, count_, kMortonBlock),
                          [&](const tbb::blocked_range<std::uint32_t>& r) {
                              for (std::uint32_t k = r.begin(); k < r.end(); ++k) {
                                  codes_[k] = static_cast<std::uint32_t>(keys_[k] >> 32);
                              }
                          });
        const Range all{0, count_};
        // The root is a node even over a single leaf.
        const bool root_leaf = is_leaf(all);
        const std::unique_ptr<Planned> root = root_leaf ? nullptr : plan(all, 1);
        const Size total = root_leaf ? Size{1, blocks_of(all)} : size_of(*root);
        resize_with_huge_pages(wide.nodes, total.nodes);
        nodes_ = wide.nodes.data();
        blocks_ = allocate_blocks(wide, total.blocks);
        if (root_leaf) {
            Children one;
            one.range[0] = all;
            one.count = 1;
            std::array<Aabb, N> boxes;
            boxes[0] = fill_leaf(all, 0);
            wide.root_box = write_node(one, 0, {}, {}, boxes);
        } else {
            wide.root_box = make_planned(*root, 0, 0);
        }
        wide.triangle_count = count_;
        return wide;
    }

private:
    std::uint32_t id(std::uint32_t k) const { return static_cast<std::uint32_t>(keys_[k]); }
    bool is_leaf(Range r) const { return r.size() <= leaf_prims_; }
    static std::uint32_t blocks_of(Range r) { return (r.size() + kBlockLanes - 1) / kBlockLanes; }

    /// Splits an inner node's range into its children: the largest child above leaf size is
    /// split (the first of equal ones), until there are N or none is left to split.
    Children split(Range r) const {
        Children c;
        c.range[0] = r;
        c.count = 1;
        while (c.count < N) {
            int largest = -1;
            std::uint32_t largest_size = leaf_prims_;
            for (int i = 0; i < c.count; ++i) {
                if (c.range[i].size() > largest_size) {
                    largest = i;
                    largest_size = c.range[i].size();
                }
            }
            if (largest < 0) break;
            const Range whole = c.range[largest];
            const std::uint32_t mid = morton_split(codes_, whole.begin, whole.end);
            for (int i = c.count; i > largest + 1; --i) c.range[i] = c.range[i - 1];
            c.range[largest] = Range{whole.begin, mid};
            c.range[largest + 1] = Range{mid, whole.end};
            ++c.count;
        }
        return c;
    }

    /// The nodes and blocks the subtree over `r` will take: the same splits, nothing written
    /// but the inner nodes' children, appended to `record` in depth-first order for the making
    /// to read back instead of splitting again.
    Size count(Range r, std::vector<Children>& record) const {
        if (is_leaf(r)) return Size{0, blocks_of(r)};
        const Children c = split(r);
        record.push_back(c);
        Size s{1, 0};
        for (int i = 0; i < c.count; ++i) s += count(c.range[i], record);
        return s;
    }

    /// A node of the top levels, split and its children's subtrees counted before any is made:
    /// the inner children above kParallelDepth are planned nodes themselves.
    struct Planned {
        Children children;
        std::array<Size, N> sizes{};
        std::array<std::unique_ptr<Planned>, N> below;
        /// The splits below the inner children that are not planned (count's record).
        std::array<std::vector<Children>, N> recorded;
    };

    /// The nodes and blocks of a planned node's subtree, the node included.
    static Size size_of(const Planned& p) {
        Size s{1, 0};
        for (int i = 0; i < p.children.count; ++i) s += p.sizes[i];
        return s;
    }

    /// Plans the inner node over `r` at `depth` and its top-level descendants, the children
    /// as parallel tasks.
    std::unique_ptr<Planned> plan(Range r, std::uint32_t depth) const {
        auto node = std::make_unique<Planned>();
        node->children = split(r);
        tbb::parallel_for(0, node->children.count, [&](int i) {
            const Range child = node->children.range[i];
            if (is_leaf(child) || depth >= kParallelDepth) {
                node->sizes[i] = count(child, node->recorded[i]);
                return;
            }
            node->below[i] = plan(child, depth + 1);
            node->sizes[i] = size_of(*node->below[i]);
        });
        return node;
    }

    /// Makes the planned node at `at` with its subtrees, the children as parallel tasks.
    /// Returns the node's box.
    Aabb make_planned(const Planned& p, std::uint32_t at, std::uint32_t first_block) {
        const Children& c = p.children;
        std::array<std::uint32_t, N> child_at{}, child_block{};
        std::uint32_t next_node = at + 1, next_block = first_block;
        for (int i = 0; i < c.count; ++i) {
            child_at[i] = next_node;
            child_block[i] = next_block;
            next_node += p.sizes[i].nodes;
            next_block += p.sizes[i].blocks;
        }
        std::array<Aabb, N> boxes;
        tbb::parallel_for(0, c.count, [&](int i) {
            const Range r = c.range[i];
            if (is_leaf(r)) {
                boxes[i] = fill_leaf(r, child_block[i]);
            } else if (p.below[i]) {
                boxes[i] = make_planned(*p.below[i], child_at[i], child_block[i]);
            } else {
                const Children* next = p.recorded[i].data();
                std::uint32_t node = child_at[i] + 1, block = child_block[i];
                const Children& top = *next++;
                boxes[i] = make_serial(top, child_at[i], node, block, next);
            }
        });
        return write_node(c, at, child_at, child_block, boxes);
    }

    /// Makes the node at `at` over `c` with its subtrees in order, taking the places of its
    /// descendants from `next_node` and of its leaves' blocks from `next_block` on, and their
    /// children from `recorded` on (count's record).
    Aabb make_serial(const Children& c, std::uint32_t at, std::uint32_t& next_node,
                     std::uint32_t& next_block, const Children*& recorded) {
        std::array<std::uint32_t, N> child_at{}, child_block{};
        std::array<Aabb, N> boxes;
        for (int i = 0; i < c.count; ++i) {
            const Range r = c.range[i];
            child_block[i] = next_block;
            if (is_leaf(r)) {
                boxes[i] = fill_leaf(r, next_block);
                next_block += blocks_of(r);
            } else {
                child_at[i] = next_node++;
                const Children& below = *recorded++;
                boxes[i] = make_serial(below, child_at[i], next_node, next_block, recorded);
            }
        }
        return write_node(c, at, child_at, child_block, boxes);
    }

    Aabb write_node(const Children& c, std::uint32_t at,
                    const std::array<std::uint32_t, N>& child_at,
                    const std::array<std::uint32_t, N>& child_block,
                    const std::array<Aabb, N>& boxes) {
        Node node = Node::empty();
        Aabb box;
        for (int i = 0; i < c.count; ++i) {
            node.set_box(i, boxes[i]);
            box.extend(boxes[i]);
            if (is_leaf(c.range[i])) {
                node.child[i] = child_block[i];
                node.blocks[i] = static_cast<std::uint16_t>(blocks_of(c.range[i]));
            } else {
                node.child[i] = child_at[i];
            }
        }
        nodes_[at] = node;
        return box;
    }

    /// Writes the leaf over `r` into blocks from `first_block` on; returns its box.
    Aabb fill_leaf(Range r, std::uint32_t first_block) {
        BlockWriter writer(blocks_ + first_block);
        Aabb box;
        for (std::uint32_t k = r.begin; k < r.end; ++k) {
            if (k + kPrefetchAhead < count_) tris_.prefetch(id(k + kPrefetchAhead));
            const Triangle t = tris_[id(k)];
            box.extend(t.v0);
            box.extend(t.v1);
            box.extend(t.v2);
            writer.add(t, id(k));
        }
        writer.finish();
        return box;
    }

    const TriangleSource& tris_;
    const std::uint64_t* keys_;
    std::uint32_t* codes_;
    std::uint32_t count_;
    std::uint32_t leaf_prims_;
    Node* nodes_ = nullptr;
    BlockTarget blocks_;
};

}  // namespace

WideBvh build_wide_morton(const TriangleSource& tris, const BoxCenterRef* refs,
                          std::size_t count, const Aabb& center_box, std::uint32_t leaf_prims,
                          MortonKeys& keys, WideBvh&& recycled) {
    // The key's low half is the triangle's own index: refs are in increasing index order, so
    // equal codes keep that order.
    const std::uint64_t* sorted = morton_sorted_keys(
        refs, count, center_box, keys, [refs](std::size_t i) { return refs[i].id; });
    // The codes go into the sort's other buffer, no longer needed.
    std::uint64_t* const other = sorted == keys.keys.get() ? keys.other.get() : keys.keys.get();
    return WideMortonBuilder(tris, sorted, reinterpret_cast<std::uint32_t*>(other),
                             static_cast<std::uint32_t>(count), leaf_prims)
        .run(std::move(recycled));
}

}  // namespace dynrt::bvh::detail
