#pragma once
// The space that changed between two traces, as exact pixel reuse (exact_reuse.h) tests rays
// against it: the old and new world boxes of every object that moved, padded so that the
// tests stay conservative under float rounding. A ray that meets none of the boxes before its
// previous hit (or, for a shadow ray, anywhere along its segment) sees exactly what it saw: the
// objects it can reach are unchanged, and the tracer's answer depends only on the ray and
// those triangles (ties go to the smallest (t, object, prim) whatever the tree).
//
// Three tests, from coarse to fine: a tile's primary rays as the pyramid from the eye through
// its corner pixels, and as the hull of the eye and the tile's hit points when every pixel hit;
// a tile's shadow rays as the hull of the light and their end points (or, toward a
// directional light, their origins swept toward it); one ray's segment.

#include "dynrt/bvh/aabb.h"
#include "dynrt/packet/ray_packet.h"

#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace dynrt::detail {

class ChangedSpace {
public:
    /// `boxes`: the changed boxes (empty ones are dropped). `scale`: the largest coordinate
    /// magnitude of the scene, eye and lights; every box is padded by a small multiple of it,
    /// which covers the rounding of rays, hit points and the tests themselves.
    ChangedSpace(std::span<const bvh::Aabb> boxes, float scale);

    bool empty() const { return boxes_.empty(); }
    std::size_t size() const { return boxes_.size(); }
    /// Extra margin for boxes of points computed in float (hit points, shadow ray ends).
    float pad() const { return pad_; }

    /// The lanes of `candidates` whose ray in `rays`, over t in [0, until[lane]] (the rays'
    /// own tmin and tmax are not read), may meet a box: a slab test, 256 lanes at a time in
    /// float (the padding covers its rounding).
    packet::LaneMask meets_rays(const packet::RayPacket& rays, const float* until,
                                const packet::LaneMask& candidates) const;

    /// Whether the hull of `apex` and `points` (a box) may meet a box: the segments from the
    /// apex to any point of `points` lie in it.
    bool meets_hull(const glm::vec3& apex, const bvh::Aabb& points) const;

    /// Whether the pyramid from `apex` spanned by the four directions (any order around it;
    /// corner rays of a tile) may meet a box: rays from the apex through the convex hull of
    /// the directions lie in it.
    bool meets_pyramid(const glm::vec3& apex, const glm::vec3 (&corners)[4]) const;

    /// The boxes of this space that may meet the pyramid (as meets_pyramid) or the hull (as
    /// meets_hull), as a space of their own with the same padding, written into `out` (its
    /// storage reused): a tile's rays are then tested against the few boxes near it only.
    /// Returns whether any box is kept.
    bool select_pyramid(const glm::vec3& apex, const glm::vec3 (&corners)[4], ChangedSpace& out) const;
    bool select_hull(const glm::vec3& apex, const bvh::Aabb& points, ChangedSpace& out) const;

    /// Whether `points` (a box) swept along `dir` without end may meet a box: the rays from
    /// any of them along dir (a directional light's shadow rays) lie in it. select_sweep keeps
    /// those boxes, as select_hull does.
    bool meets_sweep(const bvh::Aabb& points, const glm::vec3& dir) const;
    bool select_sweep(const bvh::Aabb& points, const glm::vec3& dir, ChangedSpace& out) const;

    ChangedSpace() = default;

private:
    std::vector<bvh::Aabb> boxes_;
    float pad_ = 0.0f;
};

}  // namespace dynrt::detail
