// Parallel top-down BVH construction with the binned surface area heuristic
// (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies").
// Small nodes use fewer bins, as Embree's builders do (Wald et al. 2014, "Embree: A Kernel
// Framework for Efficient CPU Ray Tracing"): with a handful of primitives, initialising and
// sweeping 16 bins per axis costs more than binning the primitives themselves; nodes of at most
// four primitives skip bins altogether and try every split.
//
// Shape of a build: references (prim_ref.h) are binned along all three axes at once with
// four-lane vectors (float4.h), the best bin boundary is found by two sweeps, and the node's
// range is partitioned in place without branches. Nodes above kParallelTaskMin primitives split
// into oneTBB tasks (and above kParallelBinMin also bin in parallel); below it a subtree is
// built serially into a thread-local list. The result's primitive order and tree shape are
// deterministic; the order of nodes in the array is not (task scheduling decides it).

#include "binned_sah_core.h"
#include "binned_sah_phases.h"
#include "huge_pages.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dynrt::bvh {
namespace detail {
namespace {

/// Bin counts above this behave as this (keeps the per-node bin arrays small enough for the
/// stack and for oneTBB's reduction bodies).
constexpr std::uint32_t kMaxBins = 64;
/// A node with at least this many primitives is binned by several tasks.
constexpr std::size_t kParallelBinMin = 16 * 1024;
/// Block size of those tasks.
constexpr std::size_t kBinGrain = 4 * 1024;
/// Nodes up to this size try every split instead of binning (split_small).
constexpr std::size_t kExhaustiveMax = 4;
/// The two children of a node with at least this many primitives are built as separate tasks;
/// below it task overhead would exceed the work.
constexpr std::size_t kParallelTaskMin = 2 * 1024;

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Hands the allocator's free pages back to the system (every arena's, the workers' too).
void return_freed_pages() {
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
}

/// A box as two four-lane vectors (lane 3 unused), the unit the binning loop works in.
struct Box4 {
    Float4 lo, hi;

    static Box4 empty() { return {splat4(kInf), splat4(-kInf)}; }
    static Box4 from(const Aabb& b) {
        return {Float4{b.lo.x, b.lo.y, b.lo.z, 0.0f}, Float4{b.hi.x, b.hi.y, b.hi.z, 0.0f}};
    }
    void extend(Float4 l, Float4 h) {
        lo = min4(lo, l);
        hi = max4(hi, h);
    }
    void extend(const Box4& b) { extend(b.lo, b.hi); }
    void extend(Float4 p) { extend(p, p); }
    /// Only meaningful for a non-empty box.
    float half_area() const {
        const Float4 e = hi - lo;
        return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
};

/// Node storage written by the builder; trivial, so 2N-1 of them can be allocated without
/// touching the memory. Converted into BvhNode once the tree is complete.
struct RawNode {
    float lo[3], hi[3];
    std::uint32_t first, count;

    void set_box(const Box4& b) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = b.lo[a];
            hi[a] = b.hi[a];
        }
    }
};
static_assert(std::is_trivially_default_constructible_v<RawNode>);

/// Maps a centre to its bin along each axis. Robust by construction: an axis whose centre extent
/// is zero, denormal or overflows gets scale 0 (every primitive in bin 0, so the axis offers no
/// split), and indices are clamped in float before the conversion, so neither NaN nor infinity
/// ever reaches the float-to-int conversion.
struct BinMapping {
    Float4 lo;
    Float4 scale;  // lane 3 is 0
    Float4 last;   // bin count - 1, in every lane
    std::uint32_t count;

    BinMapping(const Box4& center_box, std::uint32_t bins)
        : lo(center_box.lo), scale(splat4(0.0f)), last(splat4(static_cast<float>(bins - 1))),
          count(bins) {
        for (int a = 0; a < 3; ++a) {
            const float extent = center_box.hi[a] - center_box.lo[a];
            const float s = static_cast<float>(bins) / extent;
            scale[a] = (extent > 0.0f && std::isfinite(s)) ? s : 0.0f;
        }
    }
    Int4 bin4(Float4 c) const {
        Float4 f = (c - lo) * scale;
        f = f > splat4(0.0f) ? f : splat4(0.0f);  // NaN lands in bin 0
        f = f < last ? f : last;
        return truncate4(f);
    }
};

/// Per axis a and bin b, at flat index a * kMaxBins + b: the bounds of the primitives' boxes
/// and their number. Flat, so one vector add turns the three bin indices into array indices.
struct Bins {
    Box4 boxes[3 * kMaxBins];
    std::uint32_t counts[3 * kMaxBins];

