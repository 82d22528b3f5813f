// The packet shading kernel and its SIMD power: simd::pow against std::pow in double (with the
// error bound simd_pow.h documents, and its exact cases), packet::shade against the Phong
// formula in double, and both lane widths giving the same bits.

#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/simd.h"
#include "dynrt/packet/simd_pow.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

namespace dynrt::packet {
namespace {

constexpr int kNative = simd::kNativeLanes;

template <int W>
float pow_at_width(float x, float s) {
    using L = simd::Lanes<W>;
    // The value under test in lane 0, neighbours differing, so lanes cannot leak into each other.
    typename L::F xs, ss;
    for (int i = 0; i < W; ++i) {
        xs[i] = i == 0 ? x : 0.5f + 0.01f * float(i);
        ss[i] = i == 0 ? s : 3.0f + float(i);
    }
    return simd::pow<W>(xs, ss)[0];
}

/// The bases of the accuracy sweep: exact cases, subnormals, powers of two and their
/// neighbours, values just above 1, and a uniform sample of [0, 1.5].
std::vector<float> pow_bases() {
    std::vector<float> xs = {0.0f, 1e-45f, 1e-40f, 0x1p-126f, 1e-30f, 1e-10f, 1e-3f, 0.1f, 0.25f,
                             0.5f, 0.70710677f, 0.70710683f, 0.9f, 0.999f, 0.99999994f, 1.0f,
                             1.00000012f, 1.0001f, 1.41421354f, 1.41421366f, 1.5f};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.5f);
    for (int i = 0; i < 4000; ++i) xs.push_back(uniform(rng));
    return xs;
}

constexpr float kShininess[] = {0.0f, 0.25f, 0.5f, 1.0f, 2.0f, 5.0f, 8.0f, 32.0f, 128.0f,
                                1000.0f, 10000.0f};

TEST(SimdPow, WithinDocumentedErrorOfStdPowInDouble) {
    double worst_units = 0.0;     // relative error, in units of 2^-24, beyond 3|y|
    double worst_abs_le_1 = 0.0;  // absolute error for x <= 1, in units of 2^-24
    for (const float s : kShininess) {
        for (const float x : pow_bases()) {
            const double expected = std::pow(double(x), double(s));
            const float got = pow_at_width<kNative>(x, s);
            SCOPED_TRACE(testing::Message() << "x " << x << ", s " << s << ", std::pow "
                                            << expected << ", simd::pow " << got);
            if (expected < 0x1p-126) {
                // Flushed to zero or a normal float right at the threshold.
                EXPECT_LE(std::abs(double(got) - expected), 0x1p-126);
                continue;
            }
            if (expected >= 0x1p127) continue;  // documented: +inf from 2^127
            ASSERT_TRUE(std::isfinite(got));
            const double y = s == 0.0f ? 0.0 : double(s) * std::log2(double(x));
            const double rel_units = std::abs(double(got) - expected) / expected * 0x1p24;
            EXPECT_LE(rel_units, 4.0 + 3.0 * std::abs(y));
            worst_units = std::max(worst_units, rel_units - 3.0 * std::abs(y));
            if (x <= 1.0f) {
                const double abs_units = std::abs(double(got) - expected) * 0x1p24;
                EXPECT_LT(abs_units, 6.0);
                worst_abs_le_1 = std::max(worst_abs_le_1, abs_units);
            }
        }
    }
    RecordProperty("worst_rel_units_beyond_3y", std::to_string(worst_units));
    RecordProperty("worst_abs_units_x_le_1", std::to_string(worst_abs_le_1));
}

TEST(SimdPow, ExactCasesAsStdPow) {
    for (const float s : kShininess) {
        EXPECT_EQ(pow_at_width<kNative>(1.0f, s), 1.0f) << "1^" << s;
        EXPECT_EQ(pow_at_width<kNative>(0.0f, s), s == 0.0f ? 1.0f : 0.0f) << "0^" << s;
        EXPECT_EQ(pow_at_width<kNative>(-0.0f, s), s == 0.0f ? 1.0f : 0.0f) << "(-0)^" << s;
    }
    for (const float x : {1e-40f, 1e-3f, 0.3f, 0.999f, 1.5f}) {
        EXPECT_EQ(pow_at_width<kNative>(x, 0.0f), 1.0f) << x << "^0";
    }
    // Powers of two to integer powers go through exactly (log2 and 2^k are exact).
    EXPECT_EQ(pow_at_width<kNative>(0.5f, 1.0f), 0.5f);
    EXPECT_EQ(pow_at_width<kNative>(0.25f, 0.5f), 0.5f);
    EXPECT_EQ(pow_at_width<kNative>(0.5f, 100.0f), 0x1p-100f);
    // Beyond the documented range: flush below 2^-126, +inf from 2^127.
    EXPECT_EQ(pow_at_width<kNative>(0.5f, 130.0f), 0.0f);
    EXPECT_EQ(pow_at_width<kNative>(1e-30f, 10000.0f), 0.0f);
    EXPECT_EQ(pow_at_width<kNative>(1.5f, 10000.0f), std::numeric_limits<float>::infinity());
}

TEST(SimdPow, SameBitsAtEveryLaneWidth) {
    for (const float s : kShininess) {
        for (const float x : pow_bases()) {
            EXPECT_EQ(std::bit_cast<std::uint32_t>(pow_at_width<kNative>(x, s)),
                      std::bit_cast<std::uint32_t>(pow_at_width<1>(x, s)))
                << "x " << x << ", s " << s;
        }
    }
}

// ---- packet::shade ----

struct ShadingCase {
    SurfacePacket surface;
    std::vector<PhongMaterial> materials;
    std::vector<ShadingLight> lights;
    std::vector<LaneMask> visible;
    float ambient = 0.08f;
};

glm::vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> normal;
    for (;;) {
        const glm::vec3 v(normal(rng), normal(rng), normal(rng));
        if (glm::length(v) > 1e-3f) return glm::normalize(v);
    }
}

