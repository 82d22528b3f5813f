#pragma once
// A BVH paired with its triangles in leaf order: the traceable acceleration structure of one
// mesh, with closest-hit and any-hit single-ray traversal.

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"
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

struct TriangleBvh {
    /// The binary tree: what refits decide rebuilds on (its SAH cost) and what packets trace.
    Bvh bvh;
    /// The same tree collapsed to kWideWidth children per node with triangles in SIMD blocks:
    /// what packets and single rays trace when present (BuildConfig::wide). Refitted with the
    /// binary tree.
    WideBvh wide;
    /// `tris[i]` is the triangle of the caller's index `bvh.prim_ids[i]`, copied so a leaf's
    /// triangles are contiguous in memory.
    std::vector<Triangle> tris;
    /// Zero-area triangles that were left out of the tree (they can never be hit).
    std::size_t degenerate_skipped = 0;
    /// The caller's indices of those triangles, ascending (`degenerate_skipped` of them). A
    /// refit (refit.h) checks them: it can only move boxes, never add a triangle, so one of
    /// them gaining area means the tree needs a rebuild.
    std::vector<std::uint32_t> skipped_ids;
    /// The Morton builder's working storage (BuildMethod::morton only, else null), kept with
    /// the tree so that rebuilding it every frame writes memory already faulted in: fresh
    /// buffers cost a page fault and the kernel's zeroing per 4 KB page, about a tenth of a
    /// million-triangle build.
    std::shared_ptr<detail::MortonScratch> morton_scratch;
};

/// Builds with `build_binned_sah` over the non-degenerate triangles of `tris` (borrowed for the
/// call), binning each triangle by the centre of its box. Hits report indices into `tris`.
/// Triangles must be finite (check with is_finite first: the engine reports non-finite input as
/// an error before building). Runs in parallel on the calling thread's oneTBB arena.
TriangleBvh build_triangle_bvh(std::span<const Triangle> tris, const BuildConfig& config);

/// The same tree, built into the storage of `recycled`, a tree no longer needed (such as the
/// previous frame's tree of a mesh rebuilt every frame) wherever it is large enough. A fresh
/// allocation of a million-triangle tree's 80 MB is faulted in and zeroed by the kernel page by
/// page while the build fills it; reused storage skips that.
TriangleBvh build_triangle_bvh(std::span<const Triangle> tris, const BuildConfig& config,
                               TriangleBvh&& recycled);

/// Closest hit along `ray` within [ray.tmin, ray.tmax], or a miss, through the wide tree when
/// there is one, else the binary tree (the same hit either way). Thread-safe on a shared
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

/// The binary tree's traversals, whether or not a wide tree is present: for tests and
/// comparisons.
Hit intersect_closest_binary(const TriangleBvh& accel, const Ray& ray);
bool intersect_any_binary(const TriangleBvh& accel, const Ray& ray);

/// `validate` for a triangle BVH built from `tris`: the tree invariants of `accel.bvh` against
/// the triangles' boxes, except that degenerate triangles may be absent (and no others), plus
/// `accel.tris[i]` equal to `tris[accel.bvh.prim_ids[i]]`, `skipped_ids` listing exactly the
/// absent triangles in ascending order and `degenerate_skipped` equal to their number. Holds
/// after a refit too (a triangle that became degenerate stays in the tree, which is allowed).
/// When the wide tree is present, it must hold exactly the tree's triangles (validate in
/// wide_bvh.h). Returns "" when valid, else the first violation. For tests and debug checks.
std::string validate(const TriangleBvh& accel, std::span<const Triangle> tris,
                     std::uint32_t leaf_size_max);

}  // namespace dynrt::bvh
