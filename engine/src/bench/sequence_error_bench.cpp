#include "dynrt/bench/sequence_error_bench.h"

#include "dynrt/bench/columns.h"
#include "dynrt/bench/image_metrics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace dynrt {

namespace {

/// The shortest decimal that reads back as `value` (0.1f prints as 0.1).
std::string shortest(float value) {
    char text[32];
    const auto [end, ec] = std::to_chars(text, text + sizeof(text), value);
    return std::string(text, end);
}

std::string label_of(const RenderOptions& options) {
    std::string label = to_string(options.reuse);
    if (options.adaptive_tolerance > 0.0f) {
        label += " + adaptive " + shortest(options.adaptive_tolerance);
    }
    if (options.lod_pixels > 0.0f) label += " + lod " + shortest(options.lod_pixels);
    if (options.sampling.spp > 1) label += " + " + std::to_string(options.sampling.spp) + " spp";
    if (options.sampling.spp > 1 && options.sampling.adaptive_contrast > 0.0f) {
        label += " aa " + shortest(options.sampling.adaptive_contrast);
    }
    return label;
}

/// The row's summary figures from its per-frame records (at least one); `mse_sum` is the
/// frames' MSEs summed.
void summarise(SequenceErrorRow& row, double mse_sum) {
    const std::vector<SequenceErrorFrame>& frames = row.frames;
    const double n = double(frames.size());
    std::vector<double> ms;
    double ms_sum = 0, ssim_sum = 0, wrong_sum = 0, traced_sum = 0, reused_sum = 0;
    const SequenceErrorFrame& first = frames.front();
    row.worst_psnr_db = first.psnr_db;
    row.worst_psnr_frame = first.frame;
    row.min_ssim = first.ssim;
    row.min_ssim_frame = first.frame;
    row.max_wrong_share = first.wrong_share;
    row.max_wrong_frame = first.frame;
    for (const SequenceErrorFrame& f : frames) {
        ms.push_back(f.total_ms);
        ms_sum += f.total_ms;
        ssim_sum += f.ssim;
        wrong_sum += f.wrong_share;
        traced_sum += double(f.pixels_traced);
        reused_sum += double(f.pixels_reused);
        // Strict comparisons: a tie keeps the first such frame.
        if (f.psnr_db < row.worst_psnr_db) {
            row.worst_psnr_db = f.psnr_db;
            row.worst_psnr_frame = f.frame;
        }
        if (f.ssim < row.min_ssim) {
            row.min_ssim = f.ssim;
            row.min_ssim_frame = f.frame;
        }
        if (f.wrong_share > row.max_wrong_share) {
            row.max_wrong_share = f.wrong_share;
            row.max_wrong_frame = f.frame;
        }
    }
    row.total_ms = spread_of(ms);
    row.mean_ms = ms_sum / n;
    row.psnr_db = psnr_from_mse(mse_sum / n);
    row.mean_ssim = ssim_sum / n;
    row.mean_wrong_share = wrong_sum / n;
    row.mean_pixels_traced = traced_sum / n;
    row.mean_pixels_reused = reused_sum / n;
}

SequenceErrorFrame frame_record(const RenderedFrame& frame) {
    SequenceErrorFrame f;
    f.frame = frame.stats.frame;
    f.total_ms = frame.stats.total_ms;
    f.pixels_traced = frame.stats.pixels_traced;
    f.pixels_reused = frame.stats.pixels_reused;
    return f;
}

/// A configuration's renderer and the frame it renders into, kept from frame to frame (the
/// reuse modes read the previous frame's buffers).
struct Lane {
    std::unique_ptr<Renderer> renderer;
    RenderedFrame frame;
    double mse_sum = 0.0;
};

/// The columns of a row in output order (CSV and JSON), errors as percentages.
struct ForEachSequenceErrorColumn {
    template <typename Visit>
    void operator()(const SequenceErrorRow& r, Visit&& visit) const {
        visit("label", r.label);
        visit("reuse", to_string(r.reuse));
        visit("adaptive_tolerance", r.adaptive_tolerance);
        visit("lod_pixels", r.lod_pixels);
        visit("spp", r.sampling.spp);
        visit("aa_contrast", r.sampling.adaptive_contrast);
        visit("total_ms", r.total_ms);
        visit("mean_ms", r.mean_ms);
        visit("speedup", r.speedup);
        visit("psnr_db", r.psnr_db);
        visit("worst_psnr_db", r.worst_psnr_db);
        visit("worst_psnr_frame", r.worst_psnr_frame);
        visit("mean_ssim", r.mean_ssim);
        visit("min_ssim", r.min_ssim);
        visit("min_ssim_frame", r.min_ssim_frame);
        visit("mean_wrong_pct", 100.0 * r.mean_wrong_share);
        visit("max_wrong_pct", 100.0 * r.max_wrong_share);
        visit("max_wrong_frame", r.max_wrong_frame);
        visit("mean_pixels_traced", r.mean_pixels_traced);
        visit("mean_pixels_reused", r.mean_pixels_reused);
    }
};
constexpr ForEachSequenceErrorColumn for_each_sequence_error_column{};

struct ForEachFrameColumn {
    template <typename Visit>
    void operator()(const SequenceErrorFrame& f, Visit&& visit) const {
        visit("frame", f.frame);
        visit("total_ms", f.total_ms);
        visit("psnr_db", f.psnr_db);
        visit("ssim", f.ssim);
        visit("wrong_pct", 100.0 * f.wrong_share);
        visit("pixels_traced", f.pixels_traced);
        visit("pixels_reused", f.pixels_reused);
    }
};
constexpr ForEachFrameColumn for_each_frame_column{};

nlohmann::ordered_json row_json(const SequenceErrorRow& row) {
    nlohmann::ordered_json j;
    bench_columns::json_fields(j, row, for_each_sequence_error_column);
    j["per_frame"] = nlohmann::ordered_json::array();
    for (const SequenceErrorFrame& f : row.frames) {
        nlohmann::ordered_json jf;
        bench_columns::json_fields(jf, f, for_each_frame_column);
        j["per_frame"].push_back(jf);
    }
    return j;
}

std::string fixed(double value, int precision) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(precision) << value;
    return out.str();
}

