// Collapsing the binary binned-SAH tree into an N-wide one by the dynamic program of Ylitie,
// Karras and Laine 2017, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide
// BVHs" (section 4.1). For a binary node n and i = 1..N slots, C(n, i) is the least SAH cost of
// n's subtree when it may occupy up to i child slots of a wide node:
//
//   C(n, 1) = min(C_leaf(n), C_node(n))
//   C(n, i) = min(C_dist(n, i), C(n, i - 1))                        for i >= 2
//   C_dist(n, j) = min over 0 < k < j of C(left, k) + C(right, j - k)
//   C_node(n) = A(n) c_node + C_dist(n, N)
//   C_leaf(n) = A(n) ceil(p(n) / 4) c_block    if p(n) <= leaf_prims_max, else infinite
//
// (A the half area, p the triangle count). A binary leaf is always one slot, a leaf, whatever
// its size. The program runs bottom-up in parallel and records its choices, and for every
// binary node the size of the wide subtree it would head; the wide tree is then read off the
// choices top-down, in depth-first order, each subtree written into the range its size
// reserves, so the top levels' subtrees are emitted (and their blocks filled) in parallel and
// the layout still does not depend on thread timing. Both arrays are allocated once at their
// final size.

#include "wide_collapse.h"

#include "block_writer.h"
#include "node_target.h"
#include "huge_pages.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace dynrt::bvh {
namespace {

/// Subtrees above this depth of the binary tree are costed as parallel tasks.
constexpr std::uint32_t kParallelDepth = 10;
/// Wide levels whose inner children are emitted as parallel tasks (8^3 or 4^4 subtrees).
template <int N>
constexpr std::uint32_t kParallelEmitDepth = N == 8 ? 3 : 4;

std::uint32_t blocks_for(std::uint32_t prims) {
    return (prims + kBlockLanes - 1) / kBlockLanes;
}

/// choices[0] of a binary node: its subtree fills one slot as a leaf or as a wide node.
constexpr std::uint8_t kLeaf = 0;
constexpr std::uint8_t kNode = 1;

/// What a subtree becomes in the wide tree: its wide nodes and triangle blocks.
struct WideSize {
    std::uint32_t nodes = 0;
    std::uint32_t blocks = 0;

    WideSize operator+(const WideSize& o) const { return {nodes + o.nodes, blocks + o.blocks}; }
};

template <int N>
class Collapser {
public:
    /// `by_id`: `tris` is in the caller's order (leaf position k's triangle is
    /// tris[prim_ids[k]]), else in leaf order (tris[k]). `consumed`, when given, is `bvh`
    /// itself, whose nodes the collapse may free once the wide nodes are made.
    Collapser(const Bvh& bvh, TriangleSource tris, bool by_id, const WideCosts& costs, Bvh* consumed = nullptr)
        : bvh_(bvh), consumed_(consumed), tris_(tris), by_id_(by_id), costs_(costs),
          choice_(std::make_unique_for_overwrite<Choices[]>(bvh.nodes.size())),
          size_as_node_(std::make_unique_for_overwrite<WideSize[]>(bvh.nodes.size())) {}

