#pragma once
// Refitting: keeping a tree's topology and recomputing its boxes after the primitives moved,
// for deformable objects whose triangles keep their connectivity from frame to frame (Wald,
// Boulos and Shirley 2007, "Ray Tracing Deformable Scenes Using Dynamic Bounding Volume
// Hierarchies"). A refit costs one pass over the triangles and nodes, far less than a build,
// but the tree's quality decays as the motion moves triangles away from the split choices made
// at build time; the returned SAH cost lets the caller decide when to rebuild instead.

#include "dynrt/bvh/bvh.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/triangle_source.h"

#include <cstdint>
#include <span>

namespace dynrt::bvh {

/// Whether a refit kept the tree.
enum class RefitStatus {
    /// Every box was recomputed; the tree is ready to trace the new primitives.
    refitted,
    /// A triangle left out of a TriangleBvh at build time because it had zero area has area
    /// now. A refit can only move boxes, never add a primitive, so the tree would miss a
    /// visible triangle: it was left untouched, and only a rebuild makes it right.
    skipped_triangle_has_area,
};

/// What a refit did, and the refitted tree's quality.
struct RefitResult {
    RefitStatus status = RefitStatus::refitted;
    /// With skipped_triangle_has_area: the caller's index of the first (lowest-index) skipped
    /// triangle that has area now, for messages. kInvalidId otherwise.
    std::uint32_t triangle_with_area = kInvalidId;
    /// The refitted tree's SAH cost under the costs passed to refit, as `sah_cost` would
    /// compute it (equal up to the rounding of another summation order in double precision).
    /// Gathered during the refit, so it costs no extra pass over the nodes.
    /// Compare it with the cost at the last build to decide when a rebuild pays off. 0 for an
    /// empty tree or when the refit was refused.
    double sah_cost = 0.0;
    /// Whether any triangle differs from what the tree held before, bit for bit: false means
    /// the refit changed no bit of the tree, so a caller may count the update as skipped.
    /// False when the refit was refused.
    bool moved = false;

    bool needs_rebuild() const { return status != RefitStatus::refitted; }
};

/// Refits `accel` to `tris`, the object's triangles after the move in the caller's order (the
/// order given to build_triangle_bvh; a copy of them, a soup's vertices or vertices read
/// through index triples, borrowed for the call). First checks that every
/// triangle left out at build (`accel.skipped_ids`) is still degenerate; if one is not,
/// returns skipped_triangle_has_area and changes nothing. Otherwise refits the tree `accel`
/// holds: the wide tree with refit_wide, or the binary tree by rewriting `accel.tris` in leaf
/// order through `accel.bvh.prim_ids`, then recomputing every node box bottom-up (a leaf's box
/// the union of its triangles' boxes, an inner node's the union of its two children's). The
/// topology and skipped_ids stay as they were, so hits still report the caller's indices. The
/// result's sah_cost is that of the tree held (sah_cost(const TriangleBvh&)). A triangle that
/// became degenerate stays in the tree (validate accepts that): the watertight test never hits
/// it when two vertices coincide, but may when they are only collinear (see is_degenerate),
/// where a rebuild would leave it out; motion makes exactly collinear vertices rarely, and the
/// hit point then lies on the segment anyway.
///
/// Preconditions: `accel` was made by build_triangle_bvh (possibly refitted since) and every
/// triangle is finite (check with is_finite first, as for build_triangle_bvh: the engine
/// reports non-finite input as an error before it gets here). Throws std::invalid_argument,
/// before changing anything, when `tris.size()` differs from the triangle count at build
/// (`accel.triangle_count() + accel.degenerate_skipped`) or `accel.skipped_ids` does not
/// hold `degenerate_skipped` ids. Throws std::invalid_argument, possibly after updating some
/// boxes, for a malformed tree (an index out of range or a path deeper than kMaxDepth).
///
/// Runs in parallel on the calling thread's oneTBB arena for large trees (subtrees of several
/// thousand triangles are refitted as separate tasks, smaller ones serially), and the result
/// is bit for bit that of a serial refit: every node's box and every partial SAH sum is
/// computed by the same expression in the same order whichever thread runs it. Refitting to
/// the very triangles of the build gives back the build's boxes (equal as floats; only the
/// sign of a zero coordinate may differ, as min and max may pick either zero). Not
/// thread-safe on one `accel`; reads `tris` and writes only `accel`.
RefitResult refit(TriangleBvh& accel, const TriangleSource& tris, const SahCosts& costs);

/// Refits a plain tree to new primitive boxes, `boxes[id]` being primitive id's box (the
/// indexing of build_binned_sah's input; borrowed for the call): a leaf's box becomes the
/// union of its primitives' boxes, an inner node's the union of its children's. Boxes must be
/// non-empty and finite. The status is always `refitted`. Throws std::invalid_argument when
/// `boxes.size()` differs from `bvh.prim_ids.size()`, and for a malformed tree as above.
/// Parallel, deterministic and not thread-safe on one `bvh`, like the triangle refit.
RefitResult refit(Bvh& bvh, std::span<const Aabb> boxes, const SahCosts& costs);

}  // namespace dynrt::bvh
