// The fast builder for objects rebuilt every frame: a linear BVH over the Morton order of the
// primitives' centres (Lauterbach, Garland, Sengupta, Luebke and Manocha 2009, "Fast BVH
// Construction on GPUs"), with the hierarchy split where the sorted codes' highest differing
// bit changes (Karras 2012, "Maximizing Parallelism in the Construction of BVHs, Octrees, and
// k-d Trees", section 4), made top-down here as Embree's Morton builder does on CPUs.
//
//   1. Codes: each centre quantised to 10 bits per axis inside the centres' bounds, the bits
//      interleaved into a 30-bit Morton code; the key is code << 32 | ref index.
//   2. A stable parallel LSD radix sort of the keys, three passes of 10 bits (per-block
//      histograms, one prefix sum, per-block scatter), so equal codes stay in ref order and
//      the result is the same whatever the thread timing.
//   3. The leaf order (prim_ids) is read off the keys; the caller's own leaf-order output
//      (the triangle gather) then runs beside the hierarchy.
//   4. The hierarchy, top-down in parallel: a range of sorted keys whose codes differ is split
//      at the first key with the highest differing bit set, one whose codes are all equal at
//      its middle; a range of at most kLeafPrims primitives becomes a leaf. Boxes are made on
//      the way back up (a leaf's from its primitives', an inner node's from its children's).
//
// No SAH is evaluated, which is why it is several times faster than the binned SAH builder
// and why its trees cost more to trace; the wide collapse (wide_collapse.cpp) then merges its
// small leaves and shallow subtrees by the SAH. Depth: at most 30 bit splits plus
// ceil(log2(n)) middle splits, below kMaxDepth for any n < 2^31.

#include "dynrt/bvh/morton_builder.h"
#include "dynrt/bvh/morton_code.h"
#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/radix_sort.h"

#include "binned_sah_core.h"
#include "huge_pages.h"
#include "morton_core.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <string>
#include <vector>

namespace dynrt::bvh::detail {
namespace {

/// A range of at most this many primitives (or BuildConfig::leaf_size_max, if smaller) is a
/// leaf: two triangle blocks. On sphere:1000000 at 1024x1024, leaves of up to 4 gave a tree of
/// lower SAH cost (56 against 61) that traced about 15% slower (3.4 triangles but 0.46 packet
/// node visits per ray, against 5.8 and 0.32: the packets pay more for a node than for a
/// block) and took 20% longer to build.
constexpr std::uint32_t kLeafPrims = 8;
/// Ranges above this many primitives are split into two tasks.
constexpr std::uint32_t kTaskMinPrims = 4 * 1024;

/// Makes the hierarchy over refs in Morton order (`refs[k]` has code `codes[k]`).
template <class Ref>
class MortonHierarchy {
public:
    MortonHierarchy(const Ref* refs, const std::uint32_t* codes, RawBvhNode* nodes,
                    std::uint32_t leaf_prims)
        : refs_(refs), codes_(codes), nodes_(nodes), leaf_prims_(leaf_prims) {}

    /// Makes node `index` over [begin, end); returns its box. Ranges above kTaskMinPrims split
    /// into two tasks, each claiming its child pair from the shared counter; a smaller range
    /// first counts its leaves, claims the nodes of its whole subtree at once and fills them
    /// serially (one atomic operation per subtree instead of one per node: with one per node,
    /// the counter's cache line moving between the cores took a sixth of the build).
    Aabb build(std::uint32_t index, std::uint32_t begin, std::uint32_t end) {
        const std::uint32_t n = end - begin;
        if (n <= kTaskMinPrims) {
            const std::uint32_t leaves = count_leaves(begin, end);
            std::uint32_t next = next_.fetch_add(2 * (leaves - 1), std::memory_order_relaxed);
            return build_serial(index, begin, end, next);
        }
        const std::uint32_t split = split_of(begin, end);
        const std::uint32_t first = next_.fetch_add(2, std::memory_order_relaxed);
        Aabb left, right;
        tbb::parallel_invoke([&] { left = build(first, begin, split); },
                             [&] { right = build(first + 1, split, end); });
        return set_inner(index, first, left, right);
    }

    /// Nodes used (the root's slot included).
    std::uint32_t used() const { return next_.load(); }

private:
    std::uint32_t count_leaves(std::uint32_t begin, std::uint32_t end) const {
        if (end - begin <= leaf_prims_) return 1;
        const std::uint32_t split = split_of(begin, end);
        return count_leaves(begin, split) + count_leaves(split, end);
    }

    /// Fills the subtree at `index` over [begin, end), taking child pairs from `next` on, in
    /// depth-first order (so every child comes after its parent).
    Aabb build_serial(std::uint32_t index, std::uint32_t begin, std::uint32_t end,
                      std::uint32_t& next) {
        if (end - begin <= leaf_prims_) {
            Aabb box;
            for (std::uint32_t k = begin; k < end; ++k) {
                box.extend(Aabb{refs_[k].lo, refs_[k].hi});
            }
            set_node(index, box, begin, end - begin);
            return box;
        }
        const std::uint32_t split = split_of(begin, end);
        const std::uint32_t first = next;
        next += 2;
        const Aabb left = build_serial(first, begin, split, next);
        const Aabb right = build_serial(first + 1, split, end, next);
        return set_inner(index, first, left, right);
    }

