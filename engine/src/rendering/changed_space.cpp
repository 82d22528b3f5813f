#include "rendering/changed_space.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynrt::detail {

namespace {

/// Relative padding: 2^-12 of the scene's scale is thousands of float ulps at any position in
/// it, far more than the rounding of a ray's point at some t, and a few pixels' worth of
/// conservatism at most.
constexpr float kRelativePad = 1.0f / 4096.0f;

}  // namespace

ChangedSpace::ChangedSpace(std::span<const bvh::Aabb> boxes, float scale)
    : pad_(kRelativePad * std::max(scale, std::numeric_limits<float>::min())) {
    for (const bvh::Aabb& box : boxes) {
        if (box.is_empty()) continue;
        bvh::Aabb padded = box;
        padded.lo -= glm::vec3(pad_);
        padded.hi += glm::vec3(pad_);
        boxes_.push_back(padded);
    }
}

packet::LaneMask ChangedSpace::meets_rays(const packet::RayPacket& rays, const float* until,
                                          const packet::LaneMask& candidates) const {
    constexpr int kLanes = packet::kPacketRays;
    // 1 / dir with zero components made tiny: the slab arithmetic then stays free of NaN
    // (0 * inf), and a ray parallel to a slab is inside it exactly when its origin is.
    alignas(64) float inv[3][kLanes];
    const float* dirs[3] = {rays.dir_x, rays.dir_y, rays.dir_z};
    for (int a = 0; a < 3; ++a) {
        for (int lane = 0; lane < kLanes; ++lane) {
            const float d = dirs[a][lane];
            const float safe = std::fabs(d) < 1e-30f ? std::copysign(1e-30f, d) : d;
            inv[a][lane] = 1.0f / safe;
        }
    }
    const float* orgs[3] = {rays.org_x, rays.org_y, rays.org_z};
    alignas(64) std::uint8_t meets[kLanes] = {};
    for (const bvh::Aabb& box : boxes_) {
        for (int lane = 0; lane < kLanes; ++lane) {
            float near = 0.0f, far = until[lane];
            for (int a = 0; a < 3; ++a) {
                const float t0 = (box.lo[a] - orgs[a][lane]) * inv[a][lane];
                const float t1 = (box.hi[a] - orgs[a][lane]) * inv[a][lane];
                const float lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
                near = lo > near ? lo : near;
                far = hi < far ? hi : far;
            }
            meets[lane] |= std::uint8_t(near <= far);
        }
    }
    packet::LaneMask out;
    for (int lane = 0; lane < kLanes; ++lane) {
        if (meets[lane] && candidates.test(lane)) out.set(lane);
    }
    return out;
}

namespace {

/// Whether the hull of `apex` and `points` may meet `box` (see meets_hull).
bool hull_meets_box(const glm::vec3& apex, const bvh::Aabb& points, float pad, const bvh::Aabb& box) {
    // The hull is the union over s in [0, 1] of the box apex + s (points - apex), whose extent
    // on each axis is [apex + s (lo - apex), apex + s (hi - apex)]. It meets a box when some s
    // satisfies, on every axis, apex + s (lo - apex) <= box.hi and apex + s (hi - apex) >=
    // box.lo: two linear inequalities in s per axis.
    double s_lo = 0.0, s_hi = 1.0;
    // k s <= r
    const auto at_most = [&](double k, double r) {
        if (k > 0.0) s_hi = std::min(s_hi, r / k);
        else if (k < 0.0) s_lo = std::max(s_lo, r / k);
        else if (r < 0.0) s_lo = 2.0;  // never
    };
    for (int a = 0; a < 3; ++a) {
        const double p = apex[a];
        at_most(double(points.lo[a]) - pad - p, double(box.hi[a]) - p);
        at_most(-(double(points.hi[a]) + pad - p), -(double(box.lo[a]) - p));
    }
    return s_lo <= s_hi;
}

/// Whether `points` swept along `dir` without end, {q + t dir : q in points, t >= 0}, may meet
/// `box`: exactly when the ray from 0 along dir meets the box of differences box - points,
/// [box.lo - points.hi, box.hi - points.lo] (widened by the pad), a slab test in double.
bool sweep_meets_box(const bvh::Aabb& points, const glm::vec3& dir, float pad, const bvh::Aabb& box) {
    double t_lo = 0.0, t_hi = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const double lo = double(box.lo[a]) - double(points.hi[a]) - pad;
        const double hi = double(box.hi[a]) - double(points.lo[a]) + pad;
        const double d = dir[a];
        if (d == 0.0) {
            if (lo > 0.0 || hi < 0.0) return false;
            continue;
        }
        const double t0 = lo / d, t1 = hi / d;
        t_lo = std::max(t_lo, std::min(t0, t1));
        t_hi = std::min(t_hi, std::max(t0, t1));
    }
    return t_lo <= t_hi;
}

