// Image metrics against a reference image. SSIM: Z. Wang, A. C. Bovik, H. R. Sheikh and
// E. P. Simoncelli, "Image quality assessment: from error visibility to structural
// similarity", IEEE Transactions on Image Processing 13(4), 600-612, 2004.

#include "dynrt/bench/image_metrics.h"

#include "output/srgb.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

namespace dynrt {

namespace {

// The paper's parameters (section III.C): an 11x11 Gaussian window of standard deviation 1.5
// samples, K1 = 0.01, K2 = 0.03, dynamic range L = 1 for encoded values in [0, 1].
constexpr int kWindow = 11;
constexpr double kWindowSigma = 1.5;
constexpr double kC1 = (0.01 * 1.0) * (0.01 * 1.0);
constexpr double kC2 = (0.03 * 1.0) * (0.03 * 1.0);

void check_sizes(const DisplayImage& test, const DisplayImage& reference, const char* what) {
    if (test.width != reference.width || test.height != reference.height) {
        throw std::invalid_argument(std::string(what) + ": the image is " +
                                    std::to_string(test.width) + "x" +
                                    std::to_string(test.height) + ", the reference " +
                                    std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height));
    }
}

/// The window's 1D weights: the 2D Gaussian is their outer product, so it is applied as a
/// row pass then a column pass. Normalised to sum 1 (then the 2D window sums to 1 too).
std::array<double, kWindow> gaussian_weights() {
    std::array<double, kWindow> w{};
    double sum = 0.0;
    for (int k = 0; k < kWindow; ++k) {
        const double d = k - kWindow / 2;
        w[k] = std::exp(-d * d / (2.0 * kWindowSigma * kWindowSigma));
        sum += w[k];
    }
    for (double& v : w) v /= sum;
    return w;
}

std::vector<double> luma(const DisplayImage& image) {
    std::vector<double> y(image.rgb.size());
    for (std::size_t i = 0; i < y.size(); ++i) {
        const glm::vec3& c = image.rgb[i];
        y[i] = 0.299 * c.x + 0.587 * c.y + 0.114 * c.z;
    }
    return y;
}

int to_8bit(float encoded) { return int(std::lround(encoded * 255.0f)); }

}  // namespace

DisplayImage display_image(const RenderedFrame& frame) {
    if (frame.width < 0 || frame.height < 0 ||
        frame.color.size() != std::size_t(frame.width) * std::size_t(frame.height)) {
        throw std::invalid_argument("display_image: " + std::to_string(frame.color.size()) +
                                    " colours for a " + std::to_string(frame.width) + "x" +
                                    std::to_string(frame.height) + " frame");
    }
    DisplayImage image;
    image.width = frame.width;
    image.height = frame.height;
    image.rgb.resize(frame.color.size());
    tbb::parallel_for(std::size_t(0), frame.color.size(), [&](std::size_t i) {
        const glm::vec3& c = frame.color[i];
        image.rgb[i] = glm::vec3(srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z));
    });
    return image;
}

double mean_squared_error(const DisplayImage& test, const DisplayImage& reference) {
    check_sizes(test, reference, "mean_squared_error");
    if (test.rgb.empty()) return 0.0;
    double sum = 0.0;
    for (std::size_t i = 0; i < test.rgb.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double d = double(test.rgb[i][c]) - double(reference.rgb[i][c]);
            sum += d * d;
        }
    }
    return sum / (3.0 * double(test.rgb.size()));
}

double psnr_from_mse(double mse) {
    return mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

double psnr_db(const DisplayImage& test, const DisplayImage& reference) {
    return psnr_from_mse(mean_squared_error(test, reference));
}

double ssim(const DisplayImage& test, const DisplayImage& reference) {
    check_sizes(test, reference, "ssim");
    if (test.width < kWindow || test.height < kWindow) {
        throw std::invalid_argument("ssim: the image is " + std::to_string(test.width) + "x" +
                                    std::to_string(test.height) + ", smaller than the " +
                                    std::to_string(kWindow) + "x" + std::to_string(kWindow) +
                                    " window");
    }
    const std::array<double, kWindow> w = gaussian_weights();
    const std::vector<double> x = luma(test);
    const std::vector<double> y = luma(reference);
    const int width = test.width;
    const int height = test.height;
    const int out_width = width - kWindow + 1;
    const int out_height = height - kWindow + 1;

    // Row pass: for every row and every window position along it, the weighted sums of x, y,
    // x^2, y^2 and xy. The column pass then completes the 2D window.
    constexpr int kMoments = 5;
    std::vector<double> rows(std::size_t(kMoments) * height * out_width);
    const auto row_moment = [&](int m, int r, int c) -> double& {
        return rows[(std::size_t(m) * height + r) * out_width + c];
    };
    tbb::parallel_for(0, height, [&](int r) {
        const double* xr = x.data() + std::size_t(r) * width;
        const double* yr = y.data() + std::size_t(r) * width;
        for (int c = 0; c < out_width; ++c) {
            double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
            for (int k = 0; k < kWindow; ++k) {
                const double a = xr[c + k], b = yr[c + k];
                sx += w[k] * a;
                sy += w[k] * b;
                sxx += w[k] * a * a;
                syy += w[k] * b * b;
                sxy += w[k] * a * b;
            }
            row_moment(0, r, c) = sx;
            row_moment(1, r, c) = sy;
            row_moment(2, r, c) = sxx;
            row_moment(3, r, c) = syy;
            row_moment(4, r, c) = sxy;
        }
    });

    // Column pass and the SSIM map, summed per output row; the rows are then added in order,
    // so the result does not depend on the thread schedule.
    std::vector<double> row_sums(out_height);
    tbb::parallel_for(0, out_height, [&](int r) {
        double sum = 0.0;
        for (int c = 0; c < out_width; ++c) {
            double m[kMoments] = {};
            for (int k = 0; k < kWindow; ++k) {
                for (int i = 0; i < kMoments; ++i) m[i] += w[k] * row_moment(i, r + k, c);
            }
            const double mu_x = m[0], mu_y = m[1];
            // sigma_x^2 = E[x^2] - mu_x^2 etc. (the window weights sum to 1).
            const double var_x = m[2] - mu_x * mu_x;
            const double var_y = m[3] - mu_y * mu_y;
            const double cov = m[4] - mu_x * mu_y;
            sum += ((2.0 * mu_x * mu_y + kC1) * (2.0 * cov + kC2)) /
                   ((mu_x * mu_x + mu_y * mu_y + kC1) * (var_x + var_y + kC2));
        }
        row_sums[r] = sum;
    });
    double total = 0.0;
    for (double s : row_sums) total += s;
    return total / (double(out_width) * double(out_height));
}

std::size_t wrong_pixels(const DisplayImage& test, const DisplayImage& reference) {
    check_sizes(test, reference, "wrong_pixels");
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < test.rgb.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            if (std::abs(to_8bit(test.rgb[i][c]) - to_8bit(reference.rgb[i][c])) > 1) {
                ++wrong;
                break;
            }
        }
    }
    return wrong;
}

ImageMetrics compare_images(const DisplayImage& test, const DisplayImage& reference) {
    ImageMetrics m;
    m.ssim = ssim(test, reference);  // first: it checks the sizes and the window
    m.mse = mean_squared_error(test, reference);
    m.psnr_db = psnr_from_mse(m.mse);
    m.wrong_pixels = wrong_pixels(test, reference);
    m.wrong_share = test.rgb.empty() ? 0.0 : double(m.wrong_pixels) / double(test.rgb.size());
    return m;
}

}  // namespace dynrt
