#pragma once

// BART's keyframe tracks (`k name { transl / rot / scale }`, see aff_parser.h) as scene-model
// samplers that evaluate to what BART's reference code computes.
//
// BART: J. Lext, U. Assarsson, T. Moller, "BART: A Benchmark for Animated Ray Tracing", IEEE
// CG&A 21(2), 2001. Its reference code interpolates with D. Eberly's Magic Software splines
// (kbsplpos.c, kbsplrot.c, quat.c): Kochanek-Bartels splines (D. Kochanek, R. Bartels,
// "Interpolating splines with local tension, continuity, and bias control", SIGGRAPH 1984) for
// positions and scales, and for rotations the same tangents taken in the quaternion logarithm,
// evaluated with Shoemake's squad ("Animating rotation with quaternion curves", SIGGRAPH 1985).
// In every track the first and the last key only shape tangents: the curve runs from key 1 to
// key n-2 and is clamped outside.

#include <span>
#include <string>

#include "aff_parser.h"
#include "dynrt/scene/animation_clip.h"

namespace dynrt::aff {

/// A `transl` or `scale` track as a cubic_spline sampler of 3 components over keys 1..n-2,
/// key times shifted by -time_offset (the conversion passes the `a` start time). Per span it
/// equals BART's KB_PosInterpolate0 up to rounding: key k's out-tangent and key k+1's in-tangent
/// are BART's Tout and Tin divided by the span's duration (glTF's Hermite multiplies them back);
/// the first kept key's in-tangent and the last kept key's out-tangent are unused and zero.
/// Equal key times (BART's robots and kitchen have them) make spans of no duration, which BART
/// never evaluates; its curve jumps there, and the sampler keeps both values one double ulp
/// apart (see sampler_keys in the .cpp), so it agrees with BART at every time but within that
/// ulp. Throws SceneError starting with `what` when there are fewer than 4 keys, times
/// decrease, keys 1..n-2 all share one time, or a number (or time_offset) is not finite.
/// Thread safe.
[[nodiscard]] AnimationSampler kochanek_bartels_sampler(std::span<const VectorKey> keys, double time_offset,
                                                        const std::string& what);

/// A `rot` track as a squad sampler (4 components, x y z w; see Interpolation::squad) over keys
/// 1..n-2, times shifted by -time_offset, built as BART's KB_RotInitialize does: angles in
/// degrees made radians, axes used as given (not normalised), a key negated in place when its
/// dot product with the previous one is negative (so later spans see it negated), tangents from
/// Eberly's log and exp with their 1e-3 cut-offs. Unused controls (the first kept key's in, the
/// last kept key's out) hold the key's value, so a constant track is_constant.
/// Known difference: a key that BART negates keeps, for the span ending at it, BART's negated
/// quaternion of its non-unit axis, while the span starting at it uses the unit-axis quaternion
/// BART re-derives; one value slot holds the latter. That span moves by O(|axis| - 1): nothing
/// for unit axes, ~1e-7 for axes unit to float precision, and every key BART negates in the
/// kitchen, robots and museum scenes has ||axis| - 1| < 6e-4.
/// Equal times and errors as kochanek_bartels_sampler, and a zero axis is an error too.
/// Thread safe.
[[nodiscard]] AnimationSampler bart_rotation_sampler(std::span<const RotationKey> keys, double time_offset,
                                                     const std::string& what);

}  // namespace dynrt::aff
