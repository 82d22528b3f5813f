// Image metrics (engine/include/dynrt/bench/image_metrics.h): PSNR, SSIM (Wang et al. 2004)
// and the share of wrong pixels, on images whose answers can be worked out by hand.

#include "dynrt/bench/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace dynrt {
namespace {

DisplayImage uniform_image(int width, int height, float value) {
    DisplayImage image;
    image.width = width;
    image.height = height;
    image.rgb.assign(std::size_t(width) * height, glm::vec3(value));
    return image;
}

/// Values in [lo, hi] per channel, from a fixed seed.
DisplayImage random_image(int width, int height, float lo, float hi, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(lo, hi);
    DisplayImage image = uniform_image(width, height, 0.0f);
    for (glm::vec3& c : image.rgb) c = glm::vec3(value(rng), value(rng), value(rng));
    return image;
}

/// A smooth image with structure (a gradient and a ripple), in [0.1, 0.9].
DisplayImage smooth_image(int width, int height) {
    DisplayImage image = uniform_image(width, height, 0.0f);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float v = 0.5f + 0.25f * std::sin(0.3f * x) * std::cos(0.2f * y) +
                            0.15f * (float(x) / width - 0.5f);
            image.rgb[std::size_t(y) * width + x] = glm::vec3(v, 0.8f * v, 0.6f * v + 0.1f);
        }
    }
    return image;
}

DisplayImage with_noise(DisplayImage image, float amplitude, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-amplitude, amplitude);
    for (glm::vec3& c : image.rgb) {
        for (int k = 0; k < 3; ++k) c[k] = std::clamp(c[k] + noise(rng), 0.0f, 1.0f);
    }
    return image;
}

TEST(ImageMetrics, IdenticalImagesArePerfect) {
    const DisplayImage a = random_image(32, 24, 0.0f, 1.0f);
    const ImageMetrics m = compare_images(a, a);
    EXPECT_EQ(m.mse, 0.0);
    EXPECT_EQ(m.psnr_db, std::numeric_limits<double>::infinity());
    EXPECT_EQ(m.ssim, 1.0);  // exactly: every window's two factors are equal
    EXPECT_EQ(m.wrong_pixels, 0u);
    EXPECT_EQ(m.wrong_share, 0.0);
}

TEST(ImageMetrics, UniformOffsetGivesThePsnrOfItsSquare) {
    // Every channel of every pixel 0.0625 (2^-4, exact in float) brighter: MSE = 2^-8.
    const DisplayImage a = random_image(20, 16, 0.1f, 0.8f);
    DisplayImage b = a;
    for (glm::vec3& c : b.rgb) c += glm::vec3(0.0625f);
    EXPECT_NEAR(mean_squared_error(b, a), 1.0 / 256.0, 1e-9);
    EXPECT_NEAR(psnr_db(b, a), 10.0 * std::log10(256.0), 1e-6);  // 24.08 dB
    EXPECT_NEAR(psnr_from_mse(0.01), 20.0, 1e-12);
}

TEST(ImageMetrics, SsimOfConstantImagesIsTheLuminanceTerm) {
    // No variance in either image: the structure factor is C2 / C2 and SSIM is
    // (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1) in every window, with grey luma = the value.
    const DisplayImage a = uniform_image(16, 13, 0.5f);
    const DisplayImage b = uniform_image(16, 13, 0.25f);
    const double c1 = 0.01 * 0.01;
    const double expected = (2 * 0.5 * 0.25 + c1) / (0.5 * 0.5 + 0.25 * 0.25 + c1);
    EXPECT_NEAR(ssim(a, b), expected, 1e-12);  // 0.80006...
    EXPECT_NEAR(ssim(uniform_image(11, 11, 0.0f), uniform_image(11, 11, 1.0f)),
                c1 / (1.0 + c1), 1e-12);
}

/// SSIM straight from the paper's definitions (eqs. 14-16 and 13): a 2D Gaussian window
/// normalised over its 121 weights, deviations taken from the window's mean, every window
/// position inside the image; no separable passes, no E[x^2] - mu^2 shortcut.
double direct_ssim(const DisplayImage& a, const DisplayImage& b) {
    const auto luma = [](const glm::vec3& c) { return 0.299 * c.x + 0.587 * c.y + 0.114 * c.z; };
    double w[11][11];
    double total = 0.0;
    for (int i = 0; i < 11; ++i) {
        for (int j = 0; j < 11; ++j) {
            w[i][j] = std::exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / (2.0 * 1.5 * 1.5));
            total += w[i][j];
        }
    }
    const double c1 = 0.0001, c2 = 0.0009;
    double sum = 0.0;
    int windows = 0;
    for (int y0 = 0; y0 + 11 <= a.height; ++y0) {
        for (int x0 = 0; x0 + 11 <= a.width; ++x0) {
            const auto at = [&](const DisplayImage& im, int i, int j) {
                return luma(im.rgb[std::size_t(y0 + i) * im.width + x0 + j]);
            };
            double mx = 0, my = 0;
            for (int i = 0; i < 11; ++i) {
                for (int j = 0; j < 11; ++j) {
                    mx += w[i][j] / total * at(a, i, j);
                    my += w[i][j] / total * at(b, i, j);
                }
            }
            double vx = 0, vy = 0, cxy = 0;
            for (int i = 0; i < 11; ++i) {
                for (int j = 0; j < 11; ++j) {
                    const double dx = at(a, i, j) - mx, dy = at(b, i, j) - my;
                    vx += w[i][j] / total * dx * dx;
                    vy += w[i][j] / total * dy * dy;
                    cxy += w[i][j] / total * dx * dy;
                }
            }
            sum += (2 * mx * my + c1) * (2 * cxy + c2) /
                   ((mx * mx + my * my + c1) * (vx + vy + c2));
            ++windows;
        }
    }
    return sum / windows;
}

