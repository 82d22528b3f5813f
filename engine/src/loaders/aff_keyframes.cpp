// BART's Kochanek-Bartels position and squad rotation splines (Lext, Assarsson, Moller 2001;
// Kochanek, Bartels 1984; Shoemake 1985), following the arithmetic of BART's kbsplpos.c,
// kbsplrot.c and quat.c (D. Eberly's Magic Software code) so samplers match what BART renders.
#include "aff_keyframes.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "dynrt/scene/scene_error.h"
#include "message_text.h"

namespace dynrt::aff {

using dynrt::cat;

namespace {

// ---- Checks shared by both kinds of track ----

template <class Key>
void check_keys(std::span<const Key> keys, double time_offset, const std::string& what) {
    // BART needs a key before and after the animated range to shape the end tangents.
    if (keys.size() < 4) throw SceneError(cat(what, ": needs at least 4 keys, has ", keys.size()));
    if (!std::isfinite(time_offset)) throw SceneError(cat(what, ": the time offset is not finite"));
    for (std::size_t k = 0; k < keys.size(); ++k) {
        if (!(std::isfinite(keys[k].time) && std::isfinite(keys[k].tension) && std::isfinite(keys[k].continuity) &&
              std::isfinite(keys[k].bias))) {
            throw SceneError(cat(what, ": key ", k, " has a number that is not finite"));
        }
    }
    // Equal and even falling times are BART's data (robots and kitchen have both); spans BART
    // never evaluates are skipped (sampler_keys), but at least one span must last.
    bool lasts = false;
    for (std::size_t k = 1; k + 2 < keys.size(); ++k) lasts = lasts || keys[k + 1].time > keys[k].time;
    if (!lasts) throw SceneError(cat(what, ": keys 1 to ", keys.size() - 2, " all have the same time"));
}

bool all_finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// ---- Kochanek-Bartels tangent weights, the same for positions and rotations ----

// For the span from key i1 to i2 (neighbours i0 and i3): Tout = out1 (P2 - P1) + out0 (P1 - P0)
// leaves P1 and Tin = in1 (P3 - P2) + in0 (P2 - P1) arrives at P2. The adj factors rescale the
// tangents for uneven key spacing (Kochanek-Bartels section 5).
struct TangentWeights {
    double out0, out1, in0, in1;
};

template <class Key>
TangentWeights tangent_weights(std::span<const Key> keys, std::size_t i0) {
    const Key &k0 = keys[i0], &k1 = keys[i0 + 1], &k2 = keys[i0 + 2], &k3 = keys[i0 + 3];
    const double t0 = k0.time, t1 = k1.time, t2 = k2.time, t3 = k3.time;
    const double adj0 = 2.0 * (t2 - t1) / (t2 - t0);
    const double adj1 = 2.0 * (t2 - t1) / (t3 - t1);
    const double tension1 = 1.0 - k1.tension, tension2 = 1.0 - k2.tension;
    return TangentWeights{
        .out0 = 0.5 * adj0 * tension1 * (1.0 + k1.continuity) * (1.0 + k1.bias),
        .out1 = 0.5 * adj0 * tension1 * (1.0 - k1.continuity) * (1.0 - k1.bias),
        .in0 = 0.5 * adj1 * tension2 * (1.0 - k2.continuity) * (1.0 + k2.bias),
        .in1 = 0.5 * adj1 * tension2 * (1.0 + k2.continuity) * (1.0 - k2.bias),
    };
}

// ---- Eberly's quaternion operations (quat.c), as glm::dvec4 (x, y, z, w) ----

// quat.c's cut-off for sin(angle) near zero in log and exp.
constexpr double kEberlyEpsilon = 1e-3;

glm::dvec4 multiply(const glm::dvec4& a, const glm::dvec4& b) {
    return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y + a.y * b.w + a.z * b.x - a.x * b.z,
            a.w * b.z + a.z * b.w + a.x * b.y - a.y * b.x, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

// The conjugate: the inverse only for unit quaternions, which BART assumes and non-unit axes break.
glm::dvec4 unit_inverse(const glm::dvec4& q) { return {-q.x, -q.y, -q.z, q.w}; }

glm::dvec4 from_angle_axis(double angle_rad, double x, double y, double z) {
    const double sn = std::sin(0.5 * angle_rad);
    return {sn * x, sn * y, sn * z, std::cos(0.5 * angle_rad)};
}

// BART writes a negated key back as angle and axis, so later spans rebuild it from those: a
// unit axis (whatever the key's was) and angle 2 acos(w).
struct AngleAxis {
    double angle_rad, x, y, z;
};

AngleAxis to_angle_axis(const glm::dvec4& q) {
    const double length2 = q.x * q.x + q.y * q.y + q.z * q.z;
    if (!(length2 > 0.0)) return {0.0, 1.0, 0.0, 0.0};
    const double inverse_length = 1.0 / std::sqrt(length2);
    return {2.0 * std::acos(q.w), q.x * inverse_length, q.y * inverse_length, q.z * inverse_length};
}

// log(cos A + sin A v) = A v. Kept as Eberly wrote it: where sin A < 1e-3 (A near 0 but also
// near pi) or |w| >= 1 the vector part is returned unscaled.
glm::dvec4 eberly_log(const glm::dvec4& q) {
    if (std::abs(q.w) < 1.0) {
        const double angle = std::acos(q.w);
        const double sn = std::sin(angle);
        if (std::abs(sn) >= kEberlyEpsilon) {
            const double coeff = angle / sn;
            return {coeff * q.x, coeff * q.y, coeff * q.z, 0.0};
        }
    }
    return {q.x, q.y, q.z, 0.0};
}

// exp(A v) = cos A + sin A v, the input's w ignored; where |sin A| < 1e-3 the vector part is
// kept unscaled (again near pi too, where the result is then far from unit).
glm::dvec4 eberly_exp(const glm::dvec4& q) {
    const double angle = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    const double sn = std::sin(angle);
    const double coeff = std::abs(sn) >= kEberlyEpsilon ? sn / angle : 1.0;
    return {coeff * q.x, coeff * q.y, coeff * q.z, std::cos(angle)};
}

// ---- Spans to sampler keys ----

// One span of a track, from key `first` + 1 to key `first` + 2 (times in the sampler's clock),
// with what its two ends hold: values and, for positions, BART's tangents per second, for
// rotations squad's controls.
template <class V>
struct Span {
    double start_time, end_time;
    V start_value, end_value, start_out, end_in;
};

// A sampler key: in-tangent (or control), value, out-tangent (or control).
template <class V>
struct SamplerKey {
    double time;
    V in, value, out;
};

// The sampler's keys for the spans of a track, as BART's span search uses them: at time t it
// evaluates the first span whose end lies after t (KB_PosInterpolate0, KB_RotInterpolate). So
// a span is used from the latest end of the spans before it (`covered`) to its own end, and
// never when that end is not later: spans of no duration (equal key times) and spans that go
// back in time (robots' tracks have both). Used spans give their ends as keys, shared where
// one starts as the previous ends. Where skipped spans lie between two used ones the value
// jumps: BART evaluates the earlier span for t < T and the later from T on, so the key ending
// the earlier one moves one double ulp down to keep both values. Before the range BART clamps
// to key 1 at t <= T (its search starts with a strict <), after it to key n-2; where those
// differ from the used spans' ends, keys one ulp apart hold both. `still` makes an unused
// tangent or control for a value (zero, or the value itself). Throws SceneError starting with
// `what` for a span that would be used from part way along (a track that goes back in time
// into the middle of a span): no key layout holds that, and BART's scenes have none.
template <class V, class Still>
std::vector<SamplerKey<V>> sampler_keys(const std::vector<Span<V>>& spans, const V& first_value,
                                        const V& last_value, Still still, const std::string& what) {
    std::vector<SamplerKey<V>> keys;
    const auto below = [](double t) { return std::nextafter(t, -INFINITY); };
    const auto above = [](double t) { return std::nextafter(t, INFINITY); };
    double covered = spans.front().start_time;
    bool contiguous = false;  // the previous span was used and ends where this one starts
    for (std::size_t i = 0; i < spans.size(); ++i) {
        const Span<V>& span = spans[i];
        if (!(span.end_time > covered)) {
            contiguous = false;
            continue;
        }
        const auto finite = [](const V& v) {
            for (int c = 0; c < v.length(); ++c) {
                if (!std::isfinite(v[c])) return false;
            }
            return true;
        };
        if (!finite(span.start_out) || !finite(span.end_in)) {
            throw SceneError(cat(what, ": the tangents of keys ", i + 1, " to ", i + 2, " are not finite (the "
                                 "key times around them make BART's spacing factors divide by zero)"));
        }
        if (span.start_time < covered) {
            throw SceneError(cat(what, ": keys ", i + 1, " to ", i + 2, " start before the time earlier keys "
                                 "already reached (", covered, "); such a track is not supported"));
        }
        if (keys.empty()) {
            if (!(span.start_value == first_value)) {
                keys.push_back({span.start_time, still(first_value), first_value, still(first_value)});
                keys.push_back({above(span.start_time), still(span.start_value), span.start_value, span.start_out});
            } else {
                keys.push_back({span.start_time, still(span.start_value), span.start_value, span.start_out});
            }
        } else if (contiguous) {
            keys.back().out = span.start_out;
        } else {
            keys.back().time = below(keys.back().time);
            keys.push_back({span.start_time, still(span.start_value), span.start_value, span.start_out});
        }
        keys.push_back({span.end_time, span.end_in, span.end_value, still(span.end_value)});
        covered = span.end_time;
        contiguous = true;
    }
    if (keys.empty()) {
        throw SceneError(cat(what, ": its key times fall back so that BART would evaluate none of its spans"));
    }
    if (!contiguous && !(keys.back().value == last_value)) {
        const double t = keys.back().time;
        keys.back().time = below(t);
        keys.push_back({t, still(last_value), last_value, still(last_value)});
    }
    return keys;
}

// The sampler holding `keys` in the cubic_spline layout (squad shares it): per key the
// in-tangent or control, the value, the out-tangent or control, each V::length() numbers
// (x, y, z[, w]).
template <class V>
AnimationSampler sampler_of(const std::vector<SamplerKey<V>>& keys, Interpolation interpolation) {
    AnimationSampler sampler;
    sampler.interpolation = interpolation;
    sampler.components = static_cast<std::uint32_t>(V::length());
    for (const SamplerKey<V>& k : keys) {
        sampler.times.push_back(k.time);
        for (const V& v : {k.in, k.value, k.out}) {
            for (int c = 0; c < V::length(); ++c) sampler.values.push_back(v[c]);
        }
    }
    return sampler;
}

}  // namespace

AnimationSampler kochanek_bartels_sampler(std::span<const VectorKey> keys, double time_offset,
                                          const std::string& what) {
    check_keys(keys, time_offset, what);
    for (std::size_t k = 0; k < keys.size(); ++k) {
        if (!all_finite(keys[k].value)) throw SceneError(cat(what, ": key ", k, " has a number that is not finite"));
    }
    const auto point = [&](std::size_t i) {
        const Vec3& v = keys[i].value;
        return glm::dvec3(v[0], v[1], v[2]);
    };
    // Span i runs from key i+1 to key i+2 of the track.
    std::vector<Span<glm::dvec3>> spans;
    for (std::size_t i = 0; i + 3 < keys.size(); ++i) {
        const double start = static_cast<double>(keys[i + 1].time) - time_offset;
        const double end = static_cast<double>(keys[i + 2].time) - time_offset;
        const glm::dvec3 p0 = point(i), p1 = point(i + 1), p2 = point(i + 2), p3 = point(i + 3);
        Span<glm::dvec3> span{start, end, p1, p2, glm::dvec3(0.0), glm::dvec3(0.0)};
        if (end > start) {
            const TangentWeights w = tangent_weights(keys, i);
            const glm::dvec3 dp = p2 - p1;
            // BART's Hermite runs in the span's own parameter u in [0, 1]; glTF's multiplies
            // the stored tangents by the span's duration, so store them per second.
            span.start_out = (w.out1 * dp + w.out0 * (p1 - p0)) / (end - start);
            span.end_in = (w.in1 * (p3 - p2) + w.in0 * dp) / (end - start);
        }
        spans.push_back(span);
    }
    const auto zero = [](const glm::dvec3&) { return glm::dvec3(0.0); };
    return sampler_of(sampler_keys(spans, point(1), point(keys.size() - 2), zero, what),
                      Interpolation::cubic_spline);
}

AnimationSampler bart_rotation_sampler(std::span<const RotationKey> keys, double time_offset,
                                       const std::string& what) {
    check_keys(keys, time_offset, what);
    std::vector<AngleAxis> rotations(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const RotationKey& key = keys[k];
        if (!all_finite(key.axis) || !std::isfinite(key.angle_deg)) {
            throw SceneError(cat(what, ": key ", k, " has a number that is not finite"));
        }
        if (key.axis[0] == 0 && key.axis[1] == 0 && key.axis[2] == 0) {
            throw SceneError(cat(what, ": key ", k, " has a zero rotation axis"));
        }
        // BART's parser: the float angle times M_PI / 180 in double.
        rotations[k] = {static_cast<double>(key.angle_deg) * std::numbers::pi / 180.0, key.axis[0], key.axis[1],
                        key.axis[2]};
    }
    const auto quaternion = [&](std::size_t i) {
        const AngleAxis& r = rotations[i];
        return from_angle_axis(r.angle_rad, r.x, r.y, r.z);
    };

    // ---- KB_RotInitialize, span by span in key order (the in-place negation needs the order) ----
    std::vector<Span<glm::dvec4>> spans;
    for (std::size_t i = 0; i + 3 < keys.size(); ++i) {
        const glm::dvec4 q0 = quaternion(i), q1 = quaternion(i + 1), q3 = quaternion(i + 3);
        glm::dvec4 q2 = quaternion(i + 2);
        // Acute angle between consecutive keys; q3 is not flipped here, only when its own turn
        // as q2 comes, so Tin may follow the long way round. That is BART's curve.
        if (glm::dot(q1, q2) < 0.0) {
            q2 = -q2;
            rotations[i + 2] = to_angle_axis(q2);
        }
        const double start = static_cast<double>(keys[i + 1].time) - time_offset;
        const double end = static_cast<double>(keys[i + 2].time) - time_offset;
        Span<glm::dvec4> span{start, end, q1, q2, q1, q2};
        if (end > start) {
            const TangentWeights w = tangent_weights(keys, i);
            const glm::dvec4 log_dq = eberly_log(multiply(unit_inverse(q1), q2));
            const glm::dvec4 tangent_out = w.out1 * log_dq + w.out0 * eberly_log(multiply(unit_inverse(q0), q1));
            const glm::dvec4 tangent_in = w.in0 * log_dq + w.in1 * eberly_log(multiply(unit_inverse(q2), q3));
            span.start_out = multiply(q1, eberly_exp(0.5 * (tangent_out - log_dq)));
            span.end_in = multiply(q2, eberly_exp(0.5 * (log_dq - tangent_in)));
        }
        spans.push_back(span);
    }

    // ---- Spans to per-key [in, value, out]; unused controls hold the key's value ----
    const auto itself = [](const glm::dvec4& q) { return q; };
    return sampler_of(sampler_keys(spans, quaternion(1), quaternion(keys.size() - 2), itself, what),
                      Interpolation::squad);
}

}  // namespace dynrt::aff
