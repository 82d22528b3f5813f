// BART's keyframe tracks as samplers (engine/src/loaders/aff_keyframes.h): Kochanek-Bartels positions
// and squad rotations worked out by hand, then compared with independent transcriptions of
// BART's kbsplpos.c, kbsplrot.c and quat.c at many times for random keys, and the errors.
#include "loaders/aff_keyframes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "dynrt/anim/animation_sampler.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/scene/scene.h"
#include "dynrt/scene/scene_error.h"

using dynrt::AnimationSampler;
using dynrt::Interpolation;
using dynrt::SceneError;
using namespace dynrt::aff;

namespace {

constexpr double kPi = std::numbers::pi;

std::array<double, 3> sample3(const AnimationSampler& sampler, double t) {
    std::array<double, 3> out{};
    dynrt::anim::sample(sampler, t, false, out);
    return out;
}

std::array<double, 4> sample4(const AnimationSampler& sampler, double t) {
    std::array<double, 4> out{};
    dynrt::anim::sample(sampler, t, true, out);
    return out;
}

// The rotation matrix of a unit quaternion (x, y, z, w), row major: sign-free, so two
// quaternions of the same rotation compare equal.
std::array<double, 9> rotation_matrix(double x, double y, double z, double w) {
    return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
            2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

// Expects the sampler's rotation at t to be `angle_deg` about +z.
void expect_z_rotation(const AnimationSampler& sampler, double t, double angle_deg) {
    const std::array<double, 4> q = sample4(sampler, t);
    const double half = angle_deg * kPi / 360.0;
    const std::array<double, 9> got = rotation_matrix(q[0], q[1], q[2], q[3]);
    const std::array<double, 9> want = rotation_matrix(0, 0, std::sin(half), std::cos(half));
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(got[i], want[i], 1e-12) << "t " << t << " entry " << i;
}

VectorKey vkey(float t, float x, float tension, float continuity, float bias) {
    // y = -x and z = 10 ride along: y must come out negated, z constant.
    return VectorKey{t, {x, -x, 10.0f}, tension, continuity, bias};
}

RotationKey zkey(float t, float angle_deg, float tension = 0, float continuity = 0, float bias = 0) {
    return RotationKey{t, {0, 0, 1}, angle_deg, tension, continuity, bias};
}

}  // namespace

// ---- Kochanek-Bartels positions by hand ----
//
// Keys (t, x; T C B):  k0 (0, 0)  k1 (1, 2; .5 .5 -.5)  k2 (3, 3; 0 -.5 .5)  k3 (4, 1; .25 0 0)
// k4 (6, 0). The curve runs from k1 (t 1) to k3 (t 4); time_offset 0.5 shifts it to [0.5, 3.5].
//
// Span k1 -> k2 (keys 0..3):
//   adj0 = 2 (3 - 1) / (3 - 0) = 4/3, adj1 = 2 (3 - 1) / (4 - 1) = 4/3.
//   At k1: 1-T = .5, 1+C = 1.5, 1-C = .5, 1+B = .5, 1-B = 1.5:
//     out0 = .5 * 4/3 * .5 * 1.5 * .5 = 1/4, out1 = .5 * 4/3 * .5 * .5 * 1.5 = 1/4.
//   DP = 3 - 2 = 1, P1 - P0 = 2: Tout = 1/4 * 1 + 1/4 * 2 = 3/4.
//   At k2: 1-T = 1, 1-C = 1.5, 1+C = .5, 1+B = 1.5, 1-B = .5:
//     in0 = .5 * 4/3 * 1.5 * 1.5 = 3/2, in1 = .5 * 4/3 * .5 * .5 = 1/6.
//   P3 - P2 = -2: Tin = 1/6 * -2 + 3/2 * 1 = 7/6.
//   u = 1/2 (t = 2): Hermite weights 1/2, 1/8, 1/2, -1/8:
//     P = 2/2 + 3/4 / 8 + 3/2 - 7/6 / 8 = 5/2 - 5/96 = 235/96.
// Span k2 -> k3 (keys 1..4):
//   adj0 = 2 (4 - 3) / (4 - 1) = 2/3, adj1 = 2 (4 - 3) / (6 - 3) = 2/3.
//   At k2: out0 = .5 * 2/3 * 1 * .5 * 1.5 = 1/4, out1 = .5 * 2/3 * 1.5 * .5 = 1/4.
//   DP = 1 - 3 = -2, P1 - P0 = 1: Tout = -2/4 + 1/4 = -1/4.
//   At k3: 1-T = .75, C = B = 0: in0 = in1 = .5 * 2/3 * .75 = 1/4.
//   P3 - P2 = -1: Tin = -1/4 - 2/4 = -3/4.
//   u = 1/2 (t = 3.5): P = 3/2 - 1/4 / 8 + 1/2 + 3/4 / 8 = 2 + 1/16 = 33/16.
//   u = 1/4 (t = 3.25): weights 27/32, 9/64, 5/32, -3/64:
//     P = 81/32 - 9/256 + 5/32 + 9/256 = 86/32 = 43/16.
TEST(AffKeyframes, KochanekBartelsByHand) {
    const std::vector<VectorKey> keys = {vkey(0, 0, 0, 0, 0), vkey(1, 2, 0.5f, 0.5f, -0.5f),
                                         vkey(3, 3, 0, -0.5f, 0.5f), vkey(4, 1, 0.25f, 0, 0), vkey(6, 0, 0, 0, 0)};
    const AnimationSampler sampler = kochanek_bartels_sampler(keys, 0.5, "test");
    ASSERT_EQ(sampler.interpolation, Interpolation::cubic_spline);
    ASSERT_EQ(sampler.components, 3u);
    EXPECT_EQ(sampler.times, (std::vector<double>{0.5, 2.5, 3.5}));
    const auto expect_x = [&](double t, double x) {
        const std::array<double, 3> p = sample3(sampler, t);
        EXPECT_NEAR(p[0], x, 1e-12) << "t " << t;
        EXPECT_NEAR(p[1], -x, 1e-12) << "t " << t;
        EXPECT_NEAR(p[2], 10.0, 1e-12) << "t " << t;
    };
    expect_x(2.0 - 0.5, 235.0 / 96.0);  // first span
    expect_x(3.5 - 0.5, 33.0 / 16.0);   // second span
    expect_x(3.25 - 0.5, 43.0 / 16.0);
    expect_x(1.0 - 0.5, 2.0);  // the keys themselves
    expect_x(3.0 - 0.5, 3.0);
    expect_x(-100.0, 2.0);  // clamped before k1 and after k3
    expect_x(0.0, 2.0);
    expect_x(3.6, 1.0);
    expect_x(100.0, 1.0);
}

TEST(AffKeyframes, ConstantTrackIsConstant) {
    const std::vector<VectorKey> keys = {vkey(0, 1, .3f, .2f, .1f), vkey(1, 1, 0, 0, 0), vkey(2, 1, 0, .5f, 0),
                                         vkey(3, 1, 0, 0, 0)};
    EXPECT_TRUE(dynrt::anim::is_constant(kochanek_bartels_sampler(keys, 0, "test")));
    const std::vector<RotationKey> rotations = {zkey(0, 30, .5f), zkey(1, 30), zkey(2, 30, 0, .5f), zkey(3, 30)};
    EXPECT_TRUE(dynrt::anim::is_constant(bart_rotation_sampler(rotations, 0, "test")));
    std::vector<RotationKey> moving = rotations;
    moving[0].angle_deg = 40;  // only shapes the first tangent, which is enough
    EXPECT_FALSE(dynrt::anim::is_constant(bart_rotation_sampler(moving, 0, "test")));
}

// ---- Rotations by hand ----
//
// About one unit axis every quaternion is (0, 0, sin f, cos f) with f half the angle, log and
// exp reduce to f, products add half angles, and slerp interpolates f linearly (while the
// difference is under 180 degrees and its sine over 1e-3). So, in half-angle degrees:
// a = f1 + (Tout - D) / 2, b = f2 + (D - Tin) / 2 with D = f2 - f1, and
// squad(s) = L1 + 2s(1 - s)(L2 - L1), L1 = f1 + s (f2 - f1), L2 = fa + s (fb - fa).
//
// Keys (t, angle; T C B): (0, 0) (1, 40; .5 .5 0) (2, 100; 0 0 .5) (4, 120) (5, 200):
// f = 0, 20, 50, 60, 100.
// Span 1 -> 2 (keys 0..3): adj0 = 2 * 1 / 2 = 1, adj1 = 2 * 1 / 3 = 2/3.
//   out0 = .5 * 1 * .5 * 1.5 = 3/8, out1 = .5 * 1 * .5 * .5 = 1/8; D = 30:
//   Tout = 30/8 + 3/8 * 20 = 11.25.  in0 = .5 * 2/3 * 1.5 = 1/2, in1 = .5 * 2/3 * .5 = 1/6:
//   Tin = 10/6 + 30/2 = 50/3.  fa = 20 + (11.25 - 30) / 2 = 10.625, fb = 50 + (30 - 50/3) / 2
//   = 170/3.  s = 1/2 (t = 1.5): L1 = 35, L2 = 201.875/6, f = (35 + L2) / 2 = 411.875/12,
//   so the angle is 411.875/6 degrees.
// Span 2 -> 3 (keys 1..4): adj0 = 2 * 2 / 3 = adj1 = 4/3.
//   out0 = .5 * 4/3 * 1.5 = 1, out1 = .5 * 4/3 * .5 = 1/3; D = 10: Tout = 10/3 + 30 = 100/3.
//   in0 = in1 = 2/3: Tin = 2/3 * 40 + 2/3 * 10 = 100/3. fa = 50 + 35/3, fb = 60 - 35/3.
//   s = 1/4 (t = 2.5): L1 = 52.5, L2 = fa + (fb - fa) / 4 = fa - 10/3 = 175/3, weight 3/8:
//   f = 52.5 + 3/8 * 35/6 = 54.6875, angle 109.375 degrees.
TEST(AffKeyframes, RotationAboutOneAxisByHand) {
    const std::vector<RotationKey> keys = {zkey(0, 0), zkey(1, 40, .5f, .5f, 0), zkey(2, 100, 0, 0, .5f),
                                           zkey(4, 120), zkey(5, 200)};
    const AnimationSampler sampler = bart_rotation_sampler(keys, 1.0, "test");
    ASSERT_EQ(sampler.interpolation, Interpolation::squad);
    ASSERT_EQ(sampler.components, 4u);
    EXPECT_EQ(sampler.times, (std::vector<double>{0.0, 1.0, 3.0}));
    expect_z_rotation(sampler, 1.5 - 1.0, 411.875 / 6.0);
    expect_z_rotation(sampler, 2.5 - 1.0, 109.375);
    expect_z_rotation(sampler, 1.0 - 1.0, 40);
    expect_z_rotation(sampler, 2.0 - 1.0, 100);
    expect_z_rotation(sampler, -5.0, 40);  // clamped
    expect_z_rotation(sampler, 3.0, 120);
    expect_z_rotation(sampler, 50.0, 120);
}

// Keys 1 and 2 are 340 degrees apart (f 85 and -85: dot cos 170 < 0), so BART negates key 2
// (f 95, angle 190) and writes it back; keys 2 and 3 then are (f 95 and -75), again negated
// (key 3: f 105). Keys (t = 0..4, angle): 150, 170, -170, -150, -130 (f 75, 85, -85, -75, -65),
// TCB 0, so adj = 1 and every multiplier is 1/2.
// Span 1 -> 2: D = 95 - 85 = 10, log(q0^-1 q1) = 10: Tout = 10, fa = 85.
//   q3 is not flipped: log(q2^-1 q3) = -75 - 95 = -170 (the long way), Tin = -85 + 5 = -80,
//   fb = 95 + (10 + 80) / 2 = 140. s = 1/2: L1 = 90, L2 = 112.5, f = 101.25: 202.5 degrees.
// Span 2 -> 3: q1 is the negated key 2 (f 95; had it not been written back, q1 would be f -85,
//   dot(q1, q2) > 0 and nothing would flip). q2 flips to f 105, D = 10, log(q0^-1 q1) = 10,
//   Tout = 10, fa = 95; log(q2^-1 q3) = -65 - 105 = -170, Tin = -80, fb = 105 + 45 = 150.
//   s = 1/2: L1 = 100, L2 = 122.5, f = 111.25: 222.5 degrees.
TEST(AffKeyframes, RotationNegatesKeysInPlace) {
    const std::vector<RotationKey> keys = {zkey(0, 150), zkey(1, 170), zkey(2, -170), zkey(3, -150), zkey(4, -130)};
    const AnimationSampler sampler = bart_rotation_sampler(keys, 0.0, "test");
    expect_z_rotation(sampler, 1.5, 202.5);
    expect_z_rotation(sampler, 2.5, 222.5);
    expect_z_rotation(sampler, 3.0, -150);
}

// Keys 1 and 2 differ by f = 0.0005 rad (sin < 1e-3): Eberly's slerp returns its first
// quaternion, so the whole span stays at key 1's rotation (the identity) and so does the value
// after the end, evaluated at s = 1 of the last span: not key 2's 0.001 rad.
// (log(q1^-1 q2) is cut off too and gives sin(f), exp keeps tiny arguments unscaled; the
// controls are within 1e-3 of the identity, so their slerps are cut off as well.)
TEST(AffKeyframes, SlerpSmallAngleCutOff) {
    const float angle_deg = static_cast<float>(0.001 * 180.0 / kPi);
    const std::vector<RotationKey> keys = {zkey(0, 0), zkey(1, 0), zkey(2, angle_deg), zkey(3, angle_deg)};
    const AnimationSampler sampler = bart_rotation_sampler(keys, 0.0, "test");
    for (const double t : {0.0, 1.0, 1.25, 1.5, 1.99, 2.0, 3.0}) expect_z_rotation(sampler, t, 0.0);
}

// Non-unit axes: BART takes its final rotation as angle 2 acos(w) about the normalised axis, so
// at the keys the rotation is the key's angle, not that of the normalised quaternion.
TEST(AffKeyframes, NonUnitAxisKeepsKeyAngles) {
    std::vector<RotationKey> keys = {zkey(0, 10), zkey(1, 20), zkey(2, 60), zkey(3, 70)};
    for (RotationKey& key : keys) key.axis = {0, 0, 1.05f};
    const AnimationSampler sampler = bart_rotation_sampler(keys, 0.0, "test");
    expect_z_rotation(sampler, 1.0, 20);
    expect_z_rotation(sampler, 2.0, 60);
}

// ---- Independent transcription of BART's kbsplpos.c: the polynomial form ----

namespace {

struct BartCubic {
    std::array<double, 3> c0, c1, c2, c3;
    double tmin, tmax;
};

std::vector<BartCubic> bart_position_polys(const std::vector<VectorKey>& key) {
    std::vector<BartCubic> polys;
    for (std::size_t i0 = 0; i0 + 3 < key.size(); ++i0) {
        const VectorKey &k0 = key[i0], &k1 = key[i0 + 1], &k2 = key[i0 + 2], &k3 = key[i0 + 3];
        const double adj0 = 2.0 * (double(k2.time) - k1.time) / (double(k2.time) - k0.time);
        const double out0 = 0.5 * adj0 * (1.0 - k1.tension) * (1.0 + k1.continuity) * (1.0 + k1.bias);
        const double out1 = 0.5 * adj0 * (1.0 - k1.tension) * (1.0 - k1.continuity) * (1.0 - k1.bias);
        const double adj1 = 2.0 * (double(k2.time) - k1.time) / (double(k3.time) - k1.time);
        const double in0 = 0.5 * adj1 * (1.0 - k2.tension) * (1.0 - k2.continuity) * (1.0 + k2.bias);
        const double in1 = 0.5 * adj1 * (1.0 - k2.tension) * (1.0 + k2.continuity) * (1.0 - k2.bias);
        BartCubic poly{};
        for (int c = 0; c < 3; ++c) {
            const double dp = double(k2.value[c]) - k1.value[c];
            const double tout = out1 * dp + out0 * (double(k1.value[c]) - k0.value[c]);
            const double tin = in1 * (double(k3.value[c]) - k2.value[c]) + in0 * dp;
            poly.c0[c] = k1.value[c];
            poly.c1[c] = tout;
            poly.c2[c] = 3 * dp - 2 * tout - tin;
            poly.c3[c] = -2 * dp + tout + tin;
        }
        poly.tmin = k1.time;
        poly.tmax = k2.time;
        polys.push_back(poly);
    }
    return polys;
}

// BART's ComputeIAndU: the span and its parameter, clamped to [tmin, tmax].
std::pair<std::size_t, double> bart_span(double t, std::size_t count, auto tmin, auto tmax) {
    if (!(tmin(0) < t)) return {0, 0.0};
    if (!(t < tmax(count - 1))) return {count - 1, 1.0};
    std::size_t i = 0;
    while (!(t < tmax(i))) ++i;
    return {i, (t - tmin(i)) / (tmax(i) - tmin(i))};
}

std::array<double, 3> bart_position(const std::vector<BartCubic>& polys, double t) {
    const auto [i, u] = bart_span(
        t, polys.size(), [&](std::size_t j) { return polys[j].tmin; }, [&](std::size_t j) { return polys[j].tmax; });
    const BartCubic& p = polys[i];
    std::array<double, 3> out{};
    for (int c = 0; c < 3; ++c) out[c] = p.c0[c] + u * (p.c1[c] + u * (p.c2[c] + u * p.c3[c]));
    return out;
}

// Times 0.1 .. 1.6 apart, values in [-10, 10], tension, continuity and bias in [-0.9, 0.9].
std::vector<float> random_times(std::mt19937& rng, std::size_t n) {
    std::uniform_real_distribution<float> gap(0.1f, 1.6f);
    std::vector<float> times(n);
    float t = std::uniform_real_distribution<float>(-2.0f, 2.0f)(rng);
    for (float& time : times) time = t += gap(rng);
    return times;
}

}  // namespace

TEST(AffKeyframes, KochanekBartelsMatchesBartsPolynomials) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> value(-10, 10), tcb(-0.9f, 0.9f);
    for (int track = 0; track < 50; ++track) {
        const std::size_t n = 4 + static_cast<std::size_t>(track % 7);
        const std::vector<float> times = random_times(rng, n);
        std::vector<VectorKey> keys(n);
        for (std::size_t k = 0; k < n; ++k) {
            keys[k] = VectorKey{times[k], {value(rng), value(rng), value(rng)}, tcb(rng), tcb(rng), tcb(rng)};
        }
        const double offset = 0.75;
        const AnimationSampler sampler = kochanek_bartels_sampler(keys, offset, "random");
        const std::vector<BartCubic> polys = bart_position_polys(keys);
        const double from = times.front() - 0.5, to = times.back() + 0.5;
        for (int step = 0; step <= 400; ++step) {
            const double t = from + (to - from) * step / 400.0;
            const std::array<double, 3> want = bart_position(polys, t);
            const std::array<double, 3> got = sample3(sampler, t - offset);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12) << "track " << track << " t " << t;
        }
    }
}

