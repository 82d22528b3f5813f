#pragma once
// Samples per pixel (docs/rendering.md "Samples per pixel and area lights"): how many rays a
// pixel's colour is the mean of, where in and around the pixel they go, and which pixels take
// them all.
//
// - Where: sample s of pixel p is point s of a (0,2)-sequence in base 2 (Sobol's first two
//   dimensions), scrambled per pixel by a random XOR of its digits (Kollig and Keller 2002,
//   "Efficient multidimensional sampling"). The first 2^k samples of every pixel then fall one
//   in each of the 2^k strata of each elementary interval (4x4 cells for 16 samples, and 2x8,
//   8x2 too); the scramble is a hash of the pixel alone, so a frame renders the same bits on
//   any number of threads, and a pixel whose scene is unchanged takes the same samples frame
//   after frame. Area lights draw their points from the same sequence, scrambled by another
//   hash and in another order.
// - Reconstruction: filter importance sampling (Ernst et al. 2006, as pbrt-v4 does): each
//   sample is moved from the pixel's centre by the filter's distribution on each axis, and the
//   pixel is the plain mean of its samples; every sample's weight is 1/n, so the weights sum
//   to one and no sample reaches another pixel's sum (tiles stay independent).
// - Adaptive: with `adaptive_contrast` > 0 every pixel first takes sample 0; the pixels that
//   differ from a neighbour (in colour by more than the contrast, or in the object or the
//   triangle's facing they show) take the other spp - 1 (Whitted 1980 refined where
//   neighbours differed).
//
// One sample per pixel (the default) is the pixel's centre, as before: the same bits as a
// renderer without samples.

#include <cstdint>
#include <string>
#include <string_view>

namespace dynrt {

/// The reconstruction filter: its samples' distribution around the pixel's centre.
///   box              uniform over the pixel (1 pixel wide);
///   tent             triangle of radius 1 pixel;
///   blackman_harris  Blackman-Harris window 1.5 pixels wide (Blender Cycles' default): as
///                    sharp as the box and without its aliasing. The default.
enum class PixelFilter : std::uint8_t { box, tent, blackman_harris };

/// "box", "tent", "blackman-harris".
const char* pixel_filter_name(PixelFilter filter);
/// Reads a pixel_filter_name; throws std::invalid_argument naming the text and the choices.
PixelFilter parse_pixel_filter(std::string_view text);

/// TraceSettings::sampling.
struct PixelSampling {
    /// Samples per pixel, 1 to kMaxSamplesPerPixel. Powers of two are stratified best.
    int spp = 1;
    PixelFilter filter = PixelFilter::blackman_harris;
    /// 0: every pixel takes `spp` samples. Above 0: every pixel takes one, and those whose
    /// colour differs from a 4-neighbour's by more than this (in any channel, after clamping
    /// to [0, 1]), or that show another object or another side of a triangle, take `spp`.
    float adaptive_contrast = 0.0f;

    static constexpr int kMaxSamplesPerPixel = 4096;

    bool operator==(const PixelSampling&) const = default;
};

/// Throws std::invalid_argument naming the bad value: spp outside [1, 4096], a contrast
/// negative or not finite.
void check_sampling(const PixelSampling& sampling);

/// What `--spp` shows: "16", "16 blackman-harris", "16 adaptive 0.05".
std::string to_string(const PixelSampling& sampling);

}  // namespace dynrt
