#pragma once
// The builder's core, shared by build_binned_sah (caller's boxes and centres) and
// build_triangle_bvh (boxes computed from triangles): both first fill an array of primitive
// references, then hand it over here.

#include "prim_ref.h"

#include "dynrt/bvh/binned_sah_builder.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <cstddef>
#include <functional>
#include <span>

namespace dynrt::bvh::detail {

/// Builds the tree over `refs[0, count)`, reordering them in place (they end in leaf order).
/// `root_box` must be the union of the refs' boxes and `root_center_box` the bounds of their
/// centres. `count` must be >= 1 and < 2^31. `config` must already be checked. Runs on the
/// calling thread's oneTBB arena. `alongside_output`, when set, runs once the primitive ids are
/// in leaf order (it gets them), before the nodes are laid out (the caller's own per-primitive
/// output, such as triangles in leaf order). The result's vectors reuse the storage of
/// `recycled` (a tree no longer needed) where it is large enough. `release_refs`, when set, says
/// the caller lets go of the refs: it is called once they are read for the last time (before
/// the nodes are laid out), so that the caller may free them, and a build over 64 MB of refs
/// or more hands their pages back to the system range by range as it finishes with them
/// (they then read as zeros: the caller must not read them after the call).
/// Instantiated for BoxCenterRef and ExplicitCenterRef.
template <class Ref>
Bvh build_from_prim_refs(Ref* refs, std::size_t count, const Aabb& root_box,
                         const Aabb& root_center_box, const BuildConfig& config,
                         const std::function<void(std::span<const std::uint32_t>)>& alongside_output,
                         Bvh&& recycled = {},
                         const std::function<void()>& release_refs = {});

/// Throws std::invalid_argument unless cost_ratio > 0, leaf_size_max >= 1 and bin_count >= 2.
void check_config(const BuildConfig& config);

/// Fills the references from the caller's spans and gathers the root bounds in the same pass
/// (tbb::parallel_reduce body; build_binned_sah and build_morton).
struct RefFiller {
    std::span<const Aabb> boxes;
    std::span<const glm::vec3> centers;
    ExplicitCenterRef* refs;
    Aabb box;
    Aabb center_box;

    RefFiller(std::span<const Aabb> b, std::span<const glm::vec3> c, ExplicitCenterRef* r)
        : boxes(b), centers(c), refs(r) {}
    RefFiller(RefFiller& other, tbb::split)
        : boxes(other.boxes), centers(other.centers), refs(other.refs) {}
    void operator()(const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            const Aabb& b = boxes[i];
            refs[i] = ExplicitCenterRef{b.lo, static_cast<std::uint32_t>(i), b.hi, 0, centers[i], 0};
            box.extend(b);
            center_box.extend(centers[i]);
        }
    }
    void join(const RefFiller& other) {
        box.extend(other.box);
        center_box.extend(other.center_box);
    }
};


}  // namespace dynrt::bvh::detail