    Box4& box(int axis, std::uint32_t bin) { return boxes[axis * kMaxBins + bin]; }
    const Box4& box(int axis, std::uint32_t bin) const { return boxes[axis * kMaxBins + bin]; }
    std::uint32_t count(int axis, std::uint32_t bin) const { return counts[axis * kMaxBins + bin]; }

    void clear(std::uint32_t bins) {
        for (int a = 0; a < 3; ++a) {
            for (std::uint32_t b = 0; b < bins; ++b) {
                boxes[a * kMaxBins + b] = Box4::empty();
                counts[a * kMaxBins + b] = 0;
            }
        }
    }
    void merge(const Bins& other, std::uint32_t bins) {
        for (int a = 0; a < 3; ++a) {
            for (std::uint32_t b = 0; b < bins; ++b) {
                boxes[a * kMaxBins + b].extend(other.boxes[a * kMaxBins + b]);
                counts[a * kMaxBins + b] += other.counts[a * kMaxBins + b];
            }
        }
    }
};

template <class Ref>
inline void bin_one(Ref& r, const BinMapping& mapping, Bins& bins) {
    const Float4 lo = r.lo4();
    const Float4 hi = r.hi4();
    const Int4 b = mapping.bin4(r.center4());
    // The three bin indices, one byte each, for partition (bins < 256; lane 3 is always 0).
    r.bin_ids = pack_low_bytes(b);
    const Int4 flat = b + Int4{0, static_cast<std::int32_t>(kMaxBins),
                               static_cast<std::int32_t>(2 * kMaxBins), 0};
    const auto ix = static_cast<std::uint32_t>(flat[0]);
    const auto iy = static_cast<std::uint32_t>(flat[1]);
    const auto iz = static_cast<std::uint32_t>(flat[2]);
    bins.boxes[ix].extend(lo, hi);
    bins.boxes[iy].extend(lo, hi);
    bins.boxes[iz].extend(lo, hi);
    ++bins.counts[ix];
    ++bins.counts[iy];
    ++bins.counts[iz];
}

template <class Ref>
void bin_refs(Ref* refs, std::size_t begin, std::size_t end, const BinMapping& mapping,
              Bins& bins) {
    for (std::size_t i = begin; i < end; ++i) bin_one(refs[i], mapping, bins);
}

/// oneTBB reduction body binning a large node in blocks; joining is exact (min, max and integer
/// sums), so the result does not depend on how the range was split.
template <class Ref>
struct ParallelBinner {
    Ref* refs;
    const BinMapping* mapping;
    Bins bins;

    ParallelBinner(Ref* r, const BinMapping& m) : refs(r), mapping(&m) { bins.clear(m.count); }
    ParallelBinner(ParallelBinner& other, tbb::split) : refs(other.refs), mapping(other.mapping) {
        bins.clear(mapping->count);
    }
    void operator()(const tbb::blocked_range<std::size_t>& range) {
        bin_refs(refs, range.begin(), range.end(), *mapping, bins);
    }
    void join(const ParallelBinner& other) { bins.merge(other.bins, mapping->count); }
};

/// The best binned split of a node: left child = bins [0, bin] along `axis`.
struct Split {
    /// A(left) * n(left) + A(right) * n(right), half areas.
    float cost = kInf;
    int axis = -1;
    std::uint32_t bin = 0;
    Box4 left_box, right_box;