// ---- Independent transcription of BART's kbsplrot.c and quat.c ----

namespace {

struct Quat {
    double w, x, y, z;
};

Quat quat_mul(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y + a.y * b.w + a.z * b.x - a.x * b.z, a.w * b.z + a.z * b.w + a.x * b.y - a.y * b.x};
}
Quat quat_scale(const Quat& q, double c) { return {q.w * c, q.x * c, q.y * c, q.z * c}; }
Quat quat_add(const Quat& a, const Quat& b) { return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z}; }
Quat quat_sub(const Quat& a, const Quat& b) { return {a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z}; }
double quat_dot(const Quat& a, const Quat& b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }
Quat quat_conj(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }

struct BartRotation {
    double angle, x, y, z;
};

Quat from_angle_axis(const BartRotation& r) {
    const double sn = std::sin(0.5 * r.angle);
    return {std::cos(0.5 * r.angle), sn * r.x, sn * r.y, sn * r.z};
}

BartRotation to_angle_axis(const Quat& q) {
    const double length2 = q.x * q.x + q.y * q.y + q.z * q.z;
    if (length2 > 0.0) {
        const double inv = 1.0 / std::sqrt(length2);
        return {2.0 * std::acos(q.w), q.x * inv, q.y * inv, q.z * inv};
    }
    return {0, 1, 0, 0};
}

