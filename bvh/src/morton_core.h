#pragma once
// The Morton-order builder's core (morton_builder.cpp), shared by build_morton (caller's boxes
// and centres) and build_triangle_bvh with BuildMethod::morton (boxes from triangles).

#include "prim_ref.h"

#include "dynrt/bvh/binned_sah_builder.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

namespace dynrt::bvh::detail {

/// Builds a tree over `refs[0, count)` in the Morton order of their centres. Unlike the binned
/// SAH core, the refs are not reordered: the result's prim_ids give the leaf order. Once they
/// are known, `alongside_output` (when set) runs concurrently with the making of the hierarchy,
/// with the prim_ids in leaf order (the caller's per-primitive output, such as triangles in
/// leaf order, overlaps with it). `root_box` must be the union of the refs' boxes and
/// `root_center_box` the bounds of their centres; `count` >= 1 and < 2^31; `config` checked.
/// Storage of `recycled` (a tree no longer needed) is reused where large enough. Instantiated
/// for BoxCenterRef and ExplicitCenterRef.
template <class Ref>
Bvh build_morton_from_prim_refs(const Ref* refs, std::size_t count, const Aabb& root_box,
                                const Aabb& root_center_box, const BuildConfig& config,
                                const std::function<void(std::span<const std::uint32_t>)>&
                                    alongside_output,
                                Bvh&& recycled = {});

}  // namespace dynrt::bvh::detail