    bool found() const { return axis >= 0; }
};

Split best_split(const Bins& bins, const BinMapping& mapping) {
    const std::uint32_t n = mapping.count;
    Split best;
    float right_cost[kMaxBins];
    std::uint32_t right_count[kMaxBins];
    for (int a = 0; a < 3; ++a) {
        if (mapping.scale[a] == 0.0f) continue;  // every primitive is in bin 0
        // Sweep from the right: cost of the right side when it starts at bin b.
        Box4 acc = Box4::empty();
        std::uint32_t count = 0;
        for (std::uint32_t b = n - 1; b > 0; --b) {
            acc.extend(bins.box(a, b));
            count += bins.count(a, b);
            right_count[b] = count;
            right_cost[b] = count != 0 ? acc.half_area() * static_cast<float>(count) : 0.0f;
        }
        // Sweep from the left, pairing each left side with the right side after it. Splits
        // leaving one side empty are skipped: they would not make progress.
        acc = Box4::empty();
        count = 0;
        for (std::uint32_t b = 0; b + 1 < n; ++b) {
            acc.extend(bins.box(a, b));
            count += bins.count(a, b);
            if (count == 0 || right_count[b + 1] == 0) continue;
            const float cost = acc.half_area() * static_cast<float>(count) + right_cost[b + 1];
            // Strictly smaller: ties keep the lowest axis and bin, so the tree is deterministic.
            if (cost < best.cost) {
                best.cost = cost;
                best.axis = a;
                best.bin = b;
            }
        }
    }
    if (best.found()) {
        best.left_box = Box4::empty();
        best.right_box = Box4::empty();
        for (std::uint32_t b = 0; b < n; ++b) {
            (b <= best.bin ? best.left_box : best.right_box).extend(bins.box(best.axis, b));
        }
    }
    return best;
}

/// Kept out of line so the bin arrays live in this frame only, never in the recursion's.
template <class Ref>
[[gnu::noinline]] Split find_split(Ref* refs, std::size_t begin, std::size_t end,
                                   const BinMapping& mapping, bool allow_parallel) {
    if (allow_parallel && end - begin >= kParallelBinMin) {
        ParallelBinner<Ref> binner(refs, mapping);
        tbb::parallel_reduce(tbb::blocked_range<std::size_t>(begin, end, kBinGrain), binner);
        return best_split(binner.bins, mapping);
    }
    Bins bins;
    bins.clear(mapping.count);
    bin_refs(refs, begin, end, mapping, bins);
    return best_split(bins, mapping);
}

/// A range of references with its bounds.
struct ChildRange {
    std::size_t begin, end;
    Box4 box, center_box;

    std::size_t size() const { return end - begin; }
};

/// In-place branchless partition by the split's bin (Lomuto: every element is swapped with
/// the first right-side one, which advances only for left-side elements). Which side an
/// element falls on is a coin flip at upper levels, so a branchy (Hoare) loop would
/// mispredict about every other element. The side is read from the bin index binning stored
/// in the reference, so the split counts are reproduced exactly. Child boxes come from the
/// bins; child centre bounds are gathered on the way into a two-entry array indexed by the
/// side. Left elements keep their relative order.
template <int kAxis, class Ref>
[[gnu::always_inline]] inline void partition_along(Ref* refs, const ChildRange& range,
                                                   const Split& split, ChildRange& left,
                                                   ChildRange& right) {
    const std::uint32_t last_left_bin = split.bin;
    // [0] right side, [1] left side: indexing by the side keeps the loop branch-free.
    Box4 centers[2] = {Box4::empty(), Box4::empty()};
    Ref* a = refs + range.begin;
    const std::size_t n = range.size();
    std::size_t j = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t bin = (a[i].bin_ids >> (8 * kAxis)) & 0xffu;
        const std::size_t is_left = bin <= last_left_bin ? 1 : 0;
        const Ref t = a[i];
        a[i] = a[j];
        a[j] = t;
        j += is_left;
        centers[is_left].extend(t.center4());
    }
    const Box4& left_centers = centers[1];
    const Box4& right_centers = centers[0];
    const std::size_t mid = range.begin + j;
    left = ChildRange{range.begin, mid, split.left_box, left_centers};
    right = ChildRange{mid, range.end, split.right_box, right_centers};
}

/// Always inlined, like partition_along: the builder's split_node had both inline before they
/// were shared with partition_node (binned_sah_phases.h), and a second caller must not change
/// the builder's code.
template <class Ref>
[[gnu::always_inline]] inline void partition_refs(Ref* refs, const ChildRange& range,
                                                  const Split& split, ChildRange& left,
                                                  ChildRange& right) {
    switch (split.axis) {
        case 0: partition_along<0>(refs, range, split, left, right); break;
        case 1: partition_along<1>(refs, range, split, left, right); break;
        default: partition_along<2>(refs, range, split, left, right); break;
    }
}