std::string psnr_text(double psnr_db) {
    return std::isinf(psnr_db) ? "inf" : fixed(psnr_db, 2);
}

}  // namespace

RenderOptions full_render_options(const RenderOptions& base) {
    RenderOptions options = base;
    options.reuse.mode = PixelReuse::off;
    options.adaptive_tolerance = 0.0f;
    options.sampling.adaptive_contrast = 0.0f;
    options.lod_pixels = 0.0f;
    return options;
}

SequenceErrorBench bench_sequence_error(const Scene& scene, const CameraSource& view,
                                        const RenderOptions& base,
                                        const std::vector<RenderOptions>& configs,
                                        FrameRange range, int runs, int warmup) {
    if (configs.empty()) {
        throw std::invalid_argument("bench --error: no configuration to measure");
    }
    if (runs < 1) throw std::invalid_argument("bench: repeat must be at least 1");
    if (view.from_scene && scene.cameras.empty()) {
        throw std::invalid_argument("bench: " + scene.source +
                                    " has no camera of its own to follow");
    }
    for (const RenderOptions& c : configs) {
        if (c.width != base.width || c.height != base.height) {
            throw std::invalid_argument("bench --error: every configuration must render the "
                                        "full render's image size");
        }
    }
    if (base.width < 11 || base.height < 11) {
        throw std::invalid_argument("bench --frames --error: SSIM needs images of at least "
                                    "11x11 pixels (its window), not " +
                                    std::to_string(base.width) + "x" +
                                    std::to_string(base.height));
    }
    const RenderOptions full = full_render_options(base);
    {
        // Untimed: thread pool start, page and code faults, once per configuration's code path.
        RenderedFrame scratch;
        for (int i = 0; i < warmup; ++i) {
            Renderer(full).render(scene, range.first, view, scratch);
            for (const RenderOptions& c : configs) {
                Renderer(c).render(scene, range.first, view, scratch);
            }
        }
    }
    SequenceErrorBench bench;
    bench.range = range;
    bench.runs = runs;
    bench.width = base.width;
    bench.height = base.height;
    bench.reference.label = "off (full render)";
    if (full.sampling.spp > 1) bench.reference.label = "off (full render, " + std::to_string(full.sampling.spp) + " spp)";
    bench.reference.reuse = full.reuse;
    bench.reference.sampling = full.sampling;
    bench.rows.resize(configs.size());
    for (std::size_t k = 0; k < configs.size(); ++k) {
        bench.rows[k].label = label_of(configs[k]);
        bench.rows[k].reuse = configs[k].reuse;
        bench.rows[k].adaptive_tolerance = configs[k].adaptive_tolerance;
        bench.rows[k].lod_pixels = configs[k].lod_pixels;
        bench.rows[k].sampling = configs[k].sampling;
    }
    std::vector<Lane> lanes(configs.size());
    for (int run = 0; run < runs; ++run) {
        // A new sequence: new renderers (empty trees, nothing to reuse).
        Renderer full_renderer(full);
        RenderedFrame full_frame;
        for (std::size_t k = 0; k < configs.size(); ++k) {
            lanes[k].renderer = std::make_unique<Renderer>(configs[k]);
            lanes[k].frame = RenderedFrame{};
        }
        for (int f = range.first; f <= range.last; ++f) {
            full_renderer.render(scene, f, view, full_frame);
            bench.reference.frames.push_back(frame_record(full_frame));
            const DisplayImage full_image = display_image(full_frame);
            for (std::size_t k = 0; k < lanes.size(); ++k) {
                Lane& lane = lanes[k];
                lane.renderer->render(scene, f, view, lane.frame);
                const ImageMetrics m = compare_images(display_image(lane.frame), full_image);
                SequenceErrorFrame record = frame_record(lane.frame);
                record.psnr_db = m.psnr_db;
                record.ssim = m.ssim;
                record.wrong_share = m.wrong_share;
                bench.rows[k].frames.push_back(record);
                lane.mse_sum += m.mse;
            }
        }
    }
    summarise(bench.reference, 0.0);
    for (std::size_t k = 0; k < lanes.size(); ++k) {
        summarise(bench.rows[k], lanes[k].mse_sum);
        const double median = bench.rows[k].total_ms.median;
        bench.rows[k].speedup = median > 0.0 ? bench.reference.total_ms.median / median : 0.0;
    }
    return bench;
}

