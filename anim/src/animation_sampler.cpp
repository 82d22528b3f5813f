// glTF 2.0 Appendix C, "Animation Sampler Interpolation Modes"; slerp and squad after Shoemake
// 1985 ("Animating rotation with quaternion curves") and, for squad, as BART evaluates it (Lext,
// Assarsson, Moller 2001, whose quat.c is D. Eberly's Magic Software quaternion code).

#include "dynrt/anim/animation_sampler.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace dynrt::anim {

namespace {

/// The numbers of key k's value (for cubic_spline and squad, its value between the two tangents or controls).
const double* key_value(const AnimationSampler& sampler, std::size_t k) {
    const std::size_t n = sampler.components;
    const bool three_per_key =
        sampler.interpolation == Interpolation::cubic_spline || sampler.interpolation == Interpolation::squad;
    return sampler.values.data() + (three_per_key ? (3 * k + 1) * n : k * n);
}

glm::dvec4 quaternion_at(const double* q) { return glm::dvec4(q[0], q[1], q[2], q[3]); }

void copy_value(const double* value, std::size_t n, std::span<double> out) { std::copy(value, value + n, out.begin()); }

void normalize_quaternion(std::span<double> q) {
    const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& c : q) c /= length;
}

// Eberly's slerp as BART uses it, on purpose not our slerp(): no flip to the short path (BART
// flips keys once, when building the controls), the cosine clamped to [-1, 1] rather than the
// inputs normalised, and p itself, not a lerp, once sin(angle) < 1e-3. Those are what BART
// renders, so squad reproduces them.
glm::dvec4 bart_slerp(const glm::dvec4& p, const glm::dvec4& q, double u) {
    const double cos_angle = std::clamp(glm::dot(p, q), -1.0, 1.0);
    const double angle = std::acos(cos_angle);
    const double sin_angle = std::sin(angle);
    if (sin_angle < 1e-3) return p;
    return (std::sin((1.0 - u) * angle) / sin_angle) * p + (std::sin(u * angle) / sin_angle) * q;
}

// A squad result made unit as BART does: it turns it into an angle 2 acos(w) and a normalised
// axis, then back into a quaternion, which keeps w and rescales (x, y, z). For a unit result
// that is the identity; for the slightly non-unit ones that keys with non-unit axes give, it
// keeps BART's angle where normalize() would change it.
void write_bart_unit(const glm::dvec4& r, std::span<double> out) {
    const double w = std::clamp(r.w, -1.0, 1.0);
    const double xyz_length = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
    if (xyz_length == 0.0) {  // BART: angle 0 about (1, 0, 0)
        out[0] = out[1] = out[2] = 0.0;
        out[3] = 1.0;
        return;
    }
    const double scale = std::sqrt(1.0 - w * w) / xyz_length;
    out[0] = r.x * scale;
    out[1] = r.y * scale;
    out[2] = r.z * scale;
    out[3] = w;
}

// Span k of a squad sampler at fraction s of the way.
void squad_span(const AnimationSampler& sampler, std::size_t k, double s, std::span<double> out) {
    const double* a = key_value(sampler, k);
    const double* b = key_value(sampler, k + 1);
    const glm::dvec4 p = quaternion_at(a), q = quaternion_at(b);
    const glm::dvec4 out_control = quaternion_at(a + 4), in_control = quaternion_at(b - 4);
    write_bart_unit(bart_slerp(bart_slerp(p, q, s), bart_slerp(out_control, in_control, s), 2.0 * s * (1.0 - s)),
                    out);
}

}  // namespace