/// A tile of random surfaces: about 4 lanes in 5 hit; four materials (shininess 0, 1, 32 and
/// 1000) in patches, so most SIMD steps hold one material and some hold several; two lights,
/// each visible from the lanes on its side of the surface, minus some shadowed ones.
ShadingCase random_case(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    ShadingCase c;
    c.materials = {PhongMaterial{{0.8f, 0.2f, 0.1f}, {0.3f, 0.3f, 0.3f}, 0.0f},
                   PhongMaterial{{0.1f, 0.7f, 0.2f}, {0.5f, 0.4f, 0.3f}, 1.0f},
                   PhongMaterial{{0.5f, 0.5f, 0.9f}, {0.2f, 0.2f, 0.2f}, 32.0f},
                   PhongMaterial{{0.9f, 0.9f, 0.9f}, {1.0f, 0.9f, 0.8f}, 1000.0f}};
    c.lights = {ShadingLight{{4.0f, 6.0f, 3.0f}, 1.0f}, ShadingLight{{-5.0f, 2.0f, -4.0f}, 0.6f}};
    c.visible.assign(c.lights.size(), LaneMask{});
    for (int lane = 0; lane < kPacketRays; ++lane) {
        if (unit(rng) < 0.2f) {
            // A miss: garbage the kernel must not let through to hit lanes.
            for (int a = 0; a < 3; ++a) c.surface.point[a][lane] = std::nanf("");
            c.surface.material[lane] = 12345;
            continue;
        }
        c.surface.hit.set(lane);
        const glm::vec3 p(unit(rng) * 2 - 1, unit(rng) * 2 - 1, unit(rng) * 2 - 1);
        const glm::vec3 n = random_unit(rng);
        // Views around the mirror direction of the first light, so the specular lobe is
        // sampled where it is large, as well as anywhere.
        const glm::vec3 l = glm::normalize(c.lights[0].position - p);
        const glm::vec3 mirror = 2.0f * glm::dot(n, l) * n - l;
        const glm::vec3 v = unit(rng) < 0.5f ? glm::normalize(mirror + 0.05f * random_unit(rng))
                                             : random_unit(rng);
        for (int a = 0; a < 3; ++a) {
            c.surface.point[a][lane] = p[a];
            c.surface.normal[a][lane] = n[a];
            c.surface.shading_normal[a][lane] = n[a];
            c.surface.view[a][lane] = v[a];
        }
        c.surface.material[lane] = ((lane / 24) + (unit(rng) < 0.1f ? 1 : 0)) % 4;
        for (std::size_t i = 0; i < c.lights.size(); ++i) {
            if (glm::dot(n, c.lights[i].position - p) > 0.0f && unit(rng) < 0.8f) {
                c.visible[i].set(lane);
            }
        }
    }
    return c;
}