TEST(ImageMetrics, SsimMatchesThePapersWindowedFormula) {
    const DisplayImage clean = smooth_image(19, 14);
    for (float amplitude : {0.01f, 0.1f, 0.4f}) {
        const DisplayImage noisy = with_noise(clean, amplitude, 3);
        EXPECT_NEAR(ssim(noisy, clean), direct_ssim(noisy, clean), 1e-9) << amplitude;
    }
    const DisplayImage a = random_image(12, 16, 0.0f, 1.0f, 4);
    const DisplayImage b = random_image(12, 16, 0.2f, 0.7f, 5);
    EXPECT_NEAR(ssim(a, b), direct_ssim(a, b), 1e-9);
}

TEST(ImageMetrics, SsimIsSymmetricAndDropsWithNoise) {
    const DisplayImage clean = smooth_image(48, 40);
    const DisplayImage light = with_noise(clean, 0.02f, 1);
    const DisplayImage heavy = with_noise(clean, 0.2f, 2);
    const double s_light = ssim(light, clean);
    const double s_heavy = ssim(heavy, clean);
    EXPECT_NEAR(s_light, ssim(clean, light), 1e-12);
    EXPECT_NEAR(s_heavy, ssim(clean, heavy), 1e-12);
    EXPECT_LT(s_light, 1.0);
    EXPECT_GT(s_light, 0.8);
    EXPECT_LT(s_heavy, 0.5);
    EXPECT_LT(psnr_db(heavy, clean), psnr_db(light, clean));
}

TEST(ImageMetrics, WrongPixelsCountExactlyTheAlteredOnes) {
    // Reference values on exact 8-bit steps, so that a change of k steps is k steps.
    DisplayImage reference = uniform_image(11, 11, 0.0f);
    for (std::size_t i = 0; i < reference.rgb.size(); ++i) {
        reference.rgb[i] = glm::vec3(float(50 + i) / 255.0f, 100.0f / 255.0f, float(i) / 255.0f);
    }
    DisplayImage test = reference;
    // One step in any channel is not wrong: float rounding alone can cause it.
    for (std::size_t i = 0; i < test.rgb.size(); i += 2) test.rgb[i].x += 1.0f / 255.0f;
    // Two steps, in one channel each, are: 7 pixels.
    const std::size_t altered[] = {3, 11, 20, 47, 58, 90, 120};
    for (std::size_t k = 0; k < 7; ++k) {
        test.rgb[altered[k]][int(k % 3)] += (k % 2 ? -2.0f : 2.0f) / 255.0f;
    }
    EXPECT_EQ(wrong_pixels(test, reference), 7u);
    EXPECT_EQ(wrong_pixels(reference, test), 7u);
    EXPECT_DOUBLE_EQ(compare_images(test, reference).wrong_share, 7.0 / 121.0);
}

TEST(ImageMetrics, DisplayImageClampsAndEncodesAsTheImageFiles) {
    RenderedFrame frame;
    frame.width = 3;
    frame.height = 1;
    frame.color = {glm::vec3(2.0f, -1.0f, 0.5f), glm::vec3(0.0f), glm::vec3(1.0f)};
    const DisplayImage image = display_image(frame);
    ASSERT_EQ(image.rgb.size(), 3u);
    EXPECT_NEAR(image.rgb[0].x, 1.0f, 1e-6);  // 1.055 - 0.055 in float
    EXPECT_EQ(image.rgb[0].y, 0.0f);
    // sRGB: 1.055 * 0.5^(1/2.4) - 0.055.
    EXPECT_NEAR(image.rgb[0].z, 1.055 * std::pow(0.5, 1.0 / 2.4) - 0.055, 1e-6);
    EXPECT_EQ(image.rgb[1], glm::vec3(0.0f));
    EXPECT_NEAR(image.rgb[2].x, 1.0f, 1e-6);
    frame.color.pop_back();
    EXPECT_THROW(display_image(frame), std::invalid_argument);
}

TEST(ImageMetrics, SizeMismatchAndTooSmallImagesThrow) {
    const DisplayImage a = uniform_image(16, 16, 0.5f);
    const DisplayImage b = uniform_image(16, 15, 0.5f);
    EXPECT_THROW(mean_squared_error(a, b), std::invalid_argument);
    EXPECT_THROW(psnr_db(a, b), std::invalid_argument);
    EXPECT_THROW(ssim(a, b), std::invalid_argument);
    EXPECT_THROW(wrong_pixels(a, b), std::invalid_argument);
    EXPECT_THROW(compare_images(b, a), std::invalid_argument);
    const DisplayImage small = uniform_image(10, 16, 0.5f);
    EXPECT_THROW(ssim(small, small), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
