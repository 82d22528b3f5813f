#pragma once
// The structural checks behind `validate`, shared with the triangle BVH's validation, which
// must accept primitives missing from the tree (the degenerate triangles it skipped).

#include "dynrt/bvh/bvh.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dynrt::bvh::detail {

/// Checks every invariant `validate` documents, except that primitives may be absent from the
/// tree when `allow_missing` is true. On return `in_tree[id]` is 1 for each primitive id found
/// in a leaf (sized to prim_boxes.size()). Returns "" when valid, else the first violation.
std::string check_tree(const Bvh& bvh, std::span<const Aabb> prim_boxes,
                       std::uint32_t leaf_size_max, bool allow_missing,
                       std::vector<std::uint8_t>& in_tree);

}  // namespace dynrt::bvh::detail
