// glTF 2.0 Appendix C, "Animation Sampler Interpolation Modes"; slerp after Shoemake 1985.

#include "dynrt/anim/animation_sampler.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace dynrt::anim {

namespace {

/// The numbers of key k's value (for cubic_spline, its value between the two tangents).
const double* key_value(const AnimationSampler& sampler, std::size_t k) {
    const std::size_t n = sampler.components;
    return sampler.values.data() + (sampler.interpolation == Interpolation::cubic_spline ? (3 * k + 1) * n : k * n);
}

glm::dvec4 quaternion_at(const double* q) { return glm::dvec4(q[0], q[1], q[2], q[3]); }

void copy_value(const double* value, std::size_t n, std::span<double> out) { std::copy(value, value + n, out.begin()); }

void normalize_quaternion(std::span<double> q) {
    const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& c : q) c /= length;
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
    }
}

bool is_constant(const AnimationSampler& sampler) {
    const std::size_t n = sampler.components;
    const std::size_t keys = sampler.times.size();
    const double* first = key_value(sampler, 0);
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