Quat quat_log(const Quat& q) {
    if (std::fabs(q.w) < 1.0) {
        const double angle = std::acos(q.w), sn = std::sin(angle);
        if (std::fabs(sn) >= 1e-3) return {0, q.x * angle / sn, q.y * angle / sn, q.z * angle / sn};
    }
    return {0, q.x, q.y, q.z};
}

Quat quat_exp(const Quat& q) {
    const double angle = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z), sn = std::sin(angle);
    if (std::fabs(sn) >= 1e-3) return {std::cos(angle), q.x * sn / angle, q.y * sn / angle, q.z * sn / angle};
    return {std::cos(angle), q.x, q.y, q.z};
}

Quat quat_slerp(double t, const Quat& p, const Quat& q) {
    double c = quat_dot(p, q);
    if (c < -1.0) c = -1.0;
    if (c > 1.0) c = 1.0;
    const double angle = std::acos(c), sn = std::sin(angle);
    if (sn < 1e-3) return p;
    return quat_add(quat_scale(p, std::sin((1.0 - t) * angle) / sn), quat_scale(q, std::sin(t * angle) / sn));
}

struct BartSquad {
    Quat p, a, b, q;
    double tmin, tmax;
};

struct BartRotationKey {
    double t;
    BartRotation rot;
    double tension, continuity, bias;
};

