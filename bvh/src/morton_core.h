#pragma once
// The Morton-order builder's core (morton_builder.cpp), shared by build_morton (caller's boxes
// and centres) and build_triangle_bvh with BuildMethod::morton (boxes from triangles).

#include "huge_pages.h"
#include "prim_ref.h"

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/triangle.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace dynrt::bvh::detail {

/// The builder's working arrays for up to `capacity` primitives: the sort's keys and its
/// second buffer, and the refs in Morton order. Kept from build to build where a tree is
/// rebuilt every frame, so the builds write memory that is already faulted in.
/// A BvhNode without default member initialisers, so millions of them can be allocated
/// without being written: the hierarchy is made in these (up to 2n - 1 of them, most never
/// used), then the used ones are copied into the tree.
struct RawBvhNode {
    float lo[3], hi[3];
    std::uint32_t first;
    std::uint32_t count;
};
static_assert(sizeof(RawBvhNode) == sizeof(BvhNode));

template <class Ref>
struct MortonBuffers {
    std::unique_ptr<std::uint64_t[]> keys, other;
    std::unique_ptr<Ref[]> sorted;
    std::unique_ptr<RawBvhNode[]> nodes;  ///< room for 2 * capacity - 1
    std::size_t capacity = 0;

    void reserve(std::size_t count) {
        if (count <= capacity) return;
        keys = make_uninitialized_buffer<std::uint64_t>(count);
        other = make_uninitialized_buffer<std::uint64_t>(count);
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

/// The Morton builder's storage kept with a TriangleBvh (TriangleBvh::morton_scratch): its
/// buffers, build_triangle_bvh's own refs, and the binary tree and leaf-ordered triangles that
/// the wide tree is collapsed from.
struct MortonScratch {
    MortonBuffers<BoxCenterRef> buffers;
    Bvh binary;
    std::vector<Triangle> leaf_tris;
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