/// The renderer's formula (renderer.h) in double.
glm::dvec3 phong_in_double(const ShadingCase& c, int lane) {
    const SurfacePacket& s = c.surface;
    const glm::dvec3 p(s.point[0][lane], s.point[1][lane], s.point[2][lane]);
    const glm::dvec3 n(s.normal[0][lane], s.normal[1][lane], s.normal[2][lane]);
    const glm::dvec3 v(s.view[0][lane], s.view[1][lane], s.view[2][lane]);
    const PhongMaterial& m = c.materials[std::size_t(s.material[lane])];
    const glm::dvec3 kd(m.diffuse), ks(m.specular);
    glm::dvec3 color = double(c.ambient) * kd;
    for (std::size_t i = 0; i < c.lights.size(); ++i) {
        if (!c.visible[i].test(lane)) continue;
        const glm::dvec3 l = glm::normalize(glm::dvec3(c.lights[i].position) - p);
        const double n_dot_l = glm::dot(n, l);
        const glm::dvec3 r = 2.0 * n_dot_l * n - l;
        const double specular = std::pow(std::max(0.0, glm::dot(r, v)), double(m.shininess));
        color += double(c.lights[i].intensity) * (kd * n_dot_l + ks * specular);
    }
    return color;
}

TEST(PacketShade, MatchesPhongInDouble) {
    for (unsigned seed = 1; seed <= 8; ++seed) {
        const ShadingCase c = random_case(seed);
        ShadedColors out;
        shade(c.surface, c.materials, c.lights, c.visible, c.ambient, out);
        int checked = 0;
        for (int lane = 0; lane < kPacketRays; ++lane) {
            if (!c.surface.hit.test(lane)) continue;
            ++checked;
            const glm::dvec3 expected = phong_in_double(c, lane);
            for (int a = 0; a < 3; ++a) {
                // Float shading of unit vectors: a few float roundings of terms of size <= 2,
                // amplified for the specular term by up to shininess 1000 through r.v (an error
                // e in r.v near 1 moves x^s by s e). 1e-4 is ~1000 ulps of 1: it fails on any
                // wrong term, material or light, none of which is smaller than 1e-3.
                EXPECT_NEAR(out.rgb[a][lane], expected[a], 1e-4)
                    << "seed " << seed << ", lane " << lane << ", channel " << a
                    << ", material " << c.surface.material[lane];
            }
        }
        EXPECT_GT(checked, 150);
    }
}

TEST(PacketShade, SameBitsAtBothLaneWidths) {
    for (unsigned seed = 1; seed <= 8; ++seed) {
        const ShadingCase c = random_case(seed);
        ShadedColors native, scalar;
        shade(c.surface, c.materials, c.lights, c.visible, c.ambient, native, kNative);
        shade(c.surface, c.materials, c.lights, c.visible, c.ambient, scalar, 1);
        for (int lane = 0; lane < kPacketRays; ++lane) {
            if (!c.surface.hit.test(lane)) continue;
            for (int a = 0; a < 3; ++a) {
                EXPECT_EQ(std::bit_cast<std::uint32_t>(native.rgb[a][lane]),
                          std::bit_cast<std::uint32_t>(scalar.rgb[a][lane]))
                    << "seed " << seed << ", lane " << lane << ", channel " << a;
            }
        }
    }
}

TEST(PacketShade, UnlitLanesGetTheAmbientTermOnly) {
    ShadingCase c = random_case(3);
    for (LaneMask& mask : c.visible) mask = LaneMask{};
    ShadedColors out;
    shade(c.surface, c.materials, c.lights, c.visible, c.ambient, out);
    for (int lane = 0; lane < kPacketRays; ++lane) {
        if (!c.surface.hit.test(lane)) continue;
        const PhongMaterial& m = c.materials[std::size_t(c.surface.material[lane])];
        EXPECT_EQ(out.rgb[0][lane], c.ambient * m.diffuse.x);
        EXPECT_EQ(out.rgb[1][lane], c.ambient * m.diffuse.y);
        EXPECT_EQ(out.rgb[2][lane], c.ambient * m.diffuse.z);
    }
}

TEST(PacketShade, RejectsBadArguments) {
    const ShadingCase c = random_case(1);
    ShadedColors out;
    const std::vector<LaneMask> one_mask(1);
    EXPECT_THROW(shade(c.surface, c.materials, c.lights, one_mask, c.ambient, out),
                 std::invalid_argument);
    if (kNative != 2) {
        EXPECT_THROW(shade(c.surface, c.materials, c.lights, c.visible, c.ambient, out, 2),
                     std::invalid_argument);
    }
}

}  // namespace
}  // namespace dynrt::packet
