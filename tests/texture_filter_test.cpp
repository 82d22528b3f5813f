// dynrt's own texture lookups (textures/texture_filter.h, mip_pyramid.h, TextureSet) against
// the OpenImageIO TextureSystem they replace, on the same files and footprints: every wrap
// mode, magnification and minification across the MIP levels up to the 1x1 level, power-of-two
// and other sizes, grey, RGB, RGBA and 16-bit images. The documented tolerance (docs/rendering.md
// "Textures") is 1/255 per channel of the filtered, still sRGB-encoded value; the figure
// printed is the largest difference seen. Also: SIMD lanes, whole batches and one lane give
// the same bits,
// the sRGB decoding follows the exact curve, and coordinates or footprints that are not
// finite read inside the image.

#include "textures/mip_pyramid.h"
#include "textures/srgb_decode.h"
#include "textures/texture_filter.h"

#include "dynrt/engine/texture_set.h"
#include "dynrt/packet/simd.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <limits>
#include <memory>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

namespace dynrt {
namespace {

namespace fs = std::filesystem;

/// The TextureSystem as dynrt used it before (automip, 64-texel tiles, grey as RGB), reading
/// colours unassociated as dynrt's decoder does. Never destroyed: Debian's OpenImageIO 2.4
/// frees one with a mismatched sized delete (AddressSanitizer's new-delete-type-mismatch).
OIIO::TextureSystem& oiio_textures() {
    static OIIO::TextureSystem* const system = [] {
        OIIO::TextureSystem* s = OIIO::TextureSystem::create(false);
        s->attribute("automip", 1);
        s->attribute("autotile", 64);
        s->attribute("gray_to_rgb", 1);
        s->attribute("unassociatedalpha", 1);
        return s;
    }();
    return *system;
}

OIIO::TextureOpt::Wrap oiio_wrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::clamp: return OIIO::TextureOpt::WrapClamp;
        case TextureWrap::mirror: return OIIO::TextureOpt::WrapMirror;
        case TextureWrap::repeat: break;
    }
    return OIIO::TextureOpt::WrapPeriodic;
}

/// A test image: random texels of `channels` channels, 8 or 16 bits, written as a PNG.
struct TestImage {
    int width, height, channels;
    bool sixteen_bit;
    fs::path path;
};

TestImage write_random_png(const std::string& name, int width, int height, int channels, bool sixteen_bit,
                           std::uint32_t seed) {
    TestImage image{width, height, channels, sixteen_bit,
                    fs::path(::testing::TempDir()) / ("dynrt_filter_" + std::to_string(::getpid()) + "_" + name + ".png")};
    std::mt19937 random(seed);
    const std::size_t n = std::size_t(width) * std::size_t(height) * std::size_t(channels);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(image.path.string());
    EXPECT_TRUE(out) << OIIO::geterror();
    const OIIO::TypeDesc format = sixteen_bit ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8;
    EXPECT_TRUE(out->open(image.path.string(), OIIO::ImageSpec(width, height, channels, format)));
    if (sixteen_bit) {
        std::vector<std::uint16_t> texels(n);
        for (std::uint16_t& v : texels) v = std::uint16_t(random() & 0xffffu);
        EXPECT_TRUE(out->write_image(format, texels.data()));
    } else {
        std::vector<std::uint8_t> texels(n);
        // Random alpha too: an image read associated (RGB times alpha) would differ.
        for (std::uint8_t& v : texels) v = std::uint8_t(random() & 0xffu);
        EXPECT_TRUE(out->write_image(format, texels.data()));
    }
    EXPECT_TRUE(out->close());
    return image;
}

/// A scene of one material mapping `image` with `wrap`, its texels linear (no decoding, so the
/// filtered values are compared as stored).
Scene scene_of(const TestImage& image, TextureWrap wrap_s, TextureWrap wrap_t) {
    Scene scene;
    scene.source = "filter test";
    Material m;
    m.name = "m";
    m.diffuse_map = TextureMap{0, wrap_s, wrap_t};
    scene.materials.push_back(m);
    Texture t;
    t.name = t.path = image.path.string();
    t.srgb = false;
    scene.textures.push_back(t);
    return scene;
}

/// OpenImageIO's trilinear lookup over an isotropic footprint `width` wide, as dynrt made it.
glm::vec3 oiio_lookup(const TestImage& image, TextureWrap wrap_s, TextureWrap wrap_t, float s, float t, float width) {
    OIIO::TextureOpt options;
    options.swrap = oiio_wrap(wrap_s);
    options.twrap = oiio_wrap(wrap_t);
    options.mipmode = OIIO::TextureOpt::MipModeTrilinear;
    options.interpmode = OIIO::TextureOpt::InterpBilinear;
    options.fill = 1.0f;
    float rgb[3] = {-1.0f, -1.0f, -1.0f};
    EXPECT_TRUE(oiio_textures().texture(OIIO::ustring(image.path.string()), options, s, t, width, 0.0f, 0.0f, width,
                                        3, rgb))
        << oiio_textures().geterror();
    return {rgb[0], rgb[1], rgb[2]};
}