// KB_RotInitialize; counts the keys it negates in place.
std::vector<BartSquad> bart_rotation_polys(std::vector<BartRotationKey> key, int& negated) {
    std::vector<BartSquad> si;
    for (std::size_t i0 = 0; i0 + 3 < key.size(); ++i0) {
        const std::size_t i1 = i0 + 1, i2 = i0 + 2, i3 = i0 + 3;
        const Quat q0 = from_angle_axis(key[i0].rot), q1 = from_angle_axis(key[i1].rot);
        Quat q2 = from_angle_axis(key[i2].rot);
        const Quat q3 = from_angle_axis(key[i3].rot);
        if (quat_dot(q1, q2) < 0.0) {
            ++negated;
            q2 = quat_scale(q2, -1.0);
            key[i2].rot = to_angle_axis(q2);
        }
        const Quat logdq = quat_log(quat_mul(quat_conj(q1), q2));
        const BartRotationKey &k0 = key[i0], &k1 = key[i1], &k2 = key[i2], &k3 = key[i3];
        const double adj0 = 2 * (k2.t - k1.t) / (k2.t - k0.t);
        const double out0 = 0.5 * adj0 * (1 - k1.tension) * (1 + k1.continuity) * (1 + k1.bias);
        const double out1 = 0.5 * adj0 * (1 - k1.tension) * (1 - k1.continuity) * (1 - k1.bias);
        const Quat tout = quat_add(quat_scale(logdq, out1), quat_scale(quat_log(quat_mul(quat_conj(q0), q1)), out0));
        const double adj1 = 2 * (k2.t - k1.t) / (k3.t - k1.t);
        const double in0 = 0.5 * adj1 * (1 - k2.tension) * (1 - k2.continuity) * (1 + k2.bias);
        const double in1 = 0.5 * adj1 * (1 - k2.tension) * (1 + k2.continuity) * (1 - k2.bias);
        const Quat tin = quat_add(quat_scale(logdq, in0), quat_scale(quat_log(quat_mul(quat_conj(q2), q3)), in1));
        BartSquad s{};
        s.p = q1;
        s.q = q2;
        s.a = quat_mul(q1, quat_exp(quat_scale(quat_sub(tout, logdq), 0.5)));
        s.b = quat_mul(q2, quat_exp(quat_scale(quat_sub(logdq, tin), 0.5)));
        s.tmin = k1.t;
        s.tmax = k2.t;
        si.push_back(s);
    }
    return si;
}

