#pragma once
// `dynrt bench --error`: each configuration's run time beside its error against the exact
// reference image of the same frame, measured on a stratified sample of pixels (frame_error.h).
// The reference depends on the frame and the view, not on the configuration: it is rendered
// once and shared by every row, and its time is reported apart from theirs.

#include "dynrt/reference/frame_error.h"
#include "dynrt/reference/reference_renderer.h"

#include "dynrt/bench/bench.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/scene.h"

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace dynrt::reference {

/// The reference at a sample of one frame's pixels.
struct SampledReference {
    int frame = 0;
    int width = 0;
    int height = 0;
    int block = 1;  ///< one sample per block x block square
    std::vector<PixelCoord> pixels;
    std::vector<ReferencePixel> values;  ///< one per pixel
    /// Wall time of posing the frame, building the brute-force tracer and rendering the samples.
    double ms = 0.0;
};

/// Poses `scene` at `frame` with `options.pose`, and renders the reference at
/// stratified_pixels(options.width, options.height, block, seed) through `camera` with the
/// lights, background and ambient of `options` (shading_from). Throws as pose_scene,
/// stratified_pixels and render_reference_pixels do.
SampledReference sample_reference(const Scene& scene, const Camera& camera,
                                  const RenderOptions& options, int frame, int block,
                                  std::uint64_t seed = kDefaultSampleSeed);

/// One configuration measured: RenderOptions (build config, packet culling, adaptive tolerance)
/// and how the measured frame's trees come about.
struct ErrorConfiguration {
    RenderOptions options;
    BenchUpdate update = BenchUpdate::rebuild;
};

/// A configuration's timings (bench_configuration of the reference's frame) and error.
struct ErrorRow {
    BenchRow timing;
    BenchUpdate update = BenchUpdate::rebuild;
    int frame = 0;
    FrameError error;
};

/// Times `config` on `reference.frame` (bench_configuration with `repeat` and `warmup`) and
/// measures the error of the frame it rendered against `reference`. `options.width` and
/// `height` must be the reference's. Throws std::invalid_argument when they are not.
ErrorRow bench_error_row(const Scene& scene, const Camera& camera,
                         const ErrorConfiguration& config, int repeat, int warmup,
                         const SampledReference& reference);

/// A short name per row naming only what varies across `rows` (cost ratio, leaf size,
/// culling, update, adaptive tolerance), e.g. "cost 0.1, none"; "default" when nothing varies.
std::vector<std::string> error_row_labels(const std::vector<ErrorRow>& rows);

/// The table for people: the configuration columns, total ms "median (min-max)", the share of
/// samples whose hit differs where the reference says it is determined, the count of those
/// where it allows a difference, RMSE and PSNR.
void print_error_table(std::ostream& out, const std::vector<ErrorRow>& rows);

/// One line about the reference: frame, samples, block, time.
void print_reference_line(std::ostream& out, const SampledReference& reference);

/// bench_csv's columns plus update, frame, samples, ambiguous_samples, hit_differs,
/// determined_differs, ambiguous_differs, hit_differs_determined_pct, rmse, psnr_db ("inf"
/// when infinite).
std::string error_csv(const std::vector<ErrorRow>& rows);

/// bench_json's rows, each with the same error fields (psnr_db null when infinite), and a
/// "reference" object: frame, width, height, block, samples, ms.
std::string error_json(const std::vector<ErrorRow>& rows, const SampledReference& reference);

}  // namespace dynrt::reference