/// Trees whose subtrees took at least this many bytes return the freed ones to the system; a
/// build over at least this many bytes of references the caller lets go of
/// (build_from_prim_refs' release_refs) returns them as it goes (Builder::release_below).
constexpr std::size_t kTrimAfterBytes = std::size_t{64} << 20;
/// The references are returned in runs of about this many bytes (a huge page; there are a few
/// hundred runs in a 20M-triangle build, one madvise each).
constexpr std::size_t kReleaseRunBytes = std::size_t{2} << 20;

template <class Ref>
class Builder {
public:
    Builder(Ref* refs, std::size_t count, const BuildConfig& config)
        : refs_(refs),
          top_capacity_(1 + 2 * static_cast<std::size_t>(kMaxDepth) *
                                ((count + kParallelTaskMin - 1) / kParallelTaskMin)),
          top_(std::make_unique_for_overwrite<RawNode[]>(top_capacity_)),
          subtrees_(top_capacity_),
          cost_ratio_(config.cost_ratio),
          leaf_size_max_(config.leaf_size_max),
          leaf_size_min_(std::min(config.leaf_size_min, config.leaf_size_max)),
          bin_count_max_(std::min(config.bin_count, kMaxBins)) {}

    Bvh build(std::size_t count, const Aabb& root_box, const Aabb& root_center_box,
              const std::function<void(std::span<const std::uint32_t>)>& alongside_output,
              const std::function<void()>& release_refs, Bvh&& recycled) {
        Bvh bvh = std::move(recycled);
        bvh.nodes.clear();
        bvh.prim_ids.clear();
        // The primitive ids are written as the subtrees are finished, each range once its
        // references are in their final order, so that a big build can hand the references'
        // pages back as it goes (32 bytes a primitive off its peak, when the caller lets go of
        // them): the references, the subtrees and the final node array are never all held.
        resize_with_huge_pages(bvh.prim_ids, count);
        prim_ids_ = bvh.prim_ids.data();
        release_refs_early_ = release_refs && count * sizeof(Ref) >= kTrimAfterBytes;
        build_node(0, ChildRange{0, count, Box4::from(root_box), Box4::from(root_center_box)}, 1);

        // Final layout: the top nodes at their slots, then each serial subtree's nodes (all but
        // its root, which sits in its slot) in slot order.
        const std::size_t top_used = top_used_.load();
        std::vector<std::uint32_t> offset(top_used, 0);
        std::size_t total = top_used;
        for (std::size_t slot = 0; slot < top_used; ++slot) {
            offset[slot] = static_cast<std::uint32_t>(total);
            if (!subtrees_[slot].empty()) total += subtrees_[slot].size() - 1;
        }
        // The caller's own output in leaf order (the triangle gather), then, the refs released,
        // the nodes.
        if (alongside_output) alongside_output(bvh.prim_ids);
        if (release_refs) release_refs();
        reserve_with_huge_pages(bvh.nodes, total);
        for (std::size_t slot = 0; slot < top_used; ++slot) {
            const std::vector<RawNode>& local = subtrees_[slot];
            bvh.nodes.push_back(local.empty() ? convert(top_[slot])
                                              : convert(relocate(local[0], offset[slot])));
        }
        // The subtrees came from the allocator's arenas in pieces too small to be mapped on
        // their own, so freeing them leaves their pages resident: for a big tree they are
        // handed back every kTrimAfterBytes as they are copied, else the subtrees and the final
        // array (each 32 bytes a node, about one node per triangle) would both be resident at
        // its end, the build's peak (18 bytes a triangle of it on soup:20000000). Small
        // trees, rebuilt every frame, skip the arenas' walks.
        const bool trim = total * sizeof(RawNode) >= kTrimAfterBytes;
        std::size_t freed_since_trim = 0;
        for (std::size_t slot = 0; slot < top_used; ++slot) {
            std::vector<RawNode>& local = subtrees_[slot];
            for (std::size_t k = 1; k < local.size(); ++k) {
                bvh.nodes.push_back(convert(relocate(local[k], offset[slot])));
            }
            freed_since_trim += local.capacity() * sizeof(RawNode);
            std::vector<RawNode>().swap(local);
            if (trim && (freed_since_trim >= kTrimAfterBytes || slot + 1 == top_used)) {
                return_freed_pages();
                freed_since_trim = 0;
            }
        }
        return bvh;
    }

private:
    /// Depth a median-split subtree over n primitives still needs below its root:
    /// ceil(log2(ceil(n / leaf_size_max))).
    std::uint32_t levels_needed(std::size_t n) const {
        const std::size_t leaves = (n + leaf_size_max_ - 1) / leaf_size_max_;
        return leaves <= 1 ? 0u : static_cast<std::uint32_t>(std::bit_width(leaves - 1));
    }

