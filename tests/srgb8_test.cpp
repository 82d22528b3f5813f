// The 8-bit sRGB encoder (engine/src/output/srgb8.h) gives the bytes of the float path it
// replaced, srgb_encode then OpenImageIO's conversion to UINT8, for every input tried: each
// step edge and its neighbours, a million random floats in [0, 1], and the values outside it.
// Images written through it decode to the pixels of the float path.

#include "dynrt/engine/image_output.h"
#include "output/srgb.h"
#include "output/srgb8.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <vector>

namespace dynrt {
namespace srgb8_test {

/// The float path: srgb_encode into floats, converted to UINT8 by OpenImageIO itself.
std::vector<std::uint8_t> by_float_path(const std::vector<float>& linear) {
    std::vector<float> encoded(linear.size());
    for (std::size_t i = 0; i < linear.size(); ++i) encoded[i] = srgb_encode(linear[i]);
    std::vector<std::uint8_t> out(linear.size());
    EXPECT_TRUE(OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, encoded.data(),
                                           OIIO::TypeDesc::UINT8, out.data(), int(out.size())));
    return out;
}

void expect_same_codes(const std::vector<float>& linear) {
    const std::vector<std::uint8_t> expected = by_float_path(linear);
    for (std::size_t i = 0; i < linear.size(); ++i) {
        ASSERT_EQ(int(srgb8_encode(linear[i])), int(expected[i]))
            << "linear " << linear[i] << " (bits " << std::hex << std::bit_cast<std::uint32_t>(linear[i]) << ")";
    }
}

TEST(Srgb8, EveryStepEdgeAndItsNeighboursEncodeAsTheFloatPath) {
    // The edges are where the float path's code goes up: found here by walking the codes of a
    // fine sweep, independently of the encoder's own search.
    constexpr std::uint32_t kStep = 499;
    std::vector<float> inputs;
    std::uint8_t previous = 0;
    for (std::uint32_t bits = 0; bits <= 0x3f800000u; bits += kStep) {
        const float x = std::bit_cast<float>(bits);
        const std::uint8_t code = std::uint8_t(std::lround(srgb_encode(x) * 255.0f));
        if (code != previous) {
            // The edge lies within the last kStep patterns: take them all, and a few past.
            for (std::uint32_t b = bits - kStep; b <= bits + 4; ++b) inputs.push_back(std::bit_cast<float>(b));
            previous = code;
        }
    }
    EXPECT_GE(inputs.size(), 255u * kStep);
    expect_same_codes(inputs);
}

TEST(Srgb8, RandomValuesAndOutOfRangeOnesEncodeAsTheFloatPath) {
    std::mt19937 random(34);
    std::uniform_int_distribution<std::uint32_t> bits(0, 0x3f800000u);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<float> inputs;
    for (int i = 0; i < 500000; ++i) inputs.push_back(std::bit_cast<float>(bits(random)));
    for (int i = 0; i < 500000; ++i) inputs.push_back(uniform(random));
    for (const float x : {0.0f, -0.0f, -1.0f, 1.0f, 1.5f, 1e30f, std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::denorm_min(),
                          0.0031308f, std::nextafter(1.0f, 0.0f)}) {
        inputs.push_back(x);
    }
    expect_same_codes(inputs);
    EXPECT_EQ(srgb8_encode(std::numeric_limits<float>::quiet_NaN()), 0);
}

TEST(Srgb8, PngFilesDecodeToTheFloatPathsPixels) {
    RenderedFrame frame;
    frame.width = 37;
    frame.height = 23;
    std::mt19937 random(7);
    std::uniform_real_distribution<float> value(-0.1f, 1.1f);
    for (int i = 0; i < frame.width * frame.height; ++i) {
        frame.color.emplace_back(value(random), value(random), value(random));
    }
    const std::filesystem::path path = std::filesystem::path(testing::TempDir()) / "dynrt_srgb8.png";
    write_image(path, frame);
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    std::vector<std::uint8_t> decoded(frame.color.size() * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, decoded.data()));
    std::vector<float> linear;
    for (const glm::vec3& c : frame.color) linear.insert(linear.end(), {c.x, c.y, c.z});
    EXPECT_EQ(decoded, by_float_path(linear));
}

}  // namespace srgb8_test
}  // namespace dynrt
