#pragma once
// A BVH paired with its triangles in leaf order: the traceable acceleration structure of one
// mesh, with closest-hit and any-hit single-ray traversal.

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_source.h"
#include "dynrt/bvh/wide_bvh.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace dynrt::bvh {

namespace detail {
struct MortonScratch;
}

/// One mesh's tree. Exactly one of the two trees is present (both empty for no triangles):
/// the wide tree, which packets and single rays trace, or, when built without it
/// (BuildConfig::wide false, or leaves too large for it), the binary tree with the triangles
/// in its leaf order. The binary tree a wide build starts from is not kept: it would more than
/// double the bytes per triangle, and a refit then had to refit both.
struct TriangleBvh {
    /// The binary tree (built without the wide tree only).
    Bvh bvh;
    /// With the binary tree: `tris[i]` is the triangle of the caller's index
    /// `bvh.prim_ids[i]`, copied so a leaf's triangles are contiguous in memory.
    std::vector<Triangle> tris;
    /// The tree collapsed to kWideWidth children per node with its triangles in SIMD blocks
    /// (BuildConfig::wide).
    WideBvh wide;
    /// Zero-area triangles that were left out of the tree (they can never be hit).
    std::size_t degenerate_skipped = 0;
    /// The caller's indices of those triangles, ascending (`degenerate_skipped` of them). A
    /// refit (refit.h) checks them: it can only move boxes, never add a triangle, so one of
    /// them gaining area means the tree needs a rebuild.
    std::vector<std::uint32_t> skipped_ids;
    /// The Morton builder's working storage (BuildMethod::morton without compact leaves, which
    /// put memory first, else null), kept with
    /// the tree so that rebuilding it every frame writes memory already faulted in: fresh
    /// buffers cost a page fault and the kernel's zeroing per 4 KB page, about a tenth of a
    /// million-triangle build.
    std::shared_ptr<detail::MortonScratch> morton_scratch;

    bool empty() const { return bvh.empty() && wide.empty(); }
    /// Triangles in the tree (the non-degenerate ones at the build).
    std::size_t triangle_count() const {
        return wide.empty() ? bvh.prim_ids.size() : wide.triangle_count;
    }
    /// The box of every triangle in the tree (empty for an empty tree).
    Aabb root_box() const;
};

/// The SAH cost of whichever tree `accel` holds (sah_cost of the wide or the binary tree; the
/// two scales differ, so compare only costs of trees of one kind).
double sah_cost(const TriangleBvh& accel, const SahCosts& costs);

/// The shape of whichever tree `accel` holds. For the wide tree: wide nodes, leaves (slots),
/// triangles per leaf and wide depth (a leaf not counted).
BvhStats compute_stats(const TriangleBvh& accel);

/// Builds with `build_binned_sah` over the non-degenerate triangles of `tris` (borrowed for the
/// call), binning each triangle by the centre of its box. Hits report indices into `tris`.
/// Triangles must be finite (check with is_finite first: the engine reports non-finite input as
/// an error before building). Runs in parallel on the calling thread's oneTBB arena.
TriangleBvh build_triangle_bvh(const TriangleSource& tris, const BuildConfig& config);

/// The same tree, built into the storage of `recycled`, a tree no longer needed (such as the
/// previous frame's tree of a mesh rebuilt every frame) wherever it is large enough. A fresh
/// allocation of a million-triangle tree's 80 MB is faulted in and zeroed by the kernel page by
/// page while the build fills it; reused storage skips that.
TriangleBvh build_triangle_bvh(const TriangleSource& tris, const BuildConfig& config,
                               TriangleBvh&& recycled);

/// Appends to `out` at most `max_parts` boxes that together hold every triangle of the tree:
/// a cut through it, made by splitting the part of largest surface area while the parts fit
/// (so a few boxes bound a mesh much tighter than its root box). Nothing for an empty tree.
void cover_boxes(const TriangleBvh& accel, std::size_t max_parts, std::vector<Aabb>& out);

/// Closest hit along `ray` within [ray.tmin, ray.tmax], or a miss, through whichever tree
/// `accel` holds (the same hit either way). Thread-safe on a shared
/// tree. Box tests are conservative (Ize 2013, "Robust BVH Ray Traversal"), so no triangle that
/// the watertight test would hit is culled by rounding in a box test.
Hit intersect_closest(const TriangleBvh& accel, const Ray& ray);

/// True when any triangle is hit within [ray.tmin, ray.tmax] (shadow rays). Thread-safe.
bool intersect_any(const TriangleBvh& accel, const Ray& ray);

/// Work done by traversals, for benchmarks and tuning (quality of a tree beyond its SAH cost).
struct TraversalStats {
    /// Nodes whose children were box-tested, plus leaves whose triangles were tested.
    std::uint64_t nodes_visited = 0;
    std::uint64_t triangles_tested = 0;
};

/// intersect_closest that also adds its work to `stats` (a separate instantiation of the same
/// traversal; the plain overload pays nothing for counting). For the wide tree, nodes_visited
/// counts wide inner nodes plus leaves and triangles_tested the used lanes of the blocks
/// tested. Thread-safe if `stats` is not shared.
Hit intersect_closest(const TriangleBvh& accel, const Ray& ray, TraversalStats& stats);

/// intersect_any that also counts its work, as above.
bool intersect_any(const TriangleBvh& accel, const Ray& ray, TraversalStats& stats);

/// `validate` for a triangle BVH built from `tris`: the tree it holds against the triangles
/// (the binary tree's invariants with `accel.tris[i]` equal to `tris[accel.bvh.prim_ids[i]]`,
/// or the wide tree's, validate in wide_bvh.h), every triangle in the tree except degenerate
/// ones, which may be absent, `skipped_ids` listing exactly the absent triangles in ascending
/// order and `degenerate_skipped` equal to their number. Holds after a refit too (a triangle
/// that became degenerate stays in the tree, which is allowed). Returns "" when valid, else
/// the first violation. For tests and debug checks.
std::string validate(const TriangleBvh& accel, std::span<const Triangle> tris,
                     std::uint32_t leaf_size_max);

}  // namespace dynrt::bvh