    std::uint32_t bin_count(std::size_t n) const {
        // Embree's rule: 4 + n/20 bins, up to the configured count.
        const std::size_t wanted = 4 + n / 20;
        return static_cast<std::uint32_t>(std::min<std::size_t>(wanted, bin_count_max_));
    }

    /// Decides one node: writes its box and, for a leaf, its range into `node` and returns
    /// false; for an inner node partitions the range into `left` and `right` and returns true
    /// (the caller then allocates the children and sets `node.first`).
    bool split_node(const ChildRange& range, std::uint32_t depth, bool allow_parallel,
                    RawNode& node, ChildRange& left, ChildRange& right) const {
        const std::size_t n = range.size();
        node.set_box(range.box);
        node.count = 0;

        // Depth guarantee: a median split halves the leaves still needed, so while
        // depth + levels_needed(n) < kMaxDepth any split keeps a median-only completion possible
        // for the children; at equality only median splits (or a leaf) may follow. This keeps
        // every leaf at depth <= kMaxDepth for any n < 2^32.
        const bool median_only = depth + levels_needed(n) >= kMaxDepth;
        if (n <= leaf_size_min_) {
            // Fewer nodes at the build's peak (BuildConfig::leaf_size_min).
            node.first = static_cast<std::uint32_t>(range.begin);
            node.count = static_cast<std::uint32_t>(n);
            return false;
        }
        const float area = range.box.half_area();
        const bool sah_usable = !median_only && area > 0.0f && std::isfinite(area);
        if (n <= kExhaustiveMax) return split_small(range, sah_usable, area, node, left, right);

        const BinMapping mapping(range.center_box, bin_count(n));
        Split split;
        if (sah_usable) split = find_split(refs_, range.begin, range.end, mapping, allow_parallel);
        if (n <= leaf_size_max_) {
            // SAH in units of one traversal step: leaf = ratio * n,
            // split = 1 + ratio * (A_l n_l + A_r n_r) / A. Without a usable split (zero area, no
            // separating bin, depth budget spent) a leaf is the answer.
            const float leaf_cost = cost_ratio_ * static_cast<float>(n);
            if (!split.found() || leaf_cost <= 1.0f + cost_ratio_ * split.cost / area) {
                node.first = static_cast<std::uint32_t>(range.begin);
                node.count = static_cast<std::uint32_t>(n);
                return false;
            }
        }
        if (split.found()) {
            partition(range, split, left, right);
        } else {
            median_split(range, left, right);
        }
        return true;
    }

