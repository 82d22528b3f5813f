#pragma once
// The Morton-order builders' core: the sort of primitives by the Morton codes of their centres
// and the split rule, shared by the binary builder (morton_builder.cpp: build_morton from the
// caller's boxes and centres, build_triangle_bvh without the wide tree) and the wide one
// (wide_morton_builder.cpp: build_triangle_bvh's fast rebuild).

#include "huge_pages.h"
#include "prim_ref.h"

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/morton_code.h"
#include "dynrt/bvh/radix_sort.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/wide_bvh.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

namespace dynrt::bvh::detail {

/// Bits of a Morton code: 10 per axis.
inline constexpr int kMortonCodeBits = 3 * MortonGrid::kBitsPerAxis;
/// Keys per task of the builders' parallel loops over primitives.
inline constexpr std::size_t kMortonBlock = 32 * 1024;

/// The first position of the right half of the Morton-sorted range [begin, end) (more than
/// one primitive) of `codes`: the first code with the range's highest differing bit set
/// (Karras 2012, section 4), or the middle when all codes are equal. Each split by a bit leaves
/// both halves with a longer common prefix, which bounds the depth.
inline std::uint32_t morton_split(const std::uint32_t* codes, std::uint32_t begin,
                                  std::uint32_t end) {
    const std::uint32_t first_code = codes[begin];
    const std::uint32_t last_code = codes[end - 1];
    if (first_code == last_code) return begin + (end - begin) / 2;
    const std::uint32_t bit = 1u << (31 - std::countl_zero(first_code ^ last_code));
    const std::uint32_t prefix_mask = ~(bit - 1) & ~bit;
    const std::uint32_t right_start = (first_code & prefix_mask) | bit;
    // Sorted, so the codes below right_start come first. A short range (most splits are near
    // the leaves) counts them without branches, which vectorises; a long one is searched.
    constexpr std::uint32_t kCountMax = 64;
    if (end - begin <= kCountMax) {
        std::uint32_t below = 0;
        for (std::uint32_t k = begin; k < end; ++k) below += codes[k] < right_start ? 1u : 0u;
        return begin + below;
    }
    std::uint32_t lo = begin + 1, hi = end - 1;  // the answer lies in [lo, hi]
    while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (codes[mid] >= right_start) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

/// The sort's keys and its second buffer for up to `capacity` primitives.
struct MortonKeys {
    std::unique_ptr<std::uint64_t[]> keys, other;
    std::size_t capacity = 0;

    void reserve(std::size_t count) {
        if (count <= capacity) return;
        keys = make_uninitialized_buffer<std::uint64_t>(count);
        other = make_uninitialized_buffer<std::uint64_t>(count);
        capacity = count;
    }
};

/// Sorts `storage.keys[0, count)`, each `code << 32 | low`, by their codes (the radix sort is
/// stable, so equal codes keep their order): returns the sorted keys, in `storage.keys` or
/// `storage.other`.
inline const std::uint64_t* sort_morton_keys(MortonKeys& storage, std::size_t count) {
    return radix_sort_bits(storage.keys.get(), storage.other.get(), count, 32, kMortonCodeBits);
}

/// The centre a Morton build codes for a triangle whose box is [lo, hi]: BoxCenterRef::center's
/// arithmetic, so a build from references and one from the triangles sort alike.
inline glm::vec3 box_center(const glm::vec3& lo, const glm::vec3& hi) { return (lo + hi) * 0.5f; }

/// Sorts refs[0, count) by the Morton codes of their centres in the grid over `center_box`
/// (which must bound them): returns the sorted keys, `code << 32 | low(i)` for ref i, in
/// `storage.keys` or `storage.other`. The sort is stable, so equal codes keep the refs' order
/// (whatever the thread timing), when low(i) increases with i.
template <class Ref, class Low>
const std::uint64_t* morton_sorted_keys(const Ref* refs, std::size_t count, const Aabb& center_box,
                                        MortonKeys& storage, const Low& low) {
    const MortonGrid grid(center_box);
    storage.reserve(count);
    std::uint64_t* const keys = storage.keys.get();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kMortonBlock),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i) {
                              const glm::vec3 c(refs[i].center(0), refs[i].center(1),
                                                refs[i].center(2));
                              keys[i] = std::uint64_t{grid.code(c)} << 32 | low(i);
                          }
                      });
    return sort_morton_keys(storage, count);
}