// KB_RotInterpolate, then animation.c's _GetMatrix: angle and axis back to a matrix.
std::array<double, 9> bart_rotation_matrix(const std::vector<BartSquad>& si, double t) {
    const auto [i, s] = bart_span(
        t, si.size(), [&](std::size_t j) { return si[j].tmin; }, [&](std::size_t j) { return si[j].tmax; });
    const BartSquad& sq = si[i];
    const Quat squad = quat_slerp(2 * s * (1 - s), quat_slerp(s, sq.p, sq.q), quat_slerp(s, sq.a, sq.b));
    const Quat q = from_angle_axis(to_angle_axis(squad));
    return rotation_matrix(q.x, q.y, q.z, q.w);
}

enum class Axes { coordinate, unit_in_float, non_unit };

// Random rotation tracks through the sampler and through the transcription above; returns the
// largest difference of matrix entries and counts the keys BART negated in place.
double compare_random_rotations(Axes axes, float angle_max_deg, std::uint32_t seed, int& negated) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> angle(-angle_max_deg, angle_max_deg), tcb(-0.9f, 0.9f);
    std::normal_distribution<double> gauss;
    std::uniform_int_distribution<int> coordinate(0, 5);
    std::uniform_real_distribution<double> length(0.95, 1.05);
    double worst = 0.0;
    for (int track = 0; track < 60; ++track) {
        const std::size_t n = 4 + static_cast<std::size_t>(track % 7);
        const std::vector<float> times = random_times(rng, n);
        std::vector<RotationKey> keys(n);
        std::vector<BartRotationKey> bart_keys(n);
        for (std::size_t k = 0; k < n; ++k) {
            Vec3 axis{};
            if (axes == Axes::coordinate) {
                const int c = coordinate(rng);
                axis[static_cast<std::size_t>(c % 3)] = c < 3 ? 1.0f : -1.0f;
            } else {
                const double x = gauss(rng), y = gauss(rng), z = gauss(rng);
                const double scale = (axes == Axes::non_unit ? length(rng) : 1.0) / std::sqrt(x * x + y * y + z * z);
                axis = {static_cast<float>(x * scale), static_cast<float>(y * scale), static_cast<float>(z * scale)};
            }
            keys[k] = RotationKey{times[k], axis, angle(rng), tcb(rng), tcb(rng), tcb(rng)};
            // BART's parser: floats, the angle times M_PI / 180 in double.
            bart_keys[k] = BartRotationKey{keys[k].time,
                                           {keys[k].angle_deg * std::numbers::pi / 180.0, axis[0], axis[1], axis[2]},
                                           keys[k].tension, keys[k].continuity, keys[k].bias};
        }
        const std::vector<BartSquad> si = bart_rotation_polys(bart_keys, negated);
        const double offset = -1.25;
        const AnimationSampler sampler = bart_rotation_sampler(keys, offset, "random");
        const double from = times.front() - 0.5, to = times.back() + 0.5;
        for (int step = 0; step <= 300; ++step) {
            const double t = from + (to - from) * step / 300.0;
            const std::array<double, 9> want = bart_rotation_matrix(si, t);
            const std::array<double, 4> q = sample4(sampler, t - offset);
            const std::array<double, 9> got = rotation_matrix(q[0], q[1], q[2], q[3]);
            for (int e = 0; e < 9; ++e) worst = std::max(worst, std::abs(got[e] - want[e]));
        }
    }
    return worst;
}

}  // namespace

