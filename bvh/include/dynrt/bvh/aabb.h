#pragma once
// Axis-aligned bounding box, the one geometric primitive the BVH itself knows about.

#include <glm/vec3.hpp>
#include <glm/common.hpp>

#include <limits>

namespace dynrt::bvh {

/// A closed box [lo, hi]. The default value is the empty box (lo = +inf, hi = -inf), which is
/// the identity of `extend`, so boxes can be accumulated without a special first case.
struct Aabb {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};

    void extend(const glm::vec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
    void extend(const Aabb& b) { lo = glm::min(lo, b.lo); hi = glm::max(hi, b.hi); }

    /// True when no point has been added (any lo > hi).
    bool is_empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    glm::vec3 center() const { return (lo + hi) * 0.5f; }
    glm::vec3 extent() const { return hi - lo; }

    /// Half the surface area: the SAH only ever needs area ratios, so the factor 2 is dropped.
    /// Zero for an empty box.
    float half_area() const {
        if (is_empty()) return 0.0f;
        const glm::vec3 e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }

    bool contains(const Aabb& b) const {
        return b.lo.x >= lo.x && b.lo.y >= lo.y && b.lo.z >= lo.z &&
               b.hi.x <= hi.x && b.hi.y <= hi.y && b.hi.z <= hi.z;
    }
};

}  // namespace dynrt::bvh