    Aabb set_inner(std::uint32_t index, std::uint32_t first, const Aabb& left, const Aabb& right) {
        Aabb box = left;
        box.extend(right);
        set_node(index, box, first, 0);
        return box;
    }

    void set_node(std::uint32_t index, const Aabb& box, std::uint32_t first,
                  std::uint32_t count) {
        RawBvhNode& node = nodes_[index];
        for (int axis = 0; axis < 3; ++axis) {
            node.lo[axis] = box.lo[axis];
            node.hi[axis] = box.hi[axis];
        }
        node.first = first;
        node.count = count;
    }

    /// The first position of the right child of [begin, end) (more than one primitive).
    std::uint32_t split_of(std::uint32_t begin, std::uint32_t end) const {
        return morton_split(codes_, begin, end);
    }

    const Ref* refs_;
    const std::uint32_t* codes_;
    RawBvhNode* nodes_;
    std::uint32_t leaf_prims_;
    std::atomic<std::uint32_t> next_{1};
};

}  // namespace

template <class Ref>
Bvh build_morton_from_prim_refs(const Ref* refs, std::size_t count,
                                const Aabb& root_center_box, const BuildConfig& config,
                                const std::function<void(std::span<const std::uint32_t>)>&
                                    alongside_output,
                                MortonBuffers<Ref>& buffers, Bvh&& recycled) {
    buffers.reserve(count);
    std::uint64_t* const keys = buffers.keys.keys.get();
    std::uint64_t* const scratch = buffers.keys.other.get();
    const std::uint64_t* sorted = morton_sorted_keys(refs, count, root_center_box, buffers.keys,
                                                     [](std::size_t i) { return i; });

    // The refs and codes in Morton order, so the hierarchy reads them sequentially (gathered
    // by the hierarchy itself, the refs' cache misses were the largest part of its time; a
    // flat loop keeps many of them in flight).
    Ref* const sorted_refs = buffers.sorted.get();
    // The codes go into the sort's other buffer, no longer needed.
    std::uint32_t* const codes = reinterpret_cast<std::uint32_t*>(keys == sorted ? scratch : keys);
    Bvh bvh = std::move(recycled);
    bvh.prim_ids.clear();
    resize_with_huge_pages(bvh.prim_ids, count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kMortonBlock),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i) {
                              constexpr std::size_t kAhead = 16;
                              if (i + kAhead < r.end()) {
                                  prefetch_line(
                                      refs + static_cast<std::uint32_t>(sorted[i + kAhead]));
                              }
                              const Ref& ref = refs[static_cast<std::uint32_t>(sorted[i])];
                              sorted_refs[i] = ref;
                              codes[i] = static_cast<std::uint32_t>(sorted[i] >> 32);
                              bvh.prim_ids[i] = ref.id;
                          }
                      });
    // At most 2n - 1 nodes, made in the scratch array; the tree gets the used ones.
    const std::uint32_t leaf_prims = std::min(kLeafPrims, config.leaf_size_max);
    RawBvhNode* const raw = buffers.nodes.get();
    MortonHierarchy<Ref> hierarchy(sorted_refs, codes, raw, leaf_prims);
    tbb::parallel_invoke(
        [&] {
            hierarchy.build(0, 0, static_cast<std::uint32_t>(count));
            const std::size_t used = hierarchy.used();
            bvh.nodes.clear();
            resize_with_huge_pages(bvh.nodes, used);
            static_assert(std::is_trivially_copyable_v<BvhNode>);
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, used, kMortonBlock),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  std::memcpy(static_cast<void*>(bvh.nodes.data() + r.begin()),
                                              raw + r.begin(), r.size() * sizeof(BvhNode));
                              });
        },
        [&] {
            if (alongside_output) alongside_output(bvh.prim_ids);
        });
    return bvh;
}

template Bvh build_morton_from_prim_refs<BoxCenterRef>(
    const BoxCenterRef*, std::size_t, const Aabb&, const BuildConfig&,
    const std::function<void(std::span<const std::uint32_t>)>&, MortonBuffers<BoxCenterRef>&,
    Bvh&&);
template Bvh build_morton_from_prim_refs<ExplicitCenterRef>(
    const ExplicitCenterRef*, std::size_t, const Aabb&, const BuildConfig&,
    const std::function<void(std::span<const std::uint32_t>)>&,
    MortonBuffers<ExplicitCenterRef>&, Bvh&&);

}  // namespace dynrt::bvh::detail

namespace dynrt::bvh {

Bvh build_morton(std::span<const Aabb> boxes, std::span<const glm::vec3> centers,
                 const BuildConfig& config) {
    detail::check_config(config);
    if (boxes.size() != centers.size()) {
        throw std::invalid_argument("build_morton: " + std::to_string(boxes.size()) +
                                    " boxes but " + std::to_string(centers.size()) + " centres");
    }
    const std::size_t count = boxes.size();
    if (count == 0) return Bvh{};
    if (count >= (std::size_t{1} << 31)) {
        throw std::length_error("build_morton: more than 2^31 - 1 primitives");
    }
    auto refs = detail::make_uninitialized_buffer<detail::ExplicitCenterRef>(count);
    detail::RefFiller filler(boxes, centers, refs.get());
    tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, count, 16 * 1024), filler);
    detail::MortonBuffers<detail::ExplicitCenterRef> buffers;
    return detail::build_morton_from_prim_refs(refs.get(), count, filler.center_box, config, {},
                                               buffers);
}

}  // namespace dynrt::bvh
