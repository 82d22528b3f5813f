#include "dynrt/bench/error_bench.h"

#include "dynrt/anim/posed_scene.h"
#include "bench/bench_columns.h"
#include "dynrt/bench/columns.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace dynrt::reference {

namespace {

/// The shortest decimal that reads back as `value` (0.1f prints as 0.1).
std::string shortest(float value) {
    char text[32];
    const auto [end, ec] = std::to_chars(text, text + sizeof(text), value);
    return std::string(text, end);
}

std::string culling_of(const ErrorRow& row) {
    return row.timing.packet_culling.empty() ? "-" : row.timing.packet_culling;
}

double determined_pct(const FrameError& e) { return 100.0 * e.determined_share(); }

/// Calls visit(key, value) for the error columns of a row, in output order (after the timing
/// columns of its BenchRow).
struct ForEachErrorColumn {
    template <typename Visit>
    void operator()(const ErrorRow& row, Visit&& visit) const {
        visit("update", std::string(to_string(row.update)));
        visit("frame", row.frame);
        visit("samples", row.error.samples);
        visit("ambiguous_samples", row.error.ambiguous_samples);
        visit("hit_differs", row.error.hit_differs);
        visit("determined_differs", row.error.determined_differs);
        visit("ambiguous_differs", row.error.ambiguous_differs);
        visit("hit_differs_determined_pct", determined_pct(row.error));
        visit("rmse", row.error.rmse);
        visit("psnr_db", row.error.psnr_db);
    }
};
constexpr ForEachErrorColumn for_each_error_column{};

}  // namespace

SampledReference sample_reference(const Scene& scene, const Camera& camera,
                                  const RenderOptions& options, int frame, int block,
                                  std::uint64_t seed) {
    const auto start = std::chrono::steady_clock::now();
    SampledReference out;
    out.frame = frame;
    out.width = options.width;
    out.height = options.height;
    out.block = block;
    out.pixels = stratified_pixels(options.width, options.height, block, seed);
    anim::PoseSettings pose = options.pose;
    pose.skip_fixed_positions = false;  // the brute-force tracer needs every world position
    anim::PosedScene posed;
    anim::pose_scene(scene, pose, frame, posed);
    const ReferenceTracer tracer(scene, posed);
    out.values = render_reference_pixels(scene, tracer, camera, options.width, options.height,
                                         out.pixels, shading_from(scene, options));
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
    return out;
}

ErrorRow bench_error_row(const Scene& scene, const Camera& camera,
                         const ErrorConfiguration& config, int repeat, int warmup,
                         const SampledReference& reference) {
    if (config.options.width != reference.width || config.options.height != reference.height) {
        throw std::invalid_argument("bench_error_row: the configuration renders " +
                                    std::to_string(config.options.width) + "x" +
                                    std::to_string(config.options.height) +
                                    ", the reference is " + std::to_string(reference.width) +
                                    "x" + std::to_string(reference.height));
    }
    ErrorRow row;
    RenderedFrame frame;
    row.timing = bench_configuration(scene, camera, config.options, repeat, warmup, &frame,
                                     reference.frame, config.update);
    row.update = config.update;
    row.frame = reference.frame;
    row.error = frame_error(frame, reference.pixels, reference.values);
    return row;
}

std::vector<std::string> error_row_labels(const std::vector<ErrorRow>& rows) {
    const auto varies = [&](auto key) {
        return std::any_of(rows.begin(), rows.end(),
                           [&](const ErrorRow& r) { return key(r) != key(rows.front()); });
    };
    const bool cost = varies([](const ErrorRow& r) { return r.timing.build.cost_ratio; });
    const bool leaf = varies([](const ErrorRow& r) { return r.timing.build.leaf_size_max; });
    const bool culling = varies([](const ErrorRow& r) { return r.timing.packet_culling; });
    const bool update = varies([](const ErrorRow& r) { return r.update; });
    const bool adaptive = varies([](const ErrorRow& r) { return r.timing.adaptive_tolerance; });
    const bool lod = varies([](const ErrorRow& r) { return r.timing.lod_pixels; });
    std::vector<std::string> labels;
    for (const ErrorRow& r : rows) {
        std::vector<std::string> parts;
        if (cost) parts.push_back("cost " + shortest(r.timing.build.cost_ratio));
        if (leaf) parts.push_back("leaf " + std::to_string(r.timing.build.leaf_size_max));
        if (culling) parts.push_back(culling_of(r));
        if (update) parts.push_back(to_string(r.update));
        if (adaptive) parts.push_back("adaptive " + shortest(r.timing.adaptive_tolerance));
        if (lod) parts.push_back("lod " + shortest(r.timing.lod_pixels));
        std::string label;
        for (const std::string& part : parts) label += (label.empty() ? "" : ", ") + part;
        labels.push_back(label.empty() ? "default" : label);
    }
    return labels;
}

