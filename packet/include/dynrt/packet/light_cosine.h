#pragma once
// The cosine with which packet::shade lights a lane, in one place, so that the renderer can
// leave out exactly the shadow rays whose light shade would not add (the shading normal facing
// away from the light). Both compute it with this function: the same float operations in the
// same order, each rounded (the build compiles with -ffp-contract=off), hence the same bits at
// any SIMD width.

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

}  // namespace dynrt::packet
