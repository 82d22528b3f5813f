#pragma once
// Single rays and the hits they report.

#include <glm/vec3.hpp>

#include <cstdint>
#include <limits>

namespace dynrt::bvh {

inline constexpr std::uint32_t kInvalidId = 0xffffffffu;

/// A ray segment org + t * dir, t in [tmin, tmax]. `dir` need not be unit length; t is then in
/// units of |dir|.
struct Ray {
    glm::vec3 org{0.0f};
    glm::vec3 dir{0.0f, 0.0f, 1.0f};
    float tmin = 0.0f;
    float tmax = std::numeric_limits<float>::infinity();
};

/// Closest hit: distance, barycentrics of the hit point (p = (1-u-v) v0 + u v1 + v v2) and the
/// primitive, as the caller's index. `prim == kInvalidId` means a miss.
struct Hit {
    float t = std::numeric_limits<float>::infinity();
    float u = 0.0f;
    float v = 0.0f;
    std::uint32_t prim = kInvalidId;

    bool is_hit() const { return prim != kInvalidId; }
};

}  // namespace dynrt::bvh
