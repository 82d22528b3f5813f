// dynrt::save_image: the library's own image writer (stb_image_write, not OpenImageIO). Read
// back with stb_image: 8-bit files hold the sRGB encoding of the linear values, clamped; .hdr
// holds the floats; anything else is refused naming the file.

#include "api_test_world.h"

#include <gtest/gtest.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

std::filesystem::path scratch(const std::string& name) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "dynrt_save_image";
    std::filesystem::create_directories(dir);
    return dir / name;
}

// A 3x2 image: black, 18% grey, white; red over range, negative, NaN.
const std::vector<float> kPixels = {0.0f, 0.0f, 0.0f, 0.18f, 0.18f, 0.18f, 1.0f, 1.0f, 1.0f,
                                    4.0f, 0.0f, 0.0f, -1.0f, 0.5f, 0.0f, 0.0f, 0.0f, 0.25f};

TEST(ApiSaveImage, PngHoldsTheSrgbEncodingClamped) {
    const std::string path = scratch("pixels.png").string();
    save_image(path, 3, 2, kPixels);
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
    ASSERT_NE(data, nullptr);
    ASSERT_EQ(w, 3);
    ASSERT_EQ(h, 2);
    const auto srgb = [](float v) {
        v = std::fmin(std::fmax(v, 0.0f), 1.0f);
        const float e = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        return int(std::lround(255.0f * e));
    };
    for (int i = 0; i < 18; ++i) EXPECT_EQ(int(data[i]), srgb(kPixels[std::size_t(i)])) << i;
    EXPECT_EQ(int(data[3]), 118);  // 0.18 linear is sRGB 118/255
    stbi_image_free(data);
}

TEST(ApiSaveImage, HdrHoldsTheLinearFloats) {
    const std::string path = scratch("pixels.hdr").string();
    const std::vector<float> positive = {0.0f, 0.18f, 1.0f, 4.0f, 0.5f, 0.25f,
                                         2.0f, 0.75f, 0.125f, 8.0f, 1.5f, 0.0625f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f};
    save_image(path, 3, 2, positive);
    int w = 0, h = 0, channels = 0;
    float* data = stbi_loadf(path.c_str(), &w, &h, &channels, 3);
    ASSERT_NE(data, nullptr);
    // Radiance's shared-exponent format keeps about 8 bits per channel of the largest one.
    for (int i = 0; i < 18; ++i) {
        const std::size_t p = std::size_t(i / 3) * 3;
        const float largest = std::fmax(positive[p], std::fmax(positive[p + 1], positive[p + 2]));
        EXPECT_NEAR(data[i], positive[std::size_t(i)], largest / 128.0f) << i;
    }
    stbi_image_free(data);
}

TEST(ApiSaveImage, BadCallsNameTheFile) {
    expect_error([] { save_image(scratch("a.exr").string(), 3, 2, kPixels); },
                 Error::Code::invalid_argument, {"a.exr", "unknown image format"});
    expect_error([] { save_image(scratch("a.png").string(), 2, 2, kPixels); },
                 Error::Code::invalid_argument, {"a.png", "3 per pixel"});
    expect_error([] { save_image((scratch("no_such_folder") / "a.png").string(), 3, 2, kPixels); },
                 Error::Code::invalid_argument, {"does not exist"});
}

}  // namespace
}  // namespace dynrt::api_test
