#pragma once
// Keyframe animation (glTF 2.0 section 3.11): a clip's channels each drive one property of one
// node through a sampler, a list of key times and values with an interpolation mode.

#include <cstdint>
#include <string>
#include <vector>

namespace dynrt {

enum class Interpolation : std::uint8_t {
    step,          ///< the value of the last key at or before t
    linear,        ///< linear between keys; spherical linear (short path) for rotations
    cubic_spline,  ///< cubic Hermite with per-key in- and out-tangents
    /// Rotations only: Shoemake's squad through per-key control quaternions, with BART's
    /// slerp (Lext, Assarsson, Moller 2001; see AnimationSampler::values). glTF never uses it.
    squad,
};

enum class AnimatedProperty : std::uint8_t { translation, rotation, scale, weights };

/// Keyframes of one animated value with `components` numbers.
struct AnimationSampler {
    Interpolation interpolation = Interpolation::linear;
    /// Key times in seconds: finite, strictly increasing, at least one.
    std::vector<double> times;
    /// Numbers per value: 3 (translation, scale), 4 (rotation quaternion x, y, z, w) or the
    /// number of morph targets (weights).
    std::uint32_t components = 0;
    /// step and linear: key k's value at [k * components, (k + 1) * components).
    /// cubic_spline: key k holds in-tangent, value, out-tangent, at
    /// [(3k + j) * components, (3k + j + 1) * components) for j = 0, 1, 2.
    /// squad (rotation samplers only, components 4): laid out like cubic_spline, key k holding
    /// in-control, value, out-control, each a quaternion (x, y, z, w). Between keys k and k+1,
    /// at s the fraction of the way, the value is squad(s; value_k, out_k, in_k+1, value_k+1) =
    /// slerp(2s(1 - s), slerp(s, value_k, value_k+1), slerp(s, out_k, in_k+1)) with BART's slerp
    /// (no short-path flip; the first quaternion when sin(angle) < 1e-3). Before the first key
    /// it is evaluated at s = 0 of the first span, after the last at s = 1 of the last span.
    /// Quaternions need not be unit (BART keys with slightly non-unit axes); the result is made
    /// unit by keeping w and rescaling (x, y, z), as BART's angle-axis round trip does.
    /// Rotation values of step and linear samplers are unit quaternions.
    std::vector<double> values;
};

/// One animated property: `sampler` (index into the clip's samplers) drives `property` of
/// `node` (index into Scene::nodes).
struct AnimationChannel {
    std::uint32_t node = 0;
    AnimatedProperty property = AnimatedProperty::translation;
    std::uint32_t sampler = 0;
};

/// One glTF animation.
struct AnimationClip {
    /// The glTF name, or "animation<i>" after its glTF index when unnamed.
    std::string name;
    std::vector<AnimationSampler> samplers;
    /// Channels whose node lies in the scene; those aimed elsewhere are dropped at load.
    std::vector<AnimationChannel> channels;

    /// First and last key time over the samplers its channels use; 0 for a clip without channels.
    double start_time() const;
    double end_time() const;
};

}  // namespace dynrt
