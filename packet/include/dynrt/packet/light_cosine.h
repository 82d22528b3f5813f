#pragma once
// The cosine and the falloff with which packet::shade lights a lane, in one place, so that the
// renderer can leave out exactly the shadow rays whose light shade would not add (the shading
// normal facing away from the light, or a falloff of 0: outside a spot's cone or past a
// light's range). Both compute them with these functions: the same float operations in the
// same order, each rounded (the build compiles with -ffp-contract=off), hence the same bits at
// any SIMD width.

#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/simd.h"

#include <glm/vec3.hpp>

namespace dynrt::packet {

/// For W lanes with hit points p, shading normals s and light points `light` (one per lane:
/// an area light's samples): to = normalize(light - p), as glm normalises
/// (v * (1 / sqrt((x*x + y*y) + z*z))), and s.to (returned).
template <int W>
inline typename simd::Lanes<W>::F light_cosine(const typename simd::Lanes<W>::F (&p)[3],
                                               const typename simd::Lanes<W>::F (&s)[3],
                                               const typename simd::Lanes<W>::F (&light)[3],
                                               typename simd::Lanes<W>::F (&to)[3]) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    to[0] = light[0] - p[0];
    to[1] = light[1] - p[1];
    to[2] = light[2] - p[2];
    const F inv_len = L::splat(1.0f) / L::sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
    for (F& c : to) c = c * inv_len;
    return s[0] * to[0] + s[1] * to[1] + s[2] * to[2];
}

/// The same toward one point `light` for every lane.
template <int W>
inline typename simd::Lanes<W>::F light_cosine(const typename simd::Lanes<W>::F (&p)[3],
                                               const typename simd::Lanes<W>::F (&s)[3],
                                               const glm::vec3& light,
                                               typename simd::Lanes<W>::F (&to)[3]) {
    using L = simd::Lanes<W>;
    const typename L::F at[3] = {L::splat(light.x), L::splat(light.y), L::splat(light.z)};
    return light_cosine<W>(p, s, at, to);
}

/// Light `light`'s cosine at W lanes: toward its lane points `at` (light_cosine), or, for a
/// directional light, toward `light.toward` everywhere (to = toward, returns s.toward).
template <int W>
inline typename simd::Lanes<W>::F light_cosine(const ShadingLight& light, const typename simd::Lanes<W>::F (&p)[3],
                                               const typename simd::Lanes<W>::F (&s)[3],
                                               const typename simd::Lanes<W>::F (&at)[3],
                                               typename simd::Lanes<W>::F (&to)[3]) {
    using L = simd::Lanes<W>;
    if (!light.directional) return light_cosine<W>(p, s, at, to);
    for (int a = 0; a < 3; ++a) to[a] = L::splat(light.toward[a]);
    return s[0] * to[0] + s[1] * to[1] + s[2] * to[2];
}

/// The falloff of `light` at lanes with hit points p, light points `at` and unit vectors `to`
/// toward the light (ShadingLight's comment); only for lights that fall_off().
template <int W>
inline typename simd::Lanes<W>::F light_falloff(const ShadingLight& light, const typename simd::Lanes<W>::F (&p)[3],
                                                const typename simd::Lanes<W>::F (&at)[3],
                                                const typename simd::Lanes<W>::F (&to)[3]) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    const F zero = L::splat(0.0f), one = L::splat(1.0f);
    F factor = one;
    if (light.inverse_square || light.range > 0.0f) {
        const F d[3] = {at[0] - p[0], at[1] - p[1], at[2] - p[2]};
        const F d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (light.inverse_square) factor = one / d2;
        if (light.range > 0.0f) {
            const F r = d2 * L::splat(1.0f / (light.range * light.range));
            F window = one - r * r;
            window = L::select(window > zero, window, zero);
            factor = factor * window;
        }
    }
    if (light.spot) {
        const F cd = -(to[0] * L::splat(light.spot_axis.x) + to[1] * L::splat(light.spot_axis.y) +
                       to[2] * L::splat(light.spot_axis.z));
        F cone = cd * L::splat(light.cone_scale) + L::splat(light.cone_offset);
        cone = L::select(cone > zero, cone, zero);
        cone = L::select(cone < one, cone, one);
        factor = factor * (cone * cone);
    }
    return factor;
}

}  // namespace dynrt::packet