/// Footprints from far under a texel (magnification) to wider than the image, through every
/// level and the blends between them.
std::vector<float> footprints(const TestImage& image) {
    std::vector<float> widths = {0.0f, 1e-6f};
    const float texel = 1.0f / float(std::max(image.width, image.height));
    for (float k = 0.3f; k < 4.0f * float(std::max(image.width, image.height)); k *= 1.37f) widths.push_back(k * texel);
    widths.push_back(2.5f);
    return widths;
}

TEST(TextureFilter, AgreesWithOpenImageIOsTextureSystemWithinOneStep) {
    const std::vector<TestImage> images = {
        write_random_png("pot_rgb", 64, 32, 3, false, 1),     write_random_png("npot_rgb", 37, 23, 3, false, 2),
        write_random_png("grey", 19, 40, 1, false, 3),        write_random_png("rgba", 24, 24, 4, false, 4),
        write_random_png("thin", 1, 9, 3, false, 5),          write_random_png("deep", 21, 14, 3, true, 6),
    };
    std::mt19937 random(7);
    std::uniform_real_distribution<float> coordinate(-2.5f, 3.5f);
    const TextureWrap wraps[] = {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror};
    float largest = 0.0f;
    int lookups = 0;
    for (const TestImage& image : images) {
        for (const TextureWrap wrap_s : wraps) {
            for (const TextureWrap wrap_t : wraps) {
                const TextureSet set(scene_of(image, wrap_s, wrap_t));
                ASSERT_TRUE(set.maps(0)) << image.path;
                for (const float width : footprints(image)) {
                    for (int k = 0; k < 12; ++k) {
                        const float s = coordinate(random), t = coordinate(random);
                        const glm::vec3 ours = set.diffuse(0, {s, t}, width);
                        const glm::vec3 theirs = oiio_lookup(image, wrap_s, wrap_t, s, t, width);
                        const float d = std::max({std::abs(ours.x - theirs.x), std::abs(ours.y - theirs.y),
                                                  std::abs(ours.z - theirs.z)});
                        largest = std::max(largest, d);
                        ++lookups;
                        ASSERT_LE(d, 1.0f / 255.0f)
                            << image.path.filename() << " wrap " << int(wrap_s) << "," << int(wrap_t) << " at (" << s
                            << ", " << t << ") width " << width << ": (" << ours.x << ", " << ours.y << ", " << ours.z
                            << ") vs (" << theirs.x << ", " << theirs.y << ", " << theirs.z << ")";
                    }
                }
            }
        }
    }
    std::printf("dynrt vs OpenImageIO TextureSystem: %d lookups, largest difference %.3g (%.3f steps of 1/255)\n",
                lookups, largest, largest * 255.0f);
    for (const TestImage& image : images) fs::remove(image.path);
}

TEST(TextureFilter, TexelCentresAtEachLevelAreTheLevelsTexels) {
    // A footprint of exactly one texel of level m reads level m alone (blend 1): at a texel's
    // centre, that texel. Level 1 of a 4x2 image is the 2x2 box average of level 0 (rounded).
    TexelArray image{.width = 4, .height = 2, .channels = 1, .floating = false,
                     .bytes = {0, 10, 20, 31, 100, 110, 120, 130}};
    const textures::MipPyramid pyramid(image);
    ASSERT_EQ(pyramid.levels().size(), 3u);  // 4x2, 2x1, 1x1
    EXPECT_EQ(pyramid.levels()[1].width, 2);
    EXPECT_EQ(pyramid.levels()[1].height, 1);
    EXPECT_FLOAT_EQ(pyramid.texel(1, 0, 0, 0) * 255.0f, 55.0f);                 // (0 + 10 + 100 + 110) / 4
    EXPECT_FLOAT_EQ(pyramid.texel(1, 1, 0, 0) * 255.0f, std::floor(75.25f + 0.5f));  // (20 + 31 + 120 + 130) / 4
    float r, g, b;
    float* out[3] = {&r, &g, &b};
    const float s = 0.25f, t = 0.5f, width = 1.0f / 1.0f;  // level 1's smaller side is 1 texel
    textures::trilinear_lookup<1>(pyramid, TextureWrap::clamp, TextureWrap::clamp, false, &s, &t, &width, out);
    EXPECT_FLOAT_EQ(r, pyramid.texel(1, 0, 0, 0));
    EXPECT_FLOAT_EQ(g, r);  // grey widened to RGB
}

