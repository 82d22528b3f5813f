#pragma once
// Where a shadow ray ends. Wächter and Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection" (Ray Tracing Gems, ch. 6), made scale-free, plus a push for the light's
// distance, since dynrt traces shadow rays from the light to the surface.
//
// Two rounding errors decide whether the surface itself blocks its own shadow ray (acne):
//  1. The hit point, computed from barycentrics, is off the surface by a few ulps of its
//     coordinates, or of the triangle's vertices where they cancel near zero. Offsetting by a
//     fixed number of ulps per coordinate along the normal scales with that error; where a
//     coordinate is small next to the triangle's vertices, an offset relative to the vertices'
//     magnitude takes over. (The paper uses an absolute 2^-16 below 1/32, which assumes a scene
//     about 1 across: a scene 1000 across got acne on a ground plane at y = 0, and one 2e-6
//     across was pushed straight through its walls, letting light into a closed box.)
//  2. The watertight test, run from the light, rounds every vertex minus the ray origin to a
//     few ulps of the light's distance D, so it places the surface to within a few ulps of D
//     along the ray; the grazing angle cancels out (the push along the normal is seen along the
//     ray divided by the same sine). With a light far from a small scene (a light 400 times the
//     scene's size away gave acne over a third of a lit sphere) the first offset is far too
//     small, so the end is pushed a further kLightUlps ulps of D along the normal, per light.
// tests/stress/shadow_stress_test.cpp sweeps both over scales 1e-6 ... 1e6 and grazing lights.

#include <glm/vec3.hpp>

#include <bit>
#include <cmath>
#include <cstdint>

namespace dynrt {

/// Below kShadowOrigin * magnitude a coordinate is pushed by kShadowFloatScale * magnitude instead of by
/// ulps of itself (the paper's 1/32 and 2^-16, relative to the triangle's magnitude).
inline constexpr float kShadowOrigin = 1.0f / 32.0f;
inline constexpr float kShadowFloatScale = 1.0f / 65536.0f;
/// Ulps moved per unit of normal component (the paper's int_scale).
inline constexpr float kShadowIntScale = 256.0f;
/// The light-distance push, in units of D: 16 float epsilons (2^-19), several times the few
/// ulps of D the test's differences and shear round by, and below the exact reference's
/// shadow tolerance (4e-5 of the scene) for lights up to ~20 scene sizes away.
inline constexpr float kShadowLightScale = 16.0f / 8388608.0f;

/// Largest |coordinate| of a triangle's vertices.
inline float triangle_magnitude(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2) {
    float m = 0.0f;
    for (const glm::vec3* v : {&v0, &v1, &v2}) {
        for (int a = 0; a < 3; ++a) m = std::fabs((*v)[a]) > m ? std::fabs((*v)[a]) : m;
    }
    return m;
}

/// `point` moved off its surface along the unit normal `n` (the side the ray will leave on);
/// `magnitude` is triangle_magnitude of the triangle it lies on.
inline glm::vec3 offset_along_normal(const glm::vec3& point, const glm::vec3& n, float magnitude) {
    glm::vec3 out;
    for (int a = 0; a < 3; ++a) {
        const auto ulps = std::int32_t(kShadowIntScale * n[a]);
        const std::int32_t bits = std::bit_cast<std::int32_t>(point[a]);
        // Moving the integer representation moves the float away from zero when both share a
        // sign, so the step's sign follows the coordinate's.
        const float moved = std::bit_cast<float>(bits + (point[a] < 0.0f ? -ulps : ulps));
        out[a] = std::fabs(point[a]) < kShadowOrigin * magnitude
                     ? point[a] + kShadowFloatScale * magnitude * n[a]
                     : moved;
    }
    return out;
}

/// Where the shadow ray from `light` toward `origin` (offset_along_normal's result on a surface
/// with unit normal `n`, facing the light) ends: `origin` pushed kShadowLightScale * D further
/// along `n`, D the largest |component| of light - origin.
inline glm::vec3 shadow_ray_end(const glm::vec3& origin, const glm::vec3& n, const glm::vec3& light) {
    const float dx = std::fabs(light.x - origin.x), dy = std::fabs(light.y - origin.y),
                dz = std::fabs(light.z - origin.z);
    float d = dx;
    d = dy > d ? dy : d;
    d = dz > d ? dz : d;
    const float push = kShadowLightScale * d;
    return glm::vec3(origin.x + push * n.x, origin.y + push * n.y, origin.z + push * n.z);
}

}  // namespace dynrt
