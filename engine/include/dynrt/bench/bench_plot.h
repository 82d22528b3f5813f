#pragma once
// Charts of `dynrt bench` results, drawn by gnuplot (Debian's gnuplot-nox, installed by
// scripts/install-deps.sh) so that nobody has to read a table to see a trend.

#include "dynrt/bench/bench.h"
#include "dynrt/engine/frame_stats.h"

#include <filesystem>
#include <string>
#include <vector>

namespace dynrt {

/// A gnuplot script, with the data inline, that draws the median build, trace and total ms of
/// `rows` (min-max as error bars) against the swept parameter into the PNG `png`:
/// - one parameter varies across the rows (cost ratio or leaf size): one chart, one line each
///   for build, trace and total;
/// - both vary: three charts side by side (build, trace, total) against the cost ratio, one
///   line per leaf size;
/// - neither: one chart with a single point per line.
/// The x axis is logarithmic when the values span a factor of 8 or more (sweeps are usually
/// geometric). `title` heads the chart. Throws std::invalid_argument if `rows` is empty.
std::string bench_plot_script(const std::vector<BenchRow>& rows, const std::string& title,
                              const std::filesystem::path& png);

/// Writes bench_plot_script next to the image as "<png>.gp" (kept, so the chart can be
/// restyled or redrawn) and runs gnuplot on it. Throws std::runtime_error if gnuplot is not
/// installed, fails, or does not produce the image.
void plot_bench(const std::filesystem::path& png, const std::vector<BenchRow>& rows,
                const std::string& title);

/// One configuration on the chart of run time against error.
struct ErrorPoint {
    std::string label;  ///< what distinguishes the configuration, written beside its point
    Spread total_ms;
    double error = 0.0;  ///< the chart's error measure (ErrorPlotAxes::x), >= 0
};

/// What the axes of the chart of run time against error measure.
struct ErrorPlotAxes {
    /// `bench --error` (a still frame): RMSE against the exact reference.
    std::string x = "RMSE against the exact reference (linear RGB, sampled pixels)";
    std::string y = "total ms per frame (median, bars min-max)";
};

/// Indices (ascending) of the points on the Pareto front: those no other point beats, that is,
/// no other is at most as slow and at most as wrong and strictly better in one of the two.
std::vector<std::size_t> pareto_front(const std::vector<ErrorPoint>& points);

/// A gnuplot script, data inline, drawing each point's median total ms (min-max as error
/// bars; y) against its error (x) into `png`, every point labelled, and the Pareto front
/// joined by a line. The x axis is logarithmic when the non-zero errors span a factor of 8 or
/// more; points with error 0 are then drawn at a tenth of the smallest non-zero error, their
/// label saying "(0)". Throws std::invalid_argument if `points` is empty.
/// `axes` names what x and y measure.
std::string error_plot_script(const std::vector<ErrorPoint>& points, const std::string& title,
                              const std::filesystem::path& png, const ErrorPlotAxes& axes = {});

/// Writes error_plot_script as "<png>.gp" and runs gnuplot, as plot_bench does.
void plot_error(const std::filesystem::path& png, const std::vector<ErrorPoint>& points,
                const std::string& title, const ErrorPlotAxes& axes = {});

/// A gnuplot script drawing the per-frame stacked timeline of an animated run into `png`: per
/// frame, one bar split into update (animation), refit, rebuild, top level, primary rays,
/// shadow rays and shade ms. Throws std::invalid_argument if `frames` is empty.
std::string timeline_plot_script(const std::vector<FrameStats>& frames, const std::string& title,
                                 const std::filesystem::path& png);

/// Writes timeline_plot_script as "<png>.gp" and runs gnuplot, as plot_bench does.
void plot_timeline(const std::filesystem::path& png, const std::vector<FrameStats>& frames,
                   const std::string& title);

}  // namespace dynrt