glm::dvec4 slerp(const glm::dvec4& a, const glm::dvec4& b_in, double u) {
    if (u == 0.0) return a;
    glm::dvec4 b = b_in;
    double cos_angle = glm::dot(a, b);
    if (cos_angle < 0.0) {
        b = -b;
        cos_angle = -cos_angle;
    }
    // Nearly parallel: sin(angle) is too small to divide by, and lerp is as exact there.
    if (cos_angle > 1.0 - 1e-12) return glm::normalize(a + u * (b - a));
    const double angle = std::acos(cos_angle);
    const double sin_angle = std::sin(angle);
    return (std::sin((1.0 - u) * angle) / sin_angle) * a + (std::sin(u * angle) / sin_angle) * b;
}

void sample(const AnimationSampler& sampler, double t, bool rotation, std::span<double> out) {
    const std::vector<double>& times = sampler.times;
    const std::size_t n = sampler.components;
    if (sampler.interpolation == Interpolation::squad) {
        if (times.size() == 1) return write_bart_unit(quaternion_at(key_value(sampler, 0)), out);
        // BART clamps by evaluating the end spans at s = 0 and s = 1, which differs from the
        // end keys where its slerp cut-off keeps the first quaternion.
        if (t <= times.front()) return squad_span(sampler, 0, 0.0, out);
        if (t >= times.back()) return squad_span(sampler, times.size() - 2, 1.0, out);
    }
    if (t <= times.front()) return copy_value(key_value(sampler, 0), n, out);
    if (t >= times.back()) return copy_value(key_value(sampler, times.size() - 1), n, out);
    // times[k] <= t < times[k + 1].
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    const double span_s = times[k + 1] - times[k];
    const double u = (t - times[k]) / span_s;
    const double* a = key_value(sampler, k);
    const double* b = key_value(sampler, k + 1);
    switch (sampler.interpolation) {
        case Interpolation::step:
            return copy_value(a, n, out);
        case Interpolation::linear:
            if (rotation) {
                const glm::dvec4 q = slerp(quaternion_at(a), quaternion_at(b), u);
                for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(c)] = q[c];
                return;
            }
            for (std::size_t c = 0; c < n; ++c) out[c] = (1.0 - u) * a[c] + u * b[c];
            return;
        case Interpolation::cubic_spline: {
            const double* out_tangent = a + n;  // key k's out-tangent follows its value
            const double* in_tangent = b - n;   // key k+1's in-tangent precedes its value
            const double u2 = u * u, u3 = u2 * u;
            const double value_a = 2 * u3 - 3 * u2 + 1, tangent_a = span_s * (u3 - 2 * u2 + u);
            const double value_b = -2 * u3 + 3 * u2, tangent_b = span_s * (u3 - u2);
            for (std::size_t c = 0; c < n; ++c) {
                out[c] = value_a * a[c] + tangent_a * out_tangent[c] + value_b * b[c] + tangent_b * in_tangent[c];
            }
            if (rotation) normalize_quaternion(out);
            return;
        }
        case Interpolation::squad:
            return squad_span(sampler, k, u, out);
    }
}

bool is_constant(const AnimationSampler& sampler) {
    const std::size_t n = sampler.components;
    const std::size_t keys = sampler.times.size();
    const double* first = key_value(sampler, 0);
    if (sampler.interpolation == Interpolation::squad) {
        // squad(s; v, v, v, v) = v; any other control bends the curve away from v.
        for (std::size_t k = 0; k < keys; ++k) {
            const double* value = key_value(sampler, k);
            for (const double* q : {value - n, value, value + n}) {
                if (!std::equal(first, first + n, q)) return false;
            }
        }
        return true;
    }
    for (std::size_t k = 1; k < keys; ++k) {
        if (!std::equal(first, first + n, key_value(sampler, k))) return false;
    }
    if (sampler.interpolation == Interpolation::cubic_spline && keys > 1) {
        for (std::size_t k = 0; k < keys; ++k) {
            const double* value = key_value(sampler, k);
            const auto is_zero = [](double x) { return x == 0.0; };
            if (!std::all_of(value - n, value, is_zero) || !std::all_of(value + n, value + 2 * n, is_zero)) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace dynrt::anim
