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

/// A node's children: consecutive ranges in Morton order, child i over [bound[i],
/// bound[i + 1]) (40 bytes, where N ranges took 68: the splits below the top levels are
/// recorded for every inner node, 1.4M of them for 20M triangles, at the build's peak).
struct Children {
    std::array<std::uint32_t, N + 1> bound;
    std::uint32_t count = 0;

    Range range(int i) const { return Range{bound[i], bound[i + 1]}; }
};
static_assert(sizeof(Children) == 4 * (N + 2));

class WideMortonBuilder {
public:
    /// `codes` and `ids`: the sorted keys' halves (build_wide_morton splits them).
    WideMortonBuilder(const TriangleSource& tris, const std::uint32_t* codes, const std::uint32_t* ids,
                      std::uint32_t count, std::uint32_t leaf_prims)
        : tris_(tris), codes_(codes), ids_(ids), count_(count), leaf_prims_(leaf_prims) {}

    WideBvh run(WideBvh&& recycled) {
        WideBvh wide = std::move(recycled);
        wide.nodes.clear();
        wide.quantized = false;  // the builder writes float nodes (quantize_nodes may follow)
        wide.quantized_nodes.clear();
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
            one.bound[0] = all.begin;
            one.bound[1] = all.end;
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
    std::uint32_t id(std::uint32_t k) const { return ids_[k]; }
    bool is_leaf(Range r) const { return r.size() <= leaf_prims_; }
    static std::uint32_t blocks_of(Range r) { return (r.size() + kBlockLanes - 1) / kBlockLanes; }

    /// Splits an inner node's range into its children: the largest child above leaf size is
    /// split (the first of equal ones), until there are N or none is left to split.
    Children split(Range r) const {
        Children c;
        c.bound[0] = r.begin;
        c.bound[1] = r.end;
        c.count = 1;
        while (c.count < N) {
            int largest = -1;
            std::uint32_t largest_size = leaf_prims_;
            for (int i = 0; i < int(c.count); ++i) {
                if (c.range(i).size() > largest_size) {
                    largest = i;
                    largest_size = c.range(i).size();
                }
            }
            if (largest < 0) break;
            const Range whole = c.range(largest);
            // The split point goes between the bounds of the child it splits.
            for (int i = int(c.count) + 1; i > largest + 1; --i) c.bound[i] = c.bound[i - 1];
            c.bound[largest + 1] = morton_split(codes_, whole.begin, whole.end);
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
        for (int i = 0; i < int(c.count); ++i) s += count(c.range(i), record);
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
        for (int i = 0; i < int(p.children.count); ++i) s += p.sizes[i];
        return s;
    }

    /// Plans the inner node over `r` at `depth` and its top-level descendants, the children
    /// as parallel tasks.
    std::unique_ptr<Planned> plan(Range r, std::uint32_t depth) const {
        auto node = std::make_unique<Planned>();
        node->children = split(r);
        tbb::parallel_for(0, int(node->children.count), [&](int i) {
            const Range child = node->children.range(i);
            if (is_leaf(child) || depth >= kParallelDepth) {
                node->sizes[i] = count(child, node->recorded[i]);
                // The growth's slack freed: the records are held until the subtree is made.
                node->recorded[i].shrink_to_fit();
                return;
            }
            node->below[i] = plan(child, depth + 1);
            node->sizes[i] = size_of(*node->below[i]);
        });
        return node;
    }

    /// Makes the planned node at `at` with its subtrees, the children as parallel tasks.
    /// Returns the node's box.
    Aabb make_planned(Planned& p, std::uint32_t at, std::uint32_t first_block) {
        const Children& c = p.children;
        std::array<std::uint32_t, N> child_at{}, child_block{};
        std::uint32_t next_node = at + 1, next_block = first_block;
        for (int i = 0; i < int(c.count); ++i) {
            child_at[i] = next_node;
            child_block[i] = next_block;
            next_node += p.sizes[i].nodes;
            next_block += p.sizes[i].blocks;
        }
        std::array<Aabb, N> boxes;
        tbb::parallel_for(0, int(c.count), [&](int i) {
            const Range r = c.range(i);
            if (is_leaf(r)) {
                boxes[i] = fill_leaf(r, child_block[i]);
            } else if (p.below[i]) {
                boxes[i] = make_planned(*p.below[i], child_at[i], child_block[i]);
            } else {
                const Children* next = p.recorded[i].data();
                std::uint32_t node = child_at[i] + 1, block = child_block[i];
                const Children& top = *next++;
                boxes[i] = make_serial(top, child_at[i], node, block, next);
                // Read for the last time: freed while the other subtrees are made.
                std::vector<Children>().swap(p.recorded[i]);
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
        for (int i = 0; i < int(c.count); ++i) {
            const Range r = c.range(i);
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
        for (int i = 0; i < int(c.count); ++i) {
            node.set_box(i, boxes[i]);
            box.extend(boxes[i]);
            if (is_leaf(c.range(i))) {
                node.child[i] = child_block[i];
                node.blocks[i] = static_cast<std::uint16_t>(blocks_of(c.range(i)));
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
    const std::uint32_t* codes_;
    const std::uint32_t* ids_;
    std::uint32_t count_;
    std::uint32_t leaf_prims_;
    Node* nodes_ = nullptr;
    BlockTarget blocks_;
};

}  // namespace

WideBvh build_wide_morton(const TriangleSource& tris, const std::uint64_t* sorted, MortonKeys& keys,
                          std::size_t count, std::uint32_t leaf_prims, bool free_sorted,
                          WideBvh&& recycled) {
    // The sorted keys split into the sort's other buffer, no longer needed: the codes in its
    // first half, half the bytes for the splits' searches to read, and the ids in its second.
    std::unique_ptr<std::uint64_t[]>& sorted_buffer = sorted == keys.keys.get() ? keys.keys : keys.other;
    std::unique_ptr<std::uint64_t[]>& other_buffer = sorted == keys.keys.get() ? keys.other : keys.keys;
    auto* const codes = reinterpret_cast<std::uint32_t*>(other_buffer.get());
    std::uint32_t* const ids = codes + count;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kMortonBlock),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k < r.end(); ++k) {
                              codes[k] = static_cast<std::uint32_t>(sorted[k] >> 32);
                              ids[k] = static_cast<std::uint32_t>(sorted[k]);
                          }
                      });
    if (free_sorted) {
        sorted_buffer.reset();
        keys.capacity = 0;
    }
    return WideMortonBuilder(tris, codes, ids, static_cast<std::uint32_t>(count), leaf_prims)
        .run(std::move(recycled));
}

}  // namespace dynrt::bvh::detail