void print_sequence_error_table(std::ostream& out, const SequenceErrorBench& bench) {
    // The first column as wide as the longest label.
    std::size_t label_width = std::string("configuration").size();
    label_width = std::max(label_width, bench.reference.label.size());
    for (const SequenceErrorRow& r : bench.rows) label_width = std::max(label_width, r.label.size());
    const int first = int(label_width) + 2;
    out << std::left << std::setw(first) << "configuration" << std::right << std::setw(24)
        << "ms/frame" << std::setw(9) << "mean ms" << std::setw(9) << "speedup" << std::setw(9)
        << "PSNR dB" << std::setw(18) << "worst PSNR (fr)" << std::setw(10) << "mean SSIM"
        << std::setw(20) << "min SSIM (fr)" << std::setw(9) << "wrong %" << std::setw(18)
        << "max wrong % (fr)" << std::setw(13) << "traced/frame" << '\n';
    const auto line = [&](const SequenceErrorRow& r, bool full) {
        out << std::left << std::setw(first) << r.label << std::right << std::setw(24)
            << format_spread(r.total_ms) << std::setw(9) << fixed(r.mean_ms, 2) << std::setw(9)
            << fixed(r.speedup, 2);
        if (full) {
            // The reference of every error column: nothing to measure against itself.
            out << std::setw(9) << "-" << std::setw(18) << "-" << std::setw(10) << "-"
                << std::setw(20) << "-" << std::setw(9) << "-" << std::setw(18) << "-";
        } else {
            out << std::setw(9) << psnr_text(r.psnr_db) << std::setw(18)
                << psnr_text(r.worst_psnr_db) + " (" + std::to_string(r.worst_psnr_frame) + ")"
                << std::setw(10) << fixed(r.mean_ssim, 5) << std::setw(20)
                << fixed(r.min_ssim, 5) + " (" + std::to_string(r.min_ssim_frame) + ")"
                << std::setw(9) << fixed(100.0 * r.mean_wrong_share, 3) << std::setw(18)
                << fixed(100.0 * r.max_wrong_share, 3) + " (" +
                       std::to_string(r.max_wrong_frame) + ")";
        }
        out << std::setw(13) << fixed(r.mean_pixels_traced, 0) << '\n';
    };
    line(bench.reference, true);
    for (const SequenceErrorRow& r : bench.rows) line(r, false);
}

std::string sequence_error_json(const SequenceErrorBench& bench) {
    nlohmann::ordered_json doc;
    doc["frames"] = {{"first", bench.range.first}, {"last", bench.range.last}};
    doc["runs"] = bench.runs;
    doc["width"] = bench.width;
    doc["height"] = bench.height;
    doc["full_render"] = row_json(bench.reference);
    doc["rows"] = nlohmann::ordered_json::array();
    for (const SequenceErrorRow& r : bench.rows) doc["rows"].push_back(row_json(r));
    return doc.dump(2) + "\n";
}

std::string sequence_error_csv(const SequenceErrorBench& bench) {
    std::ostringstream out;
    out << std::setprecision(9);
    bench_columns::csv_header(out, bench.reference, for_each_sequence_error_column);
    out << '\n';
    bench_columns::csv_values(out, bench.reference, for_each_sequence_error_column);
    out << '\n';
    for (const SequenceErrorRow& r : bench.rows) {
        bench_columns::csv_values(out, r, for_each_sequence_error_column);
        out << '\n';
    }
    return out.str();
}

std::vector<ErrorPoint> sequence_error_points(const SequenceErrorBench& bench) {
    std::vector<ErrorPoint> points;
    points.push_back({bench.reference.label, bench.reference.total_ms, 0.0});
    for (const SequenceErrorRow& r : bench.rows) {
        // max(): a mean SSIM a rounding above 1 is still no error.
        points.push_back({r.label, r.total_ms, std::max(0.0, 1.0 - r.mean_ssim)});
    }
    return points;
}

}  // namespace dynrt
