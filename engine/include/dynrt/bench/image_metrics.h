#pragma once
// How far an image is from a reference image, as a display shows them: PSNR, SSIM and the
// share of pixels whose 8-bit value is visibly wrong. `dynrt bench --frames --error` compares
// each frame of an approximate mode (pixel reuse, adaptive sampling) with the full render of the
// same frame through these.
//
// SSIM follows Z. Wang, A. C. Bovik, H. R. Sheikh and E. P. Simoncelli, "Image quality
// assessment: from error visibility to structural similarity", IEEE Transactions on Image
// Processing 13(4), 600-612, 2004 (eq. 13 with the paper's parameters; see ssim()).

#include "dynrt/engine/renderer.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace dynrt {

/// An image as its 8-bit file shows it: each linear colour channel clamped to [0, 1] and
/// sRGB-encoded (IEC 61966-2-1), as the PNG writer does before it quantises to 8 bits.
/// Row-major, y = 0 the top row, width * height values.
struct DisplayImage {
    int width = 0;
    int height = 0;
    std::vector<glm::vec3> rgb;  ///< sRGB-encoded, each channel in [0, 1]
};

/// `frame`'s colour as a display shows it. Throws std::invalid_argument when the colour buffer
/// does not hold width * height pixels.
DisplayImage display_image(const RenderedFrame& frame);

/// Mean over pixels and channels of the squared difference of the encoded values.
/// Throws std::invalid_argument when the sizes differ (for every function below too).
double mean_squared_error(const DisplayImage& test, const DisplayImage& reference);

/// 10 log10(1 / mse) in dB, peak 1; +infinity when mse is 0.
double psnr_from_mse(double mse);

/// psnr_from_mse(mean_squared_error(test, reference)).
double psnr_db(const DisplayImage& test, const DisplayImage& reference);

/// Mean SSIM (Wang et al. 2004, eq. 13 averaged over windows) of the luma of the encoded images,
/// Y' = 0.299 R' + 0.587 G' + 0.114 B' (Rec. 601, as the paper's reference code converts colour
/// to grey):
///   SSIM(x, y) = (2 mu_x mu_y + C1)(2 sigma_xy + C2) / ((mu_x^2 + mu_y^2 + C1)(sigma_x^2 +
///   sigma_y^2 + C2)),  C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 1,
/// with means, variances and covariance weighted by an 11x11 circular-symmetric Gaussian window
/// (sigma 1.5, normalised to sum 1), at every position where the window lies inside the image
/// (no padding, no downsampling). 1 exactly for identical images; symmetric in its arguments;
/// in [-1, 1]. Throws std::invalid_argument, besides a size mismatch, for an image smaller
/// than the 11x11 window.
double ssim(const DisplayImage& test, const DisplayImage& reference);

/// Pixels counted as wrong: some channel's 8-bit value (round(255 x encoded), as the PNG writer
/// stores it) differs from the reference's by more than 1. A difference of one step is not
/// counted: it is what float rounding alone can cause, and no one sees it.
std::size_t wrong_pixels(const DisplayImage& test, const DisplayImage& reference);

/// The four measures of one image against its reference.
struct ImageMetrics {
    double mse = 0.0;
    double psnr_db = 0.0;  ///< +infinity when mse is 0
    double ssim = 1.0;
    std::size_t wrong_pixels = 0;
    double wrong_share = 0.0;  ///< wrong_pixels / (width * height), in [0, 1]
};

/// All of them. Throws as ssim() does.
ImageMetrics compare_images(const DisplayImage& test, const DisplayImage& reference);

}  // namespace dynrt
