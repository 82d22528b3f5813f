#pragma once
// Where a shadow ray starts. Wächter and Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection" (Ray Tracing Gems, ch. 6).
//
// The hit point carries a rounding error proportional to its coordinates' magnitude (a few ulps
// when computed from barycentrics). A fixed epsilon is either too small far from the origin
// (acne) or too large near it (light leaks through thin objects). Offsetting by a fixed number
// of ulps per coordinate, along the normal on the lit side, scales with that error instead.
// Near the origin, where ulps become tiny, a small absolute offset takes over.

#include <glm/vec3.hpp>

#include <bit>
#include <cmath>
#include <cstdint>

namespace dynrt {

/// `point` moved off its surface along the unit normal `n` (the side the ray will leave on).
inline glm::vec3 offset_along_normal(const glm::vec3& point, const glm::vec3& n) {
    constexpr float kOrigin = 1.0f / 32.0f;      // below this magnitude use the absolute offset
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;           // ulps moved per unit of normal component
    glm::vec3 out;
    for (int a = 0; a < 3; ++a) {
        const auto ulps = std::int32_t(kIntScale * n[a]);
        const std::int32_t bits = std::bit_cast<std::int32_t>(point[a]);
        // Moving the integer representation moves the float away from zero when both share a
        // sign, so the step's sign follows the coordinate's.
        const float moved = std::bit_cast<float>(bits + (point[a] < 0.0f ? -ulps : ulps));
        out[a] = std::fabs(point[a]) < kOrigin ? point[a] + kFloatScale * n[a] : moved;
    }
    return out;
}

}  // namespace dynrt