    /// Nodes of two to four primitives, well over half of all nodes: try every way to split
    /// them in two (1, 3 or 7 ways) exactly instead of binning. Cheaper than clearing, filling
    /// and sweeping bins at this size, and never a worse split: binning only ever proposes
    /// some of these. Same cost model and leaf rule as the binned path.
    bool split_small(const ChildRange& range, bool sah_usable, float area, RawNode& node,
                     ChildRange& left, ChildRange& right) const {
        const std::size_t n = range.size();
        Ref* r = refs_ + range.begin;
        Box4 box[kExhaustiveMax];
        for (std::size_t i = 0; i < n; ++i) box[i] = Box4{r[i].lo4(), r[i].hi4()};
        // Bit i of a mask puts primitive i on the left; the last one always goes right, so
        // each split is tried once. Equal costs (identical primitives) prefer the balanced
        // split, then the lowest mask: deterministic and no deeper than needed.
        unsigned best_mask = 0;
        float best_cost = kInf;
        unsigned best_imbalance = 0;
        if (sah_usable) {
            for (unsigned mask = 1; mask < (1u << (n - 1)); ++mask) {
                Box4 l = Box4::empty(), rb = Box4::empty();
                unsigned left_count = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    if ((mask >> i) & 1u) {
                        l.extend(box[i]);
                        ++left_count;
                    } else {
                        rb.extend(box[i]);
                    }
                }
                const unsigned right_count = static_cast<unsigned>(n) - left_count;
                const float cost = l.half_area() * static_cast<float>(left_count) +
                                   rb.half_area() * static_cast<float>(right_count);
                const unsigned imbalance =
                    left_count > right_count ? left_count - right_count : right_count - left_count;
                if (cost < best_cost || (cost == best_cost && imbalance < best_imbalance)) {
                    best_cost = cost;
                    best_mask = mask;
                    best_imbalance = imbalance;
                }
            }
        }
        if (n <= leaf_size_max_) {
            const float leaf_cost = cost_ratio_ * static_cast<float>(n);
            if (best_mask == 0 || leaf_cost <= 1.0f + cost_ratio_ * best_cost / area) {
                node.first = static_cast<std::uint32_t>(range.begin);
                node.count = static_cast<std::uint32_t>(n);
                return false;
            }
        }
        if (best_mask == 0) {
            median_split(range, left, right);
            return true;
        }
        // Reorder: the left side first, each side in its original order.
        Ref copy[kExhaustiveMax];
        for (std::size_t i = 0; i < n; ++i) copy[i] = r[i];
        left = ChildRange{range.begin, range.begin, Box4::empty(), Box4::empty()};
        right = ChildRange{range.begin, range.end, Box4::empty(), Box4::empty()};
        std::size_t out = 0;
        for (int side = 1; side >= 0; --side) {
            ChildRange& child = side ? left : right;
            child.begin = range.begin + out;
            for (std::size_t i = 0; i < n; ++i) {
                if (((best_mask >> i) & 1u) != static_cast<unsigned>(side)) continue;
                r[out++] = copy[i];
                child.box.extend(box[i]);
                child.center_box.extend(copy[i].center4());
            }
            child.end = range.begin + out;
        }
        return true;
    }

    /// Builds the subtree of `range` into top slot `slot`; `depth` counts nodes from the root
    /// (1). Large subtrees split into two tasks; small ones go to build_serial.
    void build_node(std::uint32_t slot, const ChildRange& range, std::uint32_t depth) {
        if (range.size() < kParallelTaskMin) {
            build_serial(slot, range, depth);
            return;
        }
        RawNode node;
        ChildRange left, right;
        if (!split_node(range, depth, true, node, left, right)) {
            top_[slot] = node;
            write_prim_ids(range);
            return;
        }
        const std::uint32_t child = top_used_.fetch_add(2, std::memory_order_relaxed);
        node.first = child;
        top_[slot] = node;
        tbb::parallel_invoke([&] { build_node(child, left, depth + 1); },
                             [&] { build_node(child + 1, right, depth + 1); });
        release_below(range, left, right);
    }

    /// Writes the ids of a finished subtree's range (its references in their final order).
    void write_prim_ids(const ChildRange& range) const {
        for (std::size_t i = range.begin; i < range.end; ++i) prim_ids_[i] = refs_[i].id;
    }

    /// After both children of `range` are built: hands back the references of each child
    /// under kReleaseRunBytes, whose ids are written and which nothing reads again. A child
    /// at least that big has handed back its own children's; a range under it is handed back
    /// with the first ancestor's child that is, so every reference goes back once, in runs
    /// of kReleaseRunBytes / 2 or more (builds under kTrimAfterBytes keep theirs, for the
    /// caller to free).
    void release_below(const ChildRange& range, const ChildRange& left, const ChildRange& right) const {
        if (!release_refs_early_ || range.size() * sizeof(Ref) < kReleaseRunBytes) return;
        for (const ChildRange* child : {&left, &right}) {
            if (child->size() * sizeof(Ref) < kReleaseRunBytes) {
                release_pages(refs_ + child->begin, child->size() * sizeof(Ref));
            }
        }
    }

    /// Builds a small subtree on this thread, in depth-first order with local indices (root
    /// at 0), into a thread-local scratch list, then keeps an exact-size copy for its slot. No
    /// shared counter is touched per node; the final assembly copies each list once. Small
    /// exact-size lists come from (and return to) the allocator's free lists, so a rebuild
    /// touches no fresh memory for them, unlike one 2N-node buffer.
    void build_serial(std::uint32_t slot, const ChildRange& range, std::uint32_t depth) {
        // Safe to reuse per thread: nothing below calls into oneTBB, so this thread cannot start
        // another subtree before this one is copied out.
        thread_local std::vector<RawNode> local;
        local.resize(1);
        build_local(0, range, depth, local);
        subtrees_[slot].assign(local.begin(), local.end());
        write_prim_ids(range);
    }

    void build_local(std::uint32_t index, const ChildRange& range, std::uint32_t depth,
                     std::vector<RawNode>& local) const {
        RawNode node;
        ChildRange left, right;
        if (!split_node(range, depth, false, node, left, right)) {
            local[index] = node;
            return;
        }
        const std::uint32_t child = static_cast<std::uint32_t>(local.size());
        local.resize(local.size() + 2);
        node.first = child;
        local[index] = node;
        build_local(child, left, depth + 1, local);
        build_local(child + 1, right, depth + 1, local);
    }

    static BvhNode convert(const RawNode& n) {
        return BvhNode{Aabb{glm::vec3(n.lo[0], n.lo[1], n.lo[2]), glm::vec3(n.hi[0], n.hi[1], n.hi[2])},
                       n.first, n.count};
    }

    /// A serial subtree's node with its child index moved from local numbering (root 0, the
    /// rest from 1) to the final array, where local node k >= 1 sits at base + k - 1.
    static RawNode relocate(RawNode n, std::uint32_t base) {
        if (n.count == 0) n.first = base + n.first - 1;
        return n;
    }

    void partition(const ChildRange& range, const Split& split, ChildRange& left,
                   ChildRange& right) const {
        partition_refs(refs_, range, split, left, right);
    }

    /// Forced split when no binned split is usable: an object median along the widest centre
    /// axis, or, when all centres coincide, the middle of the range in its current order. Each
    /// child gets half the primitives (rounded), which is what the depth guarantee relies on.
    void median_split(const ChildRange& range, ChildRange& left, ChildRange& right) const {
        const std::size_t mid = range.begin + range.size() / 2;
        const Float4 extent = range.center_box.hi - range.center_box.lo;
        int axis = 0;
        if (extent[1] > extent[axis]) axis = 1;
        if (extent[2] > extent[axis]) axis = 2;
        if (extent[axis] > 0.0f) {
            std::nth_element(refs_ + range.begin, refs_ + mid, refs_ + range.end,
                             [axis](const Ref& a, const Ref& b) {
                                 return a.center(axis) < b.center(axis);
                             });
        }
        left = bounds_of(range.begin, mid);
        right = bounds_of(mid, range.end);
    }

    ChildRange bounds_of(std::size_t begin, std::size_t end) const {
        ChildRange r{begin, end, Box4::empty(), Box4::empty()};
        for (std::size_t i = begin; i < end; ++i) {
            r.box.extend(refs_[i].lo4(), refs_[i].hi4());
            r.center_box.extend(refs_[i].center4());
        }
        return r;
    }

    Ref* refs_;
    /// The top of the tree, down to the roots of the serial subtrees: the root in slot 0 and
    /// child pairs claimed with an atomic counter. Every node built by build_node has at least
    /// kParallelTaskMin primitives, and those of one depth are disjoint, so at most
    /// kMaxDepth * ceil(n / kParallelTaskMin) of them split: a bound on the slots needed.
    std::size_t top_capacity_;
    std::unique_ptr<RawNode[]> top_;
    std::atomic<std::uint32_t> top_used_{1};
    /// The serial subtree rooted in each top slot (empty for other slots).
    std::vector<std::vector<RawNode>> subtrees_;
    float cost_ratio_;
    std::uint32_t leaf_size_max_;
    std::uint32_t leaf_size_min_;
    /// bvh.prim_ids, written range by range (write_prim_ids).
    std::uint32_t* prim_ids_ = nullptr;
    /// Whether finished ranges of references are handed back during the build.
    bool release_refs_early_ = false;
    std::uint32_t bin_count_max_;
};

}  // namespace