    WideBvhOf<N> run(WideBvhOf<N>&& recycled) {
        WideBvhOf<N> wide = std::move(recycled);
        // Quantised nodes when the tree handed in says so (as it says compact leaves) and the
        // root box can be: each node is then quantised as it is written.
        const bool quantize =
            wide.quantized && !bvh_.nodes.empty() && can_quantize(bvh_.nodes[0].box);
        wide.nodes.clear();
        wide.quantized = false;
        wide.quantized_nodes.clear();
        wide.blocks.clear();
        wide.prim_blocks.clear();
        wide.root_box = Aabb{};
        wide.triangle_count = 0;
        if (bvh_.nodes.empty()) return wide;
        const Result root = cost(0, 1);
        // The root is a wide node: over one leaf when the whole tree is best as one leaf (or
        // is a single binary leaf), else over the best distribution of its children.
        const bool root_leaf = bvh_.nodes[0].is_leaf() || choice_[0][0] == kLeaf;
        const WideSize size = root_leaf ? WideSize{1, root.size[0].blocks} : size_as_node_[0];
        // With the binary tree ours to free and every subtree over one run of leaf positions,
        // the blocks are written after the binary nodes and the program's records are freed:
        // those and the blocks (50 bytes a triangle) are then never held at once.
        defer_blocks_ = consumed_ != nullptr && contiguous_.load(std::memory_order_relaxed);
        nodes_ = detail::allocate_nodes(wide, size.nodes, quantize);
        if (defer_blocks_) {
            leaf_ranges_ = std::make_unique_for_overwrite<LeafRange[]>(size.blocks);
        } else {
            blocks_ = detail::allocate_blocks(wide, size.blocks);
        }
        if (root_leaf) {
            WideNode<N> root = WideNode<N>::empty();
            std::uint32_t next_node = 1, next_block = 0;
            fill_slot(root, 0, 0, next_node, next_block, nullptr);
            nodes_.store(0, root);
        } else {
            emit_node(0, 0, 0, 1);
        }
        wide.root_box = bvh_.nodes[0].box;
        wide.triangle_count = bvh_.prim_ids.size();
        if (defer_blocks_) {
            choice_.reset();
            size_as_node_.reset();
            std::vector<BvhNode>().swap(consumed_->nodes);
            blocks_ = detail::allocate_blocks(wide, size.blocks);
            fill_deferred_leaves(wide.node_count());
            leaf_ranges_.reset();
        }
        return wide;
    }

private:
    using Costs = std::array<float, N>;
    /// choices[0]: kLeaf or kNode, how the subtree fills one slot; choices[i - 1] for
    /// 2 <= i <= N: the k of the best split of i slots between the children, or 0 when fewer
    /// slots, C(n, i - 1), were no worse; choices[N]: the k of C_dist(n, N), the split of a
    /// wide node's own N slots when the subtree becomes one.
    using Choices = std::array<std::uint8_t, N + 1>;

    /// C(n, 1..N) of a subtree, what each choice makes of it in the wide tree, and p(n).
    struct Result {
        Costs cost;
        std::array<WideSize, N> size;
        std::uint32_t prims = 0;
        /// The leaf positions the subtree's leaves cover, when they are one run [first, end).
        std::uint32_t first = 0, end = 0;
    };

