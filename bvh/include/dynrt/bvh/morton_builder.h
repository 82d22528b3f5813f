#pragma once
// The fast builder for objects rebuilt every frame: a linear BVH over the Morton order of the
// primitives' centres (Lauterbach et al. 2009; Karras 2012), parallel and several times faster
// than build_binned_sah, with trees that cost somewhat more to trace. build_triangle_bvh uses
// it when BuildConfig::method is BuildMethod::morton; the algorithm is described in
// bvh/src/morton_builder.cpp.

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/bvh.h"

#include <glm/vec3.hpp>

#include <span>

namespace dynrt::bvh {

/// Builds a tree over `boxes.size()` primitives ordered along the Morton curve through
/// `centers` (each inside its box). Same contract as build_binned_sah: boxes non-empty and
/// finite, spans borrowed for the call, the result satisfies `validate` with leaf_size_max
/// min(8, config.leaf_size_max), its depth is below kMaxDepth, and its prim_ids and tree shape do
/// not depend on thread timing (the order of the nodes in the array may). Ignores
/// config.method, cost_ratio and bin_count. Throws as build_binned_sah does.
Bvh build_morton(std::span<const Aabb> boxes, std::span<const glm::vec3> centers,
                 const BuildConfig& config);

}  // namespace dynrt::bvh
