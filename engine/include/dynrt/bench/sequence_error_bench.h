#pragma once
// `dynrt bench --frames A-B --error`: run time against error over a whole sequence. Each
// configuration (a pixel reuse mode and budget, an adaptive sampling tolerance) renders the
// frames in order with a renderer of its own, as an application would (the reuse modes build
// on the previous frame), and each of its frames is compared with the full render of the same
// frame (reuse off, no adaptive sampling) through image_metrics.h: PSNR, SSIM and the share of
// wrong pixels. The full renders are timed too: they are the baseline every speed-up is
// measured against.

#include "dynrt/bench/bench_plot.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/sequence.h"
#include "dynrt/engine/spread.h"
#include "dynrt/scene/scene.h"

#include <cstddef>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace dynrt {

/// One frame of one configuration against the full render of that frame.
struct SequenceErrorFrame {
    int frame = 0;
    double total_ms = 0.0;  ///< FrameStats::total_ms
    /// +infinity when the frame equals the full render.
    double psnr_db = std::numeric_limits<double>::infinity();
    double ssim = 1.0;
    double wrong_share = 0.0;  ///< image_metrics.h's wrong pixels over all pixels
    std::size_t pixels_traced = 0;  ///< FrameStats::pixels_traced
    std::size_t pixels_reused = 0;  ///< FrameStats::pixels_reused
};

/// One configuration over the sequence (every frame of every run is one sample).
struct SequenceErrorRow {
    /// What distinguishes the configuration: its reuse setting as --reuse reads it, then
    /// " + adaptive T" when it samples adaptively ("exact", "cache:0.25", "off + adaptive 0.05");
    /// no commas, so it stays one CSV field.
    std::string label;
    ReuseSettings reuse;
    float adaptive_tolerance = 0.0f;
    /// RenderOptions::lod_pixels (label: " + lod P" when above 0).
    float lod_pixels = 0.0f;
    /// Samples per pixel and adaptive anti-aliasing (label: " + 16 spp", " + 16 spp aa 0.05").
    PixelSampling sampling;
    Spread total_ms;  ///< ms per frame, median (min-max)
    double mean_ms = 0.0;
    /// The full render's median ms per frame over this one's (1 for the full render itself).
    double speedup = 1.0;
    /// 10 log10(1 / MSE) with the MSE averaged over every frame: a mean that stays finite
    /// when some frames are exact (+infinity only when all are).
    double psnr_db = 0.0;
    double worst_psnr_db = 0.0;  ///< the lowest frame's PSNR
    int worst_psnr_frame = 0;    ///< and its frame (the first such)
    double mean_ssim = 1.0;
    double min_ssim = 1.0;
    int min_ssim_frame = 0;
    double mean_wrong_share = 0.0;
    double max_wrong_share = 0.0;
    int max_wrong_frame = 0;
    double mean_pixels_traced = 0.0;
    double mean_pixels_reused = 0.0;
    std::vector<SequenceErrorFrame> frames;  ///< in the order rendered
};

/// The full renders (`reference`, whose errors are 0 by definition) and every configuration.
struct SequenceErrorBench {
    SequenceErrorRow reference;
    std::vector<SequenceErrorRow> rows;
    FrameRange range;
    int runs = 1;
    int width = 0;
    int height = 0;
};

/// `base` as the exact full render: reuse off, adaptive tolerance 0, base's own samples per
/// pixel without adaptive anti-aliasing (`--spp 256` makes it a converged reference for the
/// sampling settings the rows sweep).
RenderOptions full_render_options(const RenderOptions& base);

/// Renders frames `range` of `scene` `runs` times (each run from empty trees and a new
/// renderer per configuration, as a new sequence would), seen through `view`. Within a run the
/// frames go in order and in lockstep: frame f is rendered first by the full-render renderer
/// (full_render_options(base)), then by each configuration's own renderer, and each of those
/// frames is compared with the full render at once, so only one full frame is kept. Before
/// the runs, the first frame is rendered `warmup` times untimed by a throwaway renderer of
/// each. `configs` (non-empty) must all have `base`'s image size. Throws
/// std::invalid_argument for no configuration, a size mismatch, runs < 1, a scene camera the
/// scene does not have, or an image smaller than SSIM's 11x11 window.
SequenceErrorBench bench_sequence_error(const Scene& scene, const CameraSource& view,
                                        const RenderOptions& base,
                                        const std::vector<RenderOptions>& configs,
                                        FrameRange range, int runs, int warmup);

/// The table: the full render first, then one row per configuration: ms per frame "median
/// (min-max)", mean ms, speed-up, PSNR dB (over the sequence) and the worst frame's with its
/// index, mean and minimum SSIM, mean and maximum % of wrong pixels, pixels traced per frame.
void print_sequence_error_table(std::ostream& out, const SequenceErrorBench& bench);

/// {"frames": {"first", "last"}, "runs", "width", "height", "full_render": row, "rows": [row]}
/// with each row's fields: label, reuse, adaptive_tolerance, total_ms (median/min/max),
/// mean_ms, speedup, psnr_db, worst_psnr_db, worst_psnr_frame, mean_ssim, min_ssim,
/// min_ssim_frame, mean_wrong_pct, max_wrong_pct, max_wrong_frame, mean_pixels_traced,
/// mean_pixels_reused and "per_frame": [{frame, total_ms, psnr_db, ssim, wrong_pct,
/// pixels_traced, pixels_reused}]. Infinite PSNRs are null.
std::string sequence_error_json(const SequenceErrorBench& bench);

/// The same rows (full render first, without per-frame records) as CSV.
std::string sequence_error_csv(const SequenceErrorBench& bench);

/// The error measure the chart draws: 1 - mean SSIM (0 for a sequence equal to the full
/// renders).
inline constexpr const char* kSequenceErrorAxis =
    "1 - mean SSIM against the full render (luma of the sRGB image)";

/// One point per row for plot_error, the full render first (label "off (full render)"):
/// ms per frame against 1 - mean SSIM.
std::vector<ErrorPoint> sequence_error_points(const SequenceErrorBench& bench);

}  // namespace dynrt