void check_config(const BuildConfig& config) {
    if (!(config.cost_ratio > 0.0f) || !std::isfinite(config.cost_ratio)) {
        throw std::invalid_argument("BuildConfig: cost_ratio must be finite and > 0, got " +
                                    std::to_string(config.cost_ratio));
    }
    if (config.leaf_size_max < 1) {
        throw std::invalid_argument("BuildConfig: leaf_size_max must be >= 1");
    }
    if (config.leaf_size_min < 1) {
        throw std::invalid_argument("BuildConfig: leaf_size_min must be >= 1");
    }
    if (config.bin_count < 2) {
        throw std::invalid_argument("BuildConfig: bin_count must be >= 2, got " +
                                    std::to_string(config.bin_count));
    }
}

BinnedSplit bin_node(BoxCenterRef* refs, std::size_t count, const Aabb& center_box,
                     std::uint32_t bin_count, bool parallel) {
    const BinMapping mapping(Box4::from(center_box), std::clamp(bin_count, 2u, kMaxBins));
    const Split split = find_split(refs, 0, count, mapping, parallel);
    return BinnedSplit{split.axis, split.bin, split.cost};
}

std::size_t partition_node(BoxCenterRef* refs, std::size_t count, const BinnedSplit& split) {
    Split s;
    s.axis = split.axis;
    s.bin = split.bin;
    s.cost = split.cost;
    s.left_box = Box4::empty();
    s.right_box = Box4::empty();
    ChildRange left, right;
    partition_refs(refs, ChildRange{0, count, Box4::empty(), Box4::empty()}, s, left, right);
    return left.size();
}

