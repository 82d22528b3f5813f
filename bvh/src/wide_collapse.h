#pragma once
// The collapse as build_triangle_bvh runs it: over a binary tree that is its own to free.

#include "dynrt/bvh/bvh.h"
#include "dynrt/bvh/triangle_source.h"
#include "dynrt/bvh/wide_bvh.h"

namespace dynrt::bvh {

/// collapse_to_wide_by_id (the same tree, byte for byte) that frees `bvh`'s nodes, and its own
/// records of the dynamic program, once the wide nodes are made and before the triangle
/// blocks are allocated: the binary tree (32 bytes a node, about one node per triangle) and the
/// blocks (about 50 bytes a triangle) are then never held at once. `bvh` is left empty. A tree
/// whose subtrees do not each cover one run of leaf positions (no builder of ours makes one)
/// is collapsed as collapse_to_wide_by_id does, blocks and nodes together.
template <int N>
WideBvhOf<N> collapse_to_wide_consuming(Bvh&& bvh, const TriangleSource& tris, const WideCosts& costs,
                                        WideBvhOf<N>&& recycled);

}  // namespace dynrt::bvh