    /// Runs the dynamic program over the subtree at `index`, recording the choices and, for
    /// every inner node, the size of the wide subtree it gives as a wide node (so that the
    /// emission knows where each subtree goes before it is made, and can run in parallel).
    Result cost(std::uint32_t index, std::uint32_t depth) {
        const BvhNode& node = bvh_.nodes[index];
        const float area = node.box.half_area();
        Result r;
        Choices& choice = choice_[index];
        if (node.is_leaf()) {
            if (node.count > kWideLeafSizeMax) {
                throw std::length_error("collapse_to_wide: a leaf of " +
                                        std::to_string(node.count) +
                                        " triangles needs more than 65535 blocks");
            }
            r.cost.fill(area * static_cast<float>(blocks_for(node.count)) * costs_.block);
            r.size.fill(WideSize{0, blocks_for(node.count)});
            r.prims = node.count;
            r.first = node.first;
            r.end = node.first + node.count;
            choice.fill(0);
            choice[0] = kLeaf;
            return r;
        }
        Result left, right;
        if (depth < kParallelDepth) {
            tbb::parallel_invoke([&] { left = cost(node.first, depth + 1); },
                                 [&] { right = cost(node.first + 1, depth + 1); });
        } else {
            left = cost(node.first, depth + 1);
            right = cost(node.first + 1, depth + 1);
        }
        r.prims = left.prims + right.prims;
        r.first = left.first;
        r.end = right.end;
        if (left.end != right.first) contiguous_.store(false, std::memory_order_relaxed);

        // C_dist(n, j) for j = 2..N, each with its best k.
        Costs dist;
        std::array<std::uint8_t, N> dist_k{};
        for (int j = 2; j <= N; ++j) {
            float best = std::numeric_limits<float>::infinity();
            int best_k = 1;
            for (int k = 1; k < j; ++k) {
                const float sum = left.cost[k - 1] + right.cost[j - k - 1];
                if (sum < best) {
                    best = sum;
                    best_k = k;
                }
            }
            dist[j - 1] = best;
            dist_k[j - 1] = static_cast<std::uint8_t>(best_k);
        }
        auto dist_size = [&](int j, int k) { return left.size[k - 1] + right.size[j - k - 1]; };
        choice[N] = dist_k[N - 1];
        const WideSize as_node_size = WideSize{1, 0} + dist_size(N, dist_k[N - 1]);
        size_as_node_[index] = as_node_size;
        const float as_node = area * costs_.node + dist[N - 1];
        const float as_leaf = r.prims <= costs_.leaf_prims_max
                                  ? area * static_cast<float>(blocks_for(r.prims)) * costs_.block
                                  : std::numeric_limits<float>::infinity();
        choice[0] = as_leaf <= as_node ? kLeaf : kNode;
        r.cost[0] = std::min(as_leaf, as_node);
        r.size[0] = choice[0] == kLeaf ? WideSize{0, blocks_for(r.prims)} : as_node_size;
        for (int i = 2; i <= N; ++i) {
            if (dist[i - 1] < r.cost[i - 2]) {
                r.cost[i - 1] = dist[i - 1];
                r.size[i - 1] = dist_size(i, dist_k[i - 1]);
                choice[i - 1] = dist_k[i - 1];
            } else {
                r.cost[i - 1] = r.cost[i - 2];
                r.size[i - 1] = r.size[i - 2];
                choice[i - 1] = 0;
            }
        }
        return r;
    }

    /// The binary nodes that fill the slots of a wide node made from `index`, in order.
    void slots_of(std::uint32_t index, int slots, std::array<std::uint32_t, N>& out, int& used) const {
        const BvhNode& node = bvh_.nodes[index];
        if (slots == 1 || node.is_leaf()) {
            out[used++] = index;
            return;
        }
        const std::uint8_t k = choice_[index][slots - 1];
        if (k == 0) {
            slots_of(index, slots - 1, out, used);
            return;
        }
        slots_of(node.first, k, out, used);
        slots_of(node.first + 1, slots - k, out, used);
    }

    /// Writes the wide node made from the binary inner node `index` at `at`, its leaves'
    /// blocks from `first_block` on and its inner children's subtrees right after it, in slot
    /// order (depth-first order, each subtree in the range its size reserves); the subtrees
    /// of the top levels as parallel tasks.
    void emit_node(std::uint32_t index, std::uint32_t at, std::uint32_t first_block,
                   std::uint32_t depth) {
        WideNode<N> wide_node = WideNode<N>::empty();
        // The node's children share its N slots by the best split of C_dist(n, N).
        const BvhNode& node = bvh_.nodes[index];
        const int k = choice_[index][N];
        std::array<std::uint32_t, N> slots;
        int used = 0;
        slots_of(node.first, k, slots, used);
        slots_of(node.first + 1, N - k, slots, used);
        std::uint32_t next_node = at + 1;
        std::uint32_t next_block = first_block;
        struct Job {
            std::uint32_t binary, at, first_block;
        };
        std::array<Job, N> jobs;
        int job_count = 0;
        for (int i = 0; i < used; ++i) {
            Job job;
            if (fill_slot(wide_node, i, slots[i], next_node, next_block, &job.at)) {
                job.binary = slots[i];
                job.first_block = next_block - size_as_node_[slots[i]].blocks;
                jobs[job_count++] = job;
            }
        }
        nodes_.store(at, wide_node);
        auto run = [&](int j) { emit_node(jobs[j].binary, jobs[j].at, jobs[j].first_block, depth + 1); };
        if (depth < kParallelEmitDepth<N> && job_count > 1) {
            tbb::parallel_for(0, job_count, run);
        } else {
            for (int j = 0; j < job_count; ++j) run(j);
        }
    }

