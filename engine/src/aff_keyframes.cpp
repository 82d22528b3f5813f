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
        if (k > 0 && !(keys[k].time > keys[k - 1].time)) {
            throw SceneError(cat(what, ": key times are not strictly increasing (key ", k, ")"));
        }
    }
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

// One squad span of KB_RotInitialize: from p to q with controls a and b.
struct SquadSpan {
    glm::dvec4 p, a, b, q;
};

void write(std::vector<double>& values, std::size_t at, const glm::dvec4& q) {
    values[at] = q.x;
    values[at + 1] = q.y;
    values[at + 2] = q.z;
    values[at + 3] = q.w;
}

}  // namespace

AnimationSampler kochanek_bartels_sampler(std::span<const VectorKey> keys, double time_offset,
                                          const std::string& what) {
    check_keys(keys, time_offset, what);
    for (std::size_t k = 0; k < keys.size(); ++k) {
        if (!all_finite(keys[k].value)) throw SceneError(cat(what, ": key ", k, " has a number that is not finite"));
    }
    const std::size_t kept = keys.size() - 2;
    AnimationSampler sampler;
    sampler.interpolation = Interpolation::cubic_spline;
    sampler.components = 3;
    sampler.times.resize(kept);
    sampler.values.assign(kept * 3 * 3, 0.0);
    const auto point = [&](std::size_t i) {
        const Vec3& v = keys[i].value;
        return glm::dvec3(v[0], v[1], v[2]);
    };
    for (std::size_t k = 0; k < kept; ++k) {
        sampler.times[k] = static_cast<double>(keys[k + 1].time) - time_offset;
        const glm::dvec3 value = point(k + 1);
        for (int c = 0; c < 3; ++c) sampler.values[(3 * k + 1) * 3 + static_cast<std::size_t>(c)] = value[c];
    }
    // Span k of the sampler runs from key k+1 to key k+2 of the track.
    for (std::size_t k = 0; k + 1 < kept; ++k) {
        const TangentWeights w = tangent_weights(keys, k);
        const glm::dvec3 p0 = point(k), p1 = point(k + 1), p2 = point(k + 2), p3 = point(k + 3);
        const glm::dvec3 dp = p2 - p1;
        const glm::dvec3 tangent_out = w.out1 * dp + w.out0 * (p1 - p0);
        const glm::dvec3 tangent_in = w.in1 * (p3 - p2) + w.in0 * dp;
        // BART's Hermite runs in the span's own parameter u in [0, 1]; glTF's multiplies the
        // stored tangents by the span's duration, so store them per second.
        const double duration = sampler.times[k + 1] - sampler.times[k];
        for (int c = 0; c < 3; ++c) {
            const std::size_t cc = static_cast<std::size_t>(c);
            sampler.values[(3 * k + 2) * 3 + cc] = tangent_out[c] / duration;
            sampler.values[(3 * (k + 1)) * 3 + cc] = tangent_in[c] / duration;
        }
    }
    return sampler;
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
    std::vector<SquadSpan> spans(keys.size() - 3);
    for (std::size_t i = 0; i < spans.size(); ++i) {
        const glm::dvec4 q0 = quaternion(i), q1 = quaternion(i + 1), q3 = quaternion(i + 3);
        glm::dvec4 q2 = quaternion(i + 2);
        // Acute angle between consecutive keys; q3 is not flipped here, only when its own turn
        // as q2 comes, so Tin may follow the long way round. That is BART's curve.
        if (glm::dot(q1, q2) < 0.0) {
            q2 = -q2;
            rotations[i + 2] = to_angle_axis(q2);
        }
        const TangentWeights w = tangent_weights(keys, i);
        const glm::dvec4 log_dq = eberly_log(multiply(unit_inverse(q1), q2));
        const glm::dvec4 tangent_out = w.out1 * log_dq + w.out0 * eberly_log(multiply(unit_inverse(q0), q1));
        const glm::dvec4 tangent_in = w.in0 * log_dq + w.in1 * eberly_log(multiply(unit_inverse(q2), q3));
        spans[i] = SquadSpan{
            .p = q1,
            .a = multiply(q1, eberly_exp(0.5 * (tangent_out - log_dq))),
            .b = multiply(q2, eberly_exp(0.5 * (log_dq - tangent_in))),
            .q = q2,
        };
    }

    // ---- Spans to per-key [in, value, out] ----
    const std::size_t kept = keys.size() - 2;
    AnimationSampler sampler;
    sampler.interpolation = Interpolation::squad;
    sampler.components = 4;
    sampler.times.resize(kept);
    sampler.values.assign(kept * 3 * 4, 0.0);
    for (std::size_t k = 0; k < kept; ++k) {
        sampler.times[k] = static_cast<double>(keys[k + 1].time) - time_offset;
        // Span k starts at kept key k; the last kept key only ends span k-1.
        const glm::dvec4 value = k < spans.size() ? spans[k].p : spans[k - 1].q;
        write(sampler.values, (3 * k) * 4, k > 0 ? spans[k - 1].b : value);
        write(sampler.values, (3 * k + 1) * 4, value);
        write(sampler.values, (3 * k + 2) * 4, k < spans.size() ? spans[k].a : value);
    }
    return sampler;
}

}  // namespace dynrt::aff