template <class Ref>
Bvh build_from_prim_refs(Ref* refs, std::size_t count, const Aabb& root_box,
                         const Aabb& root_center_box, const BuildConfig& config,
                         const std::function<void(std::span<const std::uint32_t>)>& alongside_output,
                         Bvh&& recycled, const std::function<void()>& release_refs) {
    Builder<Ref> builder(refs, count, config);
    return builder.build(count, root_box, root_center_box, alongside_output, release_refs, std::move(recycled));
}

template Bvh build_from_prim_refs<BoxCenterRef>(BoxCenterRef*, std::size_t, const Aabb&,
                                                const Aabb&, const BuildConfig&,
                                                const std::function<void(std::span<const std::uint32_t>)>&,
                                                Bvh&&, const std::function<void()>&);
template Bvh build_from_prim_refs<ExplicitCenterRef>(ExplicitCenterRef*, std::size_t, const Aabb&,
                                                     const Aabb&, const BuildConfig&,
                                                     const std::function<void(std::span<const std::uint32_t>)>&,
                                                     Bvh&&, const std::function<void()>&);

}  // namespace detail

const char* build_method_name(BuildMethod method) {
    return method == BuildMethod::morton ? "morton" : "sah";
}

Bvh build_binned_sah(std::span<const Aabb> boxes, std::span<const glm::vec3> centers,
                     const BuildConfig& config) {
    detail::check_config(config);
    if (boxes.size() != centers.size()) {
        throw std::invalid_argument("build_binned_sah: " + std::to_string(boxes.size()) +
                                    " boxes but " + std::to_string(centers.size()) + " centres");
    }
    const std::size_t count = boxes.size();
    if (count == 0) return Bvh{};
    if (count >= (std::size_t{1} << 31)) {
        throw std::length_error("build_binned_sah: more than 2^31 - 1 primitives");
    }
    auto refs = detail::make_uninitialized_buffer<detail::ExplicitCenterRef>(count);
    detail::RefFiller filler(boxes, centers, refs.get());
    tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, count, 16 * 1024), filler);
    return detail::build_from_prim_refs(refs.get(), count, filler.box, filler.center_box, config, {});
}

}  // namespace dynrt::bvh