/// A BvhNode without default member initialisers, so millions of them can be allocated
/// without being written: the hierarchy is made in these (up to 2n - 1 of them, most never
/// used), then the used ones are copied into the tree.
struct RawBvhNode {
    float lo[3], hi[3];
    std::uint32_t first;
    std::uint32_t count;
};
static_assert(sizeof(RawBvhNode) == sizeof(BvhNode));

/// The binary builder's working arrays for up to `capacity` primitives: the sort's keys, the
/// refs in Morton order and the nodes. Kept from build to build where a tree is rebuilt every
/// frame, so the builds write memory that is already faulted in.
template <class Ref>
struct MortonBuffers {
    MortonKeys keys;
    std::unique_ptr<Ref[]> sorted;
    std::unique_ptr<RawBvhNode[]> nodes;  ///< room for 2 * capacity - 1
    std::size_t capacity = 0;

    void reserve(std::size_t count) {
        keys.reserve(count);
        if (count <= capacity) return;
        sorted = make_uninitialized_buffer<Ref>(count);
        nodes = make_uninitialized_buffer<RawBvhNode>(2 * count);
        capacity = count;
    }
};

/// Builds a tree over `refs[0, count)` in the Morton order of their centres. Unlike the binned
/// SAH core, the refs are not reordered: the result's prim_ids give the leaf order. Once they
/// are known, `alongside_output` (when set) runs concurrently with the making of the hierarchy,
/// with the prim_ids in leaf order (the caller's per-primitive output, such as triangles in
/// leaf order, overlaps with it). `root_center_box` must be the bounds of the refs' centres
/// (the root's box is the union the hierarchy computes); `count` >= 1 and < 2^31; `config` checked.
/// Storage of `recycled` (a tree no longer needed) and of `buffers` is reused where large
/// enough. Instantiated
/// for BoxCenterRef and ExplicitCenterRef.
template <class Ref>
Bvh build_morton_from_prim_refs(const Ref* refs, std::size_t count,
                                const Aabb& root_center_box, const BuildConfig& config,
                                const std::function<void(std::span<const std::uint32_t>)>&
                                    alongside_output,
                                MortonBuffers<Ref>& buffers, Bvh&& recycled = {});

/// Builds the wide tree over `count` triangles of `tris` directly in the Morton order of their
/// centres, with no binary tree: a node's children are made by splitting its range
/// (morton_split), the child of most triangles first, until it has N children or every child
/// is a leaf of at most `leaf_prims` triangles. `keys` holds the triangles' keys, sorted in
/// `sorted` (sort_morton_keys: `code << 32 | index into tris`, ascending index among equal
/// codes), and lends its other buffer to the build; with `free_sorted`, the buffer of the
/// sorted keys is freed once they are split into codes and ids, before the tree is made (8
/// bytes a triangle off the build's peak; `keys` then has to allocate it again). `count` >= 1
/// and < 2^31. The result does not depend on the thread count. Storage of `recycled` is
/// reused where large enough.
WideBvh build_wide_morton(const TriangleSource& tris, const std::uint64_t* sorted, MortonKeys& keys,
                          std::size_t count, std::uint32_t leaf_prims, bool free_sorted,
                          WideBvh&& recycled);

/// The Morton builders' storage kept with a TriangleBvh (TriangleBvh::morton_scratch): the
/// binary builder's buffers (the wide builder uses only their keys, made straight from the
/// triangles: 16 bytes a triangle held between builds) and the binary build's refs.
struct MortonScratch {
    MortonBuffers<BoxCenterRef> buffers;
    std::unique_ptr<BoxCenterRef[]> refs;
    std::size_t refs_capacity = 0;

    BoxCenterRef* reserve_refs(std::size_t count) {
        if (count > refs_capacity) {
            refs = make_uninitialized_buffer<BoxCenterRef>(count);
            refs_capacity = count;
        }
        return refs.get();
    }
};

}  // namespace dynrt::bvh::detail