template <int W>
void lookups_of_width(const textures::MipPyramid& pyramid, TextureWrap wrap, const std::vector<float>& s,
                      const std::vector<float>& t, const std::vector<float>& width, std::vector<float> rgb[3]) {
    for (std::size_t i = 0; i < s.size(); i += W) {
        float* out[3] = {&rgb[0][i], &rgb[1][i], &rgb[2][i]};
        textures::trilinear_lookup<W>(pyramid, wrap, wrap, true, &s[i], &t[i], &width[i], out);
    }
}

TEST(TextureFilter, SimdLanesAndOneLaneGiveTheSameBits) {
    std::mt19937 random(11);
    TexelArray image{.width = 45, .height = 30, .channels = 3, .floating = false, .bytes = {}};
    image.bytes.resize(45 * 30 * 3);
    for (unsigned char& v : image.bytes) v = static_cast<unsigned char>(random() & 0xffu);
    const textures::MipPyramid pyramid(image);
    constexpr int kCount = 16 * 64;
    std::vector<float> s(kCount), t(kCount), width(kCount);
    std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f), footprint(0.0f, 0.2f);
    for (int i = 0; i < kCount; ++i) {
        s[i] = coordinate(random);
        t[i] = coordinate(random);
        width[i] = footprint(random) * footprint(random) * 5.0f;
    }
    for (const TextureWrap wrap : {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror}) {
        std::vector<float> one[3], native[3];
        for (int c = 0; c < 3; ++c) {
            one[c].assign(kCount, -1.0f);
            native[c].assign(kCount, -2.0f);
        }
        lookups_of_width<1>(pyramid, wrap, s, t, width, one);
        lookups_of_width<packet::simd::kNativeLanes>(pyramid, wrap, s, t, width, native);
        // And whole batches of 256, as shading runs them.
        std::vector<float> batched[3];
        for (int c = 0; c < 3; ++c) batched[c].assign(kCount, -3.0f);
        constexpr int kBatch = textures::TrilinearBatch<packet::simd::kNativeLanes>::kMax;
        auto batch = std::make_unique<textures::TrilinearBatch<packet::simd::kNativeLanes>>();
        for (int i = 0; i < kCount; i += kBatch) {
            float* out[3] = {&batched[0][i], &batched[1][i], &batched[2][i]};
            batch->run(pyramid, wrap, wrap, true, kBatch, &s[i], &t[i], &width[i], out);
        }
        for (int c = 0; c < 3; ++c) {
            for (int i = 0; i < kCount; ++i) {
                ASSERT_EQ(std::bit_cast<std::uint32_t>(one[c][i]), std::bit_cast<std::uint32_t>(native[c][i]))
                    << "lookup " << i << " channel " << c;
                ASSERT_EQ(std::bit_cast<std::uint32_t>(one[c][i]), std::bit_cast<std::uint32_t>(batched[c][i]))
                    << "lookup " << i << " channel " << c << " in a batch";
            }
        }
    }
}

TEST(TextureFilter, SrgbDecodingFollowsTheExactCurve) {
    using F = packet::simd::Lanes<1>::F;
    double largest = 0.0;
    for (int i = -10; i <= 100010; ++i) {
        const float encoded = float(i) / 100000.0f;
        const double c = std::clamp(double(encoded), 0.0, 1.0);
        const double exact = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        largest = std::max(largest, std::abs(double(textures::srgb_decode<1>(F{encoded})[0]) - exact));
    }
    std::printf("sRGB decoding: largest difference from the exact curve %.3g\n", largest);
    EXPECT_LT(largest, 2e-7);
    EXPECT_EQ(textures::srgb_decode<1>(F{std::nanf("")})[0], 0.0f);
    EXPECT_EQ(textures::srgb_decode<1>(F{2.0f})[0], textures::srgb_decode<1>(F{1.0f})[0]);
}

TEST(TextureFilter, NonFiniteCoordinatesAndFootprintsReadInsideTheImage) {
    TexelArray image{.width = 8, .height = 8, .channels = 3, .floating = false, .bytes = {}};
    image.bytes.assign(8 * 8 * 3, 200);
    const textures::MipPyramid pyramid(image);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
    const float values[] = {nan, inf, -inf, 1e30f, -1e30f, 3e9f, 0.5f};
    for (const TextureWrap wrap : {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror}) {
        for (const float s : values) {
            for (const float width : values) {
                float r, g, b;
                float* out[3] = {&r, &g, &b};
                textures::trilinear_lookup<1>(pyramid, wrap, wrap, false, &s, &s, &width, out);
                EXPECT_NEAR(r, 200.0f / 255.0f, 1e-6f) << s << " " << width;
            }
        }
    }
}

}  // namespace
}  // namespace dynrt
