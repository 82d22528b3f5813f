// Keyframe sampling against values computed by hand: STEP, LINEAR (with slerp for rotations),
// CUBICSPLINE with tangents, clamping before and after the keys, and the short-path slerp when
// two keys' quaternions have a negative dot product.

#include "dynrt/anim/animation_sampler.h"
#include "dynrt/scene/node.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace dynrt::anim {
namespace {

AnimationSampler make_sampler(Interpolation interpolation, std::vector<double> times, std::uint32_t components,
                              std::vector<double> values) {
    return AnimationSampler{interpolation, std::move(times), components, std::move(values)};
}

double sample_scalar(const AnimationSampler& sampler, double t) {
    double value = 0.0;
    sample(sampler, t, false, std::span(&value, 1));
    return value;
}

glm::dvec4 sample_rotation(const AnimationSampler& sampler, double t) {
    std::array<double, 4> q{};
    sample(sampler, t, true, q);
    return glm::dvec4(q[0], q[1], q[2], q[3]);
}

/// The unit quaternion (x, y, z, w) of a rotation by `degrees` about +Z.
glm::dvec4 about_z(double degrees) {
    const double half = degrees * std::numbers::pi / 360.0;
    return glm::dvec4(0.0, 0.0, std::sin(half), std::cos(half));
}

TEST(AnimationSampler, StepHoldsTheLastKeyAndClamps) {
    const AnimationSampler s = make_sampler(Interpolation::step, {1.0, 2.0, 4.0}, 1, {10.0, 20.0, 40.0});
    EXPECT_EQ(sample_scalar(s, -5.0), 10.0);  // before the first key
    EXPECT_EQ(sample_scalar(s, 1.0), 10.0);
    EXPECT_EQ(sample_scalar(s, 1.999), 10.0);
    EXPECT_EQ(sample_scalar(s, 2.0), 20.0);
    EXPECT_EQ(sample_scalar(s, 3.5), 20.0);
    EXPECT_EQ(sample_scalar(s, 4.0), 40.0);
    EXPECT_EQ(sample_scalar(s, 100.0), 40.0);  // after the last key
}

TEST(AnimationSampler, LinearInterpolatesEachComponentAndClamps) {
    const AnimationSampler s =
        make_sampler(Interpolation::linear, {0.0, 2.0, 3.0}, 3, {0.0, 0.0, 0.0, 4.0, -2.0, 8.0, 4.0, 0.0, 8.0});
    std::array<double, 3> v{};
    sample(s, 0.5, false, v);  // a quarter of the way from key 0 to key 1
    EXPECT_EQ(v, (std::array<double, 3>{1.0, -0.5, 2.0}));
    sample(s, 2.0, false, v);  // exactly on key 1
    EXPECT_EQ(v, (std::array<double, 3>{4.0, -2.0, 8.0}));
    sample(s, 2.75, false, v);
    EXPECT_EQ(v, (std::array<double, 3>{4.0, -0.5, 8.0}));
    sample(s, -1.0, false, v);
    EXPECT_EQ(v, (std::array<double, 3>{0.0, 0.0, 0.0}));
    sample(s, 9.0, false, v);
    EXPECT_EQ(v, (std::array<double, 3>{4.0, 0.0, 8.0}));
}

TEST(AnimationSampler, LinearRotationsUseSlerp) {
    const glm::dvec4 a = about_z(0.0), b = about_z(90.0);
    const AnimationSampler s =
        make_sampler(Interpolation::linear, {0.0, 1.0}, 4, {a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w});
    // Slerp at u = 0.25 turns a quarter of the angle: 22.5 degrees, unit length. Plain lerp
    // would give a shorter quaternion at a different angle (about 20.0 degrees once normalised).
    const glm::dvec4 q = sample_rotation(s, 0.25);
    const glm::dvec4 expected = about_z(22.5);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(q[c], expected[c], 1e-15) << c;
    EXPECT_NEAR(glm::length(q), 1.0, 1e-15);
    EXPECT_EQ(sample_rotation(s, 0.0), a);
    EXPECT_EQ(sample_rotation(s, -3.0), a);
    EXPECT_EQ(sample_rotation(s, 7.0), b);
}

TEST(AnimationSampler, SlerpTakesTheShortPathWhenTheDotProductIsNegative) {
    // Key 1 is the 90-degree turn written as -q (dot with key 0 is negative): the same
    // rotation. The short path reaches 45 degrees half way; the long one would reach -135.
    const glm::dvec4 a = about_z(0.0), b = -about_z(90.0);
    ASSERT_LT(glm::dot(a, b), 0.0);
    const AnimationSampler s =
        make_sampler(Interpolation::linear, {0.0, 1.0}, 4, {a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w});
    const glm::dmat3 r = quaternion_matrix(sample_rotation(s, 0.5));
    const glm::dvec3 x = r * glm::dvec3(1.0, 0.0, 0.0);
    EXPECT_NEAR(x.x, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(x.y, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(x.z, 0.0, 1e-15);

    // Wrap-around through 360 degrees: 270 -> 360 written as (0, 0, sin 135, cos 135) ->
    // (0, 0, 0, 1), dot -0.707. Half way is 315 degrees.
    const glm::dvec4 q270 = about_z(270.0), q360(0.0, 0.0, 0.0, 1.0);
    ASSERT_LT(glm::dot(q270, q360), 0.0);
    const glm::dvec3 x315 = quaternion_matrix(slerp(q270, q360, 0.5)) * glm::dvec3(1.0, 0.0, 0.0);
    EXPECT_NEAR(x315.x, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(x315.y, -std::sqrt(0.5), 1e-15);
}

TEST(AnimationSampler, SlerpOfNearlyEqualQuaternionsStaysUnit) {
    const glm::dvec4 a = about_z(10.0), b = about_z(10.0 + 1e-7);
    const glm::dvec4 q = slerp(a, b, 0.5);
    EXPECT_NEAR(glm::length(q), 1.0, 1e-15);
    EXPECT_NEAR(q.z, about_z(10.0 + 5e-8).z, 1e-15);
}

TEST(AnimationSampler, CubicSplineFollowsTheHermiteBasisWithTangents) {
    // Keys at t = 0 and 2 (td = 2): v0 = 0, out-tangent b0 = 1; v1 = 1, in-tangent a1 = 0.
    // Layout per key: in-tangent, value, out-tangent.
    const AnimationSampler s = make_sampler(Interpolation::cubic_spline, {0.0, 2.0}, 1, {9.0, 0.0, 1.0, 0.0, 1.0, 9.0});
    // t = 1: s = 0.5, basis (2s^3 - 3s^2 + 1, s^3 - 2s^2 + s, -2s^3 + 3s^2, s^3 - s^2) =
    // (0.5, 0.125, 0.5, -0.125); p = 0.5*0 + 2*0.125*1 + 0.5*1 + 2*(-0.125)*0 = 0.75.
    EXPECT_DOUBLE_EQ(sample_scalar(s, 1.0), 0.75);
    // t = 0.5: s = 0.25, basis (0.84375, 0.140625, 0.15625, -0.046875):
    // p = 2 * 0.140625 + 0.15625 = 0.4375.
    EXPECT_DOUBLE_EQ(sample_scalar(s, 0.5), 0.4375);
    // Clamped: the values, never the tangents (the 9s).
    EXPECT_EQ(sample_scalar(s, -1.0), 0.0);
    EXPECT_EQ(sample_scalar(s, 0.0), 0.0);
    EXPECT_EQ(sample_scalar(s, 2.0), 1.0);
    EXPECT_EQ(sample_scalar(s, 5.0), 1.0);
}

TEST(AnimationSampler, CubicSplineRotationsAreNormalised) {
    // Zero tangents between identity and 90 degrees about Z: the Hermite blend at s = 0.5 is
    // (a + b) / 2, normalised: exactly the 45-degree rotation.
    const glm::dvec4 a = about_z(0.0), b = about_z(90.0);
    std::vector<double> values;
    for (const glm::dvec4& q : {a, b}) {
        values.insert(values.end(), {0.0, 0.0, 0.0, 0.0, q.x, q.y, q.z, q.w, 0.0, 0.0, 0.0, 0.0});
    }
    const AnimationSampler s = make_sampler(Interpolation::cubic_spline, {0.0, 1.0}, 4, values);
    const glm::dvec4 q = sample_rotation(s, 0.5);
    const glm::dvec4 expected = about_z(45.0);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(q[c], expected[c], 1e-15) << c;
}

TEST(AnimationSampler, ConstantSamplersAreRecognised) {
    EXPECT_TRUE(is_constant(make_sampler(Interpolation::linear, {0.0}, 1, {3.0})));
    EXPECT_TRUE(is_constant(make_sampler(Interpolation::linear, {0.0, 1.0, 2.0}, 1, {3.0, 3.0, 3.0})));
    EXPECT_FALSE(is_constant(make_sampler(Interpolation::step, {0.0, 1.0}, 1, {3.0, 4.0})));
    EXPECT_TRUE(is_constant(make_sampler(Interpolation::cubic_spline, {0.0, 1.0}, 1, {0, 3, 0, 0, 3, 0})));
    // Equal values but a tangent: the curve bulges between them.
    EXPECT_FALSE(is_constant(make_sampler(Interpolation::cubic_spline, {0.0, 1.0}, 1, {0, 3, 1, 0, 3, 0})));
}

}  // namespace
}  // namespace dynrt::anim