void print_error_table(std::ostream& out, const std::vector<ErrorRow>& rows) {
    out << std::left << std::setw(8) << "cost" << std::setw(6) << "leaf" << std::setw(16)
        << "culling" << std::setw(9) << "update" << std::setw(9) << "adaptive" << std::setw(6) << "lod" << std::right
        << std::setw(24) << "total ms" << std::setw(14) << "hit differs %" << std::setw(8)
        << "ambig" << std::setw(12) << "RMSE" << std::setw(9) << "PSNR dB" << '\n';
    for (const ErrorRow& r : rows) {
        std::ostringstream pct;
        pct << std::fixed << std::setprecision(3) << determined_pct(r.error);
        std::ostringstream rmse;
        rmse << std::scientific << std::setprecision(2) << r.error.rmse;
        out << std::left << std::setw(8) << shortest(r.timing.build.cost_ratio) << std::setw(6)
            << r.timing.build.leaf_size_max << std::setw(16) << culling_of(r) << std::setw(9)
            << to_string(r.update) << std::setw(9) << shortest(r.timing.adaptive_tolerance)
            << std::setw(6) << shortest(r.timing.lod_pixels) << std::right << std::setw(24) << format_spread(r.timing.total_ms) << std::setw(14) << pct.str()
            << std::setw(8)
            << r.error.ambiguous_differs << std::setw(12) << rmse.str() << std::setw(9)
            << format_psnr(r.error.psnr_db) << '\n';
    }
}

void print_reference_line(std::ostream& out, const SampledReference& reference) {
    std::ostringstream ms;
    ms << std::fixed << std::setprecision(0) << reference.ms;
    out << "reference: frame " << reference.frame << ", " << reference.pixels.size()
        << " sampled pixels (one per " << reference.block << "x" << reference.block
        << " block) of " << reference.width << "x" << reference.height << ", " << ms.str()
        << " ms (untimed for the rows)\n";
}

std::string error_csv(const std::vector<ErrorRow>& rows) {
    std::ostringstream out;
    out << std::setprecision(9);
    const ErrorRow& first = rows.empty() ? ErrorRow{} : rows.front();
    bench_columns::csv_header(out, first.timing, for_each_column);
    bench_columns::csv_header(out, first, for_each_error_column, false);
    out << '\n';
    for (const ErrorRow& row : rows) {
        bench_columns::csv_values(out, row.timing, for_each_column);
        bench_columns::csv_values(out, row, for_each_error_column, false);
        out << '\n';
    }
    return out.str();
}

std::string error_json(const std::vector<ErrorRow>& rows, const SampledReference& reference) {
    nlohmann::ordered_json doc;
    doc["rows"] = nlohmann::ordered_json::array();
    for (const ErrorRow& row : rows) {
        nlohmann::ordered_json j;
        bench_columns::json_fields(j, row.timing, for_each_column);
        bench_columns::json_fields(j, row, for_each_error_column);
        doc["rows"].push_back(j);
    }
    doc["reference"] = {{"frame", reference.frame},
                        {"width", reference.width},
                        {"height", reference.height},
                        {"block", reference.block},
                        {"samples", reference.pixels.size()},
                        {"ms", reference.ms}};
    return doc.dump(2) + "\n";
}

}  // namespace dynrt::reference