// Coordinate axes (exactly unit) with angles over two turns: BART negates keys in place often.
TEST(AffKeyframes, RotationMatchesBartsSquad) {
    int negated = 0;
    EXPECT_LT(compare_random_rotations(Axes::coordinate, 360, 81, negated), 1e-9);
    EXPECT_GT(negated, 50);
}

// Axes up to 5% off unit, as in kitchen.aff, and angles within +-80 degrees, so that no key is
// ever negated (every w >= cos 40, every |x, y, z| <= 1.05 sin 40: dot products stay positive).
TEST(AffKeyframes, RotationMatchesBartsSquadWithNonUnitAxes) {
    int negated = 0;
    EXPECT_LT(compare_random_rotations(Axes::non_unit, 80, 82, negated), 1e-9);
    EXPECT_EQ(negated, 0);
}

// bart_rotation_sampler's known difference: a negated key whose axis is unit only to float
// precision (|axis| - 1 ~ 1e-7) moves the span ending at it by about as much.
TEST(AffKeyframes, RotationNegatedFloatAxesDifferOnlyByAxisRounding) {
    int negated = 0;
    EXPECT_LT(compare_random_rotations(Axes::unit_in_float, 360, 83, negated), 1e-5);
    EXPECT_GT(negated, 50);
}

