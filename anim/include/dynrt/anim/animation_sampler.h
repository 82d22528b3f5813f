#pragma once
// Evaluating keyframe samplers at any time (glTF 2.0 section 3.11 and Appendix C, "Animation
// Sampler Interpolation Modes"). Slerp after Shoemake 1985, "Animating rotation with
// quaternion curves".

#include "dynrt/scene/animation_clip.h"

#include <glm/vec4.hpp>

#include <span>

namespace dynrt::anim {

/// Writes the value of `sampler` at time `t` seconds into `out` (sampler.components numbers).
/// Before the first key the first value holds, after the last key the last (clamping).
/// step: the last key at or before t. linear: (1 - u) a + u b with u the fraction of the way
/// between the keys around t; for `rotation` (quaternions x, y, z, w) slerp(a, b, u) instead.
/// cubic_spline: the Hermite spline p(s) = (2s^3 - 3s^2 + 1) v_k + td (s^3 - 2s^2 + s) b_k +
/// (-2s^3 + 3s^2) v_k+1 + td (s^3 - s^2) a_k+1, td the time between the keys, b_k key k's
/// out-tangent and a_k+1 key k+1's in-tangent; a rotation result is normalised.
/// squad (rotations): squad(s; v_k, out_k, in_k+1, v_k+1) with BART's slerp, made unit by
/// keeping w (see AnimationSampler); before the first key and after the last, the first span
/// at s = 0 and the last at s = 1 (the end keys, except where BART's slerp cut-off keeps the
/// span's first quaternion).
/// Preconditions: the sampler is well formed (see AnimationSampler), out.size() == components.
void sample(const AnimationSampler& sampler, double t, bool rotation, std::span<double> out);

/// Spherical linear interpolation between unit quaternions a and b (x, y, z, w), taking the
/// short way round: when dot(a, b) < 0, b is negated first (q and -q are the same rotation).
/// Returns a exactly for u = 0; nearly parallel inputs fall back to normalised lerp.
glm::dvec4 slerp(const glm::dvec4& a, const glm::dvec4& b, double u);

/// True when the sampler gives the same value at every time: one key, or all key values equal
/// (and, for cubic_spline, every tangent zero; for squad, every control equal to the values).
/// Used to classify a channel as not animating.
bool is_constant(const AnimationSampler& sampler);

}  // namespace dynrt::anim