    /// Sets slot `slot` of `parent` to the binary subtree `binary`: a leaf, whose blocks are
    /// filled here, or an inner node, whose place (returned in *child_at, and then true) is
    /// reserved for the caller to emit.
    bool fill_slot(WideNode<N>& parent, int slot, std::uint32_t binary, std::uint32_t& next_node,
                   std::uint32_t& next_block, std::uint32_t* child_at) {
        const BvhNode& node = bvh_.nodes[binary];
        parent.set_box(slot, node.box);
        if (node.is_leaf() || choice_[binary][0] == kLeaf) {
            std::uint32_t blocks;
            if (defer_blocks_) {
                const LeafRange range = range_of(binary);
                leaf_ranges_[next_block] = range;
                blocks = blocks_for(range.prims);
            } else {
                blocks = fill_leaf(blocks_ + next_block, binary);
            }
            parent.child[slot] = next_block;
            parent.blocks[slot] = static_cast<std::uint16_t>(blocks);
            next_block += blocks;
            return false;
        }
        const WideSize size = size_as_node_[binary];
        parent.child[slot] = next_node;
        parent.blocks[slot] = 0;
        *child_at = next_node;
        next_node += size.nodes;
        next_block += size.blocks;
        return true;
    }

    /// Copies the triangles of the binary subtree at `index` into consecutive blocks; returns
    /// how many it filled.
    std::uint32_t fill_leaf(detail::BlockTarget blocks, std::uint32_t index) const {
        return write_leaf(blocks, [&](auto&& visit) { visit_leaves(index, visit); });
    }

    /// A wide leaf's run of leaf positions, for its blocks written later.
    struct LeafRange {
        std::uint32_t first, prims;
    };

    /// The run of leaf positions under the binary node `index` (from its leftmost leaf to its
    /// rightmost; every subtree's is one run, contiguous_).
    LeafRange range_of(std::uint32_t index) const {
        std::uint32_t lo = index, hi = index;
        while (!bvh_.nodes[lo].is_leaf()) lo = bvh_.nodes[lo].first;
        while (!bvh_.nodes[hi].is_leaf()) hi = bvh_.nodes[hi].first + 1;
        const BvhNode& first = bvh_.nodes[lo];
        const BvhNode& last = bvh_.nodes[hi];
        return LeafRange{first.first, last.first + last.count - first.first};
    }

    /// With defer_blocks_: every leaf slot's blocks, from the run recorded at its first block,
    /// in the order fill_leaf would have written them (a run's positions ascending).
    void fill_deferred_leaves(std::size_t node_count) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, node_count, 256),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t n = r.begin(); n < r.end(); ++n) {
                                  for (int i = 0; i < N; ++i) {
                                      if (nodes_.blocks(n, i) == 0) continue;  // not a leaf
                                      const std::uint32_t first = nodes_.child(n, i);
                                      const LeafRange range = leaf_ranges_[first];
                                      write_leaf(blocks_ + first, [&](auto&& visit) {
                                          for (std::uint32_t k = range.first; k < range.first + range.prims; ++k) visit(k);
                                      });
                                  }
                              }
                          });
    }

    /// Writes the triangles at the leaf positions `for_each_position` visits into consecutive
    /// blocks; returns how many it filled.
    template <class ForEachPosition>
    std::uint32_t write_leaf(detail::BlockTarget blocks, ForEachPosition&& for_each_position) const {
        detail::BlockWriter writer(blocks);
        if (!blocks.wants_triangles()) {
            for_each_position([&](std::uint32_t k) { writer.add_prim(bvh_.prim_ids[k]); });
            return writer.finish();
        }
        const auto at = [&](std::uint32_t k) { return by_id_ ? bvh_.prim_ids[k] : k; };
        if (tris_.indexed()) {
            // The leaf's triangles lie anywhere in the caller's order, and an indexed mesh's
            // corners are two dependent reads (the index triple, then the vertices): every
            // one is asked for before any is read, so that the misses overlap. (Measured no
            // help for plain triangles, one read each: bm_build, soup_1M.)
            for_each_position([&](std::uint32_t k) { tris_.prefetch(at(k)); });
            for_each_position([&](std::uint32_t k) { tris_.prefetch_corners(at(k)); });
        }
        for_each_position([&](std::uint32_t k) { writer.add(tris_[at(k)], bvh_.prim_ids[k]); });
        return writer.finish();
    }

    template <class Visit>
    void visit_leaves(std::uint32_t index, Visit&& visit) const {
        const BvhNode& node = bvh_.nodes[index];
        if (node.is_leaf()) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) visit(k);
            return;
        }
        visit_leaves(node.first, visit);
        visit_leaves(node.first + 1, visit);
    }

    const Bvh& bvh_;
    Bvh* consumed_;
    TriangleSource tris_;
    bool by_id_;
    WideCosts costs_;
    std::unique_ptr<Choices[]> choice_;
    /// Per binary inner node, the wide subtree it gives as a wide node.
    std::unique_ptr<WideSize[]> size_as_node_;
    detail::NodeTarget<N> nodes_;
    detail::BlockTarget blocks_;
    /// Whether every binary subtree's leaves are one run of leaf positions (the builders'
    /// trees are: they partition their ranges in place), found by the program.
    std::atomic<bool> contiguous_{true};
    bool defer_blocks_ = false;
    /// With defer_blocks_, per block: at a leaf's first block, the leaf's run.
    std::unique_ptr<LeafRange[]> leaf_ranges_;
};

}  // namespace