// The pose checks refuse squad anywhere but on a rotation channel.
TEST(AffKeyframes, SquadOnlyDrivesRotations) {
    dynrt::Scene scene;
    scene.source = "squad.test";
    scene.nodes.emplace_back().name = "arm";
    dynrt::AnimationClip clip;
    clip.name = "bart";
    clip.samplers.push_back(bart_rotation_sampler(
        std::vector<RotationKey>{zkey(0, 0), zkey(1, 10), zkey(2, 20), zkey(3, 30)}, 0.0, "test"));
    clip.channels.push_back(dynrt::AnimationChannel{0, dynrt::AnimatedProperty::rotation, 0});
    scene.clips.push_back(clip);
    EXPECT_NO_THROW(dynrt::anim::ScenePoser(scene, {}));
    scene.clips[0].channels[0].property = dynrt::AnimatedProperty::translation;
    try {
        dynrt::anim::ScenePoser poser(scene, {});
        ADD_FAILURE() << "no SceneError";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("squad interpolation is for rotations only"), std::string::npos)
            << e.what();
    }
}

// ---- Errors name the track ----

TEST(AffKeyframes, ErrorsNameTheTrack) {
    const std::string what = "robots/Robot.aff:123: k 'arm_rot1' rot";
    const auto expect_error = [&](auto convert) {
        try {
            convert();
            ADD_FAILURE() << "no SceneError";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    const std::vector<VectorKey> good = {vkey(0, 0, 0, 0, 0), vkey(1, 1, 0, 0, 0), vkey(2, 2, 0, 0, 0),
                                         vkey(3, 3, 0, 0, 0)};
    const std::vector<RotationKey> good_rot = {zkey(0, 0), zkey(1, 10), zkey(2, 20), zkey(3, 30)};
    EXPECT_NO_THROW((void)kochanek_bartels_sampler(good, 0, what));
    EXPECT_NO_THROW((void)bart_rotation_sampler(good_rot, 0, what));

    const auto vector_error = [&](std::vector<VectorKey> keys) {
        expect_error([&] { (void)kochanek_bartels_sampler(keys, 0, what); });
    };
    const auto rotation_error = [&](std::vector<RotationKey> keys) {
        expect_error([&] { (void)bart_rotation_sampler(keys, 0, what); });
    };
    vector_error({good.begin(), good.begin() + 3});
    rotation_error({good_rot.begin(), good_rot.begin() + 3});
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    {
        std::vector<VectorKey> keys = good;
        keys[2].time = keys[1].time;  // equal times
        vector_error(keys);
        keys = good;
        keys[0].time = keys[2].time;  // a spacing factor divides by zero
        vector_error(keys);
        keys = good;
        keys[1].value[2] = nan;
        vector_error(keys);
        keys = good;
        keys[0].bias = inf;
        vector_error(keys);
        keys = good;
        keys[3].time = inf;
        vector_error(keys);
        expect_error([&] { (void)kochanek_bartels_sampler(good, nan, what); });
    }
    {
        std::vector<RotationKey> keys = good_rot;
        keys[2].time = keys[1].time;
        rotation_error(keys);
        keys = good_rot;
        keys[1].angle_deg = nan;
        rotation_error(keys);
        keys = good_rot;
        keys[2].axis[0] = inf;
        rotation_error(keys);
        keys = good_rot;
        keys[3].tension = nan;
        rotation_error(keys);
        keys = good_rot;
        keys[0].axis = {0, 0, 0};
        rotation_error(keys);
    }
}

// ---- Equal and falling key times: BART's robots and kitchen tracks have both ----

namespace {

// Times with repeats and a fall back to before an earlier key, arranged as in Robot1.aff's
// gun_rot1 (the track restarts at an earlier time and only its spans past the first part's
// end are ever evaluated): keys 1..5 rise with a repeat at 2, keys 6..10 restart at 1 and rise
// to 3, which the first part reached, then keys 11.. go on from 3.
const std::vector<float> kRestartingTimes = {0, 0, 1, 2, 2, 3, 1, 1.5f, 2, 2.5f, 3, 4, 5, 5.5f, 5.5f};

// Times at which to compare: a grid, the keys, and points within a millionth of the keys.
std::vector<double> probe_times(const std::vector<float>& times) {
    std::vector<double> probes;
    for (int step = 0; step <= 700; ++step) probes.push_back(-1.0 + step / 100.0);
    for (float t : times) {
        for (double d : {-1e-6, 0.0, 1e-6}) probes.push_back(double(t) + d);
    }
    return probes;
}

}  // namespace

TEST(AffKeyframes, EqualAndFallingTimesFollowBartsSpanSearch) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> value(-10, 10), tcb(-0.9f, 0.9f);
    const std::vector<float>& times = kRestartingTimes;
    for (int track = 0; track < 10; ++track) {
        std::vector<VectorKey> keys(times.size());
        for (std::size_t k = 0; k < keys.size(); ++k) {
            keys[k] = VectorKey{times[k], {value(rng), value(rng), value(rng)}, tcb(rng), tcb(rng), tcb(rng)};
        }
        const AnimationSampler sampler = kochanek_bartels_sampler(keys, 0.0, "restart");
        const std::vector<BartCubic> polys = bart_position_polys(keys);
        for (const double t : probe_times(times)) {
            const std::array<double, 3> want = bart_position(polys, t);
            const std::array<double, 3> got = sample3(sampler, t);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-9) << "track " << track << " t " << t;
        }
        // The jumps are there: at 2 BART takes the span starting at the second key at 2.
        EXPECT_NEAR(sample3(sampler, 2.0)[0], keys[4].value[0], 1e-12);
        EXPECT_NEAR(sample3(sampler, std::nextafter(2.0, 0.0))[0], keys[3].value[0], 1e-9);
    }
}