/// The pyramid from an apex as inward side planes (and the plane across its axis), in double.
struct Pyramid {
    glm::dvec3 apex, normals[5];
    int planes = 4;

    Pyramid(const glm::vec3& apex_point, const glm::vec3 (&corners)[4]) : apex(apex_point) {
        // The side planes through the apex and consecutive corners, facing inwards (a tile
        // gives the corners as (x0,y0), (x1,y0), (x0,y1), (x1,y1): reordered to a cycle). With
        // an apex angle below 180 degrees the four half-spaces hold exactly the forward
        // pyramid. A box is outside when it lies wholly behind one of them (or the axis plane
        // below); a degenerate plane (a tile one pixel wide) culls nothing.
        const glm::dvec3 c[4] = {glm::dvec3(corners[0]), glm::dvec3(corners[1]),
                                 glm::dvec3(corners[3]), glm::dvec3(corners[2])};
        const glm::dvec3 axis = c[0] + c[1] + c[2] + c[3];
        for (int i = 0; i < 4; ++i) {
            glm::dvec3 n = glm::cross(c[i], c[(i + 1) % 4]);
            if (glm::dot(n, axis) < 0.0) n = -n;
            normals[i] = n;
        }
        // Per-plane tests alone let through boxes that straddle the side planes' backward
        // extensions; the plane through the apex across the axis cuts those off. It bounds the
        // pyramid when every corner is in front of it (so is every combination of them).
        bool axis_plane = true;
        for (const glm::dvec3& corner : c) axis_plane = axis_plane && glm::dot(corner, axis) > 0.0;
        if (axis_plane) {
            normals[4] = axis;
            planes = 5;
        }
    }

    bool may_meet(const bvh::Aabb& box) const {
        for (int i = 0; i < planes; ++i) {
            const glm::dvec3& n = normals[i];
            // The box corner furthest along n.
            const glm::dvec3 far(n.x >= 0.0 ? box.hi.x : box.lo.x, n.y >= 0.0 ? box.hi.y : box.lo.y,
                                 n.z >= 0.0 ? box.hi.z : box.lo.z);
            if (glm::dot(n, far - apex) < 0.0) return false;
        }
        return true;
    }
};

}  // namespace

bool ChangedSpace::meets_hull(const glm::vec3& apex, const bvh::Aabb& points) const {
    if (points.is_empty()) return false;
    for (const bvh::Aabb& box : boxes_) {
        if (hull_meets_box(apex, points, pad_, box)) return true;
    }
    return false;
}

bool ChangedSpace::meets_pyramid(const glm::vec3& apex, const glm::vec3 (&corners)[4]) const {
    const Pyramid pyramid(apex, corners);
    for (const bvh::Aabb& box : boxes_) {
        if (pyramid.may_meet(box)) return true;
    }
    return false;
}

bool ChangedSpace::select_pyramid(const glm::vec3& apex, const glm::vec3 (&corners)[4],
                                  ChangedSpace& out) const {
    out.pad_ = pad_;
    out.boxes_.clear();
    const Pyramid pyramid(apex, corners);
    for (const bvh::Aabb& box : boxes_) {
        if (pyramid.may_meet(box)) out.boxes_.push_back(box);
    }
    return !out.boxes_.empty();
}

bool ChangedSpace::select_sweep(const bvh::Aabb& points, const glm::vec3& dir, ChangedSpace& out) const {
    out.pad_ = pad_;
    out.boxes_.clear();
    if (points.is_empty()) return false;
    for (const bvh::Aabb& box : boxes_) {
        if (sweep_meets_box(points, dir, pad_, box)) out.boxes_.push_back(box);
    }
    return !out.boxes_.empty();
}

bool ChangedSpace::meets_sweep(const bvh::Aabb& points, const glm::vec3& dir) const {
    if (points.is_empty()) return false;
    for (const bvh::Aabb& box : boxes_) {
        if (sweep_meets_box(points, dir, pad_, box)) return true;
    }
    return false;
}

bool ChangedSpace::select_hull(const glm::vec3& apex, const bvh::Aabb& points,
                               ChangedSpace& out) const {
    out.pad_ = pad_;
    out.boxes_.clear();
    if (points.is_empty()) return false;
    for (const bvh::Aabb& box : boxes_) {
        if (hull_meets_box(apex, points, pad_, box)) out.boxes_.push_back(box);
    }
    return !out.boxes_.empty();
}

}  // namespace dynrt::detail
