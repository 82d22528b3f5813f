#pragma once
// How far a dynrt::Renderer frame is from the exact reference, measured on a sample of its
// pixels: the brute-force reference costs about a millisecond per pixel on a scene of ~40k
// triangles, so a full 1024x1024 reference frame is out of reach, but one pixel per 8x8 block
// is not. The sample is stratified (one pixel chosen at random in every block), so every part
// of the image is represented and no regular pattern lines up with the 16x16 tiles or the
// adaptive sampler's 4-pixel grid.

#include "dynrt/reference/reference_renderer.h"

#include "dynrt/engine/renderer.h"

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace dynrt::reference {

/// The seed of the sample unless one is given: fixed, so runs measure the same pixels.
inline constexpr std::uint64_t kDefaultSampleSeed = 0x5eed'd7a7'0006ull;

/// One pixel chosen at random in every `block` x `block` square of a `width` x `height` image
/// (squares cut at the right and bottom edges hold one pixel too), row-major by square. The
/// choice depends only on the seed and the square, not on the order of evaluation. block 1
/// gives every pixel in row-major order. Throws std::invalid_argument for a size or block < 1.
std::vector<PixelCoord> stratified_pixels(int width, int height, int block,
                                          std::uint64_t seed = kDefaultSampleSeed);

/// A frame's error over the sampled pixels.
struct FrameError {
    int samples = 0;
    /// Samples whose reference hit is ambiguous (kPrimitive or kAny).
    int ambiguous_samples = 0;
    /// Samples whose hit differs from the reference's: hit/miss, object or primitive.
    int hit_differs = 0;
    /// Of them, those the reference says no correct float tracer may get otherwise: any
    /// difference on a kNone pixel, hit/miss or object on a kPrimitive pixel. Exact settings
    /// must give 0.
    int determined_differs = 0;
    /// Of them, those the reference allows (hit_differs - determined_differs).
    int ambiguous_differs = 0;
    /// Mean squared difference of the linear RGB colour, per channel, over all samples.
    double mse = 0.0;
    double rmse = 0.0;
    /// 10 log10(1 / mse), peak 1; +inf when mse is 0.
    double psnr_db = std::numeric_limits<double>::infinity();

    /// determined_differs as a fraction of the samples (0 with no samples).
    double determined_share() const {
        return samples > 0 ? double(determined_differs) / double(samples) : 0.0;
    }
};

/// Compares `got` at `pixels` with `reference` (one entry per pixel, as render_reference_pixels
/// returns). `got` must have its hit buffers (RenderOptions::hit_buffers). Throws
/// std::invalid_argument when the spans' lengths differ, a buffer of `got` is missing or has
/// the wrong size, or a pixel is outside it.
FrameError frame_error(const RenderedFrame& got, std::span<const PixelCoord> pixels,
                       std::span<const ReferencePixel> reference);

/// PSNR for people: "inf" for +inf, else one decimal ("48.3").
std::string format_psnr(double psnr_db);

}  // namespace dynrt::reference