TEST(AffKeyframes, EqualAndFallingTimesFollowBartsSpanSearchForRotations) {
    std::mt19937 rng(22);
    std::uniform_real_distribution<float> angle(-400, 400), tcb(-0.9f, 0.9f);
    std::uniform_int_distribution<int> coordinate(0, 2);
    const std::vector<float>& times = kRestartingTimes;
    int negated = 0;
    for (int track = 0; track < 10; ++track) {
        std::vector<RotationKey> keys(times.size());
        std::vector<BartRotationKey> bart_keys(times.size());
        for (std::size_t k = 0; k < keys.size(); ++k) {
            Vec3 axis{0, 0, 0};
            axis[std::size_t(coordinate(rng))] = 1;
            keys[k] = RotationKey{times[k], axis, angle(rng), tcb(rng), tcb(rng), tcb(rng)};
            bart_keys[k] = BartRotationKey{keys[k].time,
                                           {keys[k].angle_deg * std::numbers::pi / 180.0, axis[0], axis[1], axis[2]},
                                           keys[k].tension, keys[k].continuity, keys[k].bias};
        }
        const AnimationSampler sampler = bart_rotation_sampler(keys, 0.0, "restart");
        const std::vector<BartSquad> si = bart_rotation_polys(bart_keys, negated);
        for (const double t : probe_times(times)) {
            const std::array<double, 9> want = bart_rotation_matrix(si, t);
            const std::array<double, 4> q = sample4(sampler, t);
            const std::array<double, 9> got = rotation_matrix(q[0], q[1], q[2], q[3]);
            for (int e = 0; e < 9; ++e) EXPECT_NEAR(got[e], want[e], 1e-9) << "track " << track << " t " << t;
        }
    }
}

TEST(AffKeyframes, ATrackWhoseSpansAllFallBackIsRefused) {
    // Key 1 at 5, then 1 and 2: every span ends before 5, so BART would never evaluate one.
    const std::vector<VectorKey> keys = {vkey(0, 0, 0, 0, 0), vkey(5, 1, 0, 0, 0), vkey(1, 2, 0, 0, 0),
                                         vkey(2, 3, 0, 0, 0), vkey(6, 4, 0, 0, 0)};
    try {
        (void)kochanek_bartels_sampler(keys, 0.0, "k 'back'");
        ADD_FAILURE() << "no SceneError";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("k 'back': its key times fall back"), std::string::npos) << e.what();
    }
}

TEST(AffKeyframes, ATrackFallingIntoTheMiddleOfASpanIsRefused) {
    // Keys 1..3 reach 3; key 4 at 2 starts a span 2 -> 4 that BART would use from 3 on, part
    // way along: not representable, so an error naming the track.
    const std::vector<VectorKey> keys = {vkey(0, 0, 0, 0, 0), vkey(1, 1, 0, 0, 0), vkey(3, 2, 0, 0, 0),
                                         vkey(2, 3, 0, 0, 0), vkey(4, 4, 0, 0, 0), vkey(5, 5, 0, 0, 0)};
    try {
        (void)kochanek_bartels_sampler(keys, 0.0, "k 'falls'");
        ADD_FAILURE() << "no SceneError";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("k 'falls': keys 3 to 4 start before"), std::string::npos) << e.what();
    }
}