template <int N>
WideBvhOf<N> collapse_to_wide(const Bvh& bvh, std::span<const Triangle> leaf_tris,
                              const WideCosts& costs, WideBvhOf<N>&& recycled) {
    if (leaf_tris.size() != bvh.prim_ids.size()) {
        throw std::invalid_argument("collapse_to_wide: " + std::to_string(leaf_tris.size()) +
                                    " triangles for " + std::to_string(bvh.prim_ids.size()) +
                                    " primitive ids");
    }
    return Collapser<N>(bvh, leaf_tris, false, costs).run(std::move(recycled));
}

template <int N>
WideBvhOf<N> collapse_to_wide_by_id(const Bvh& bvh, const TriangleSource& tris, const WideCosts& costs,
                                    WideBvhOf<N>&& recycled) {
    for (const std::uint32_t id : bvh.prim_ids) {
        if (id >= tris.size()) {
            throw std::invalid_argument("collapse_to_wide_by_id: primitive id " + std::to_string(id) + " past " +
                                        std::to_string(tris.size()) + " triangles");
        }
    }
    return Collapser<N>(bvh, tris, true, costs).run(std::move(recycled));
}

template <int N>
WideBvhOf<N> collapse_to_wide_consuming(Bvh&& bvh, const TriangleSource& tris, const WideCosts& costs,
                                        WideBvhOf<N>&& recycled) {
    WideBvhOf<N> wide = Collapser<N>(bvh, tris, true, costs, &bvh).run(std::move(recycled));
    bvh = Bvh{};
    return wide;
}

template WideBvhOf<kWideWidth> collapse_to_wide_consuming<kWideWidth>(Bvh&&, const TriangleSource&, const WideCosts&,
                                                                      WideBvhOf<kWideWidth>&&);
template WideBvhOf<4> collapse_to_wide<4>(const Bvh&, std::span<const Triangle>, const WideCosts&,
                                          WideBvhOf<4>&&);
template WideBvhOf<8> collapse_to_wide<8>(const Bvh&, std::span<const Triangle>, const WideCosts&,
                                          WideBvhOf<8>&&);
template WideBvhOf<4> collapse_to_wide_by_id<4>(const Bvh&, const TriangleSource&, const WideCosts&,
                                                WideBvhOf<4>&&);
template WideBvhOf<8> collapse_to_wide_by_id<8>(const Bvh&, const TriangleSource&, const WideCosts&,
                                                WideBvhOf<8>&&);

}  // namespace dynrt::bvh
