#include "dynrt/bench/bench.h"

#include "dynrt/engine/report.h"
#include "dynrt/engine/resident_memory.h"
#include "dynrt/engine/stopwatch.h"

#include "dynrt/bvh/wide_bvh.h"
#include "bench/bench_columns.h"
#include "dynrt/bench/columns.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace dynrt {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = std::min(text.find(separator, start), text.size());
        parts.push_back(text.substr(start, end - start));
        if (end == text.size()) return parts;
        start = end + 1;
    }
}

double parse_number(const std::string& text, const std::string& sweep) {
    double value = 0;
    const char* last = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), last, value);
    if (ec != std::errc() || ptr != last || !std::isfinite(value)) {
        throw std::invalid_argument("--sweep '" + sweep + "': '" + text + "' is not a number");
    }
    return value;
}

}  // namespace

std::vector<bvh::BuildConfig> expand_sweeps(const std::vector<std::string>& sweeps,
                                            const bvh::BuildConfig& base) {
    std::vector<bvh::BuildConfig> configs{base};
    std::vector<std::string> swept;
    for (const std::string& sweep : sweeps) {
        const std::size_t eq = sweep.find('=');
        const std::string name = sweep.substr(0, eq);
        if (eq == std::string::npos || eq + 1 == sweep.size()) {
            throw std::invalid_argument("--sweep '" + sweep + "': expected NAME=V1,V2,...");
        }
        if (name != "cost-ratio" && name != "leaf") {
            throw std::invalid_argument("--sweep '" + sweep + "': unknown parameter '" + name +
                                        "' (known: cost-ratio, leaf, culling, adaptive, "
                                        "lod, update)");
        }
        if (std::find(swept.begin(), swept.end(), name) != swept.end()) {
            throw std::invalid_argument("--sweep: '" + name + "' is swept twice");
        }
        swept.push_back(name);
        std::vector<bvh::BuildConfig> expanded;
        for (const bvh::BuildConfig& config : configs) {
            for (const std::string& text : split(sweep.substr(eq + 1), ',')) {
                const double value = parse_number(text, sweep);
                bvh::BuildConfig c = config;
                if (name == "cost-ratio") {
                    if (!(value > 0.0)) {
                        throw std::invalid_argument("--sweep '" + sweep +
                                                    "': cost ratios must be > 0");
                    }
                    c.cost_ratio = float(value);
                } else {
                    if (value != std::floor(value) || value < 1 || value > 1024) {
                        throw std::invalid_argument("--sweep '" + sweep +
                                                    "': leaf sizes are whole numbers 1 to 1024");
                    }
                    c.leaf_size_max = std::uint32_t(value);
                }
                expanded.push_back(c);
            }
        }
        configs = std::move(expanded);
    }
    return configs;
}

std::vector<std::string> take_culling_sweep(std::vector<std::string>& sweeps) {
    std::vector<std::string> items;
    bool found = false;
    for (auto it = sweeps.begin(); it != sweeps.end();) {
        if (it->rfind("culling=", 0) != 0) {
            ++it;
            continue;
        }
        if (found) throw std::invalid_argument("--sweep: 'culling' is swept twice");
        found = true;
        const std::string sweep = *it;
        for (const std::string& item : split(sweep.substr(8), ',')) {
            if (item.empty()) {
                throw std::invalid_argument("--sweep '" + sweep + "': empty culling item");
            }
            try {
                parse_culling_item(item);
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument("--sweep '" + sweep + "': " + e.what());
            }
            items.push_back(item);
        }
        it = sweeps.erase(it);
    }
    return items;
}

packet::PacketCulling parse_culling_item(const std::string& item) {
    std::string list = item;
    std::replace(list.begin(), list.end(), '+', ',');
    return packet::PacketCulling::parse(list);
}

namespace {

/// Removes the sweep "NAME=..." from `sweeps` and returns its comma-separated items (each
/// non-empty); {} when there is none.
std::vector<std::string> take_sweep(std::vector<std::string>& sweeps, const std::string& name) {
    std::vector<std::string> items;
    bool found = false;
    const std::string prefix = name + "=";
    for (auto it = sweeps.begin(); it != sweeps.end();) {
        if (it->rfind(prefix, 0) != 0) {
            ++it;
            continue;
        }
        if (found) throw std::invalid_argument("--sweep: '" + name + "' is swept twice");
        found = true;
        const std::string sweep = *it;
        for (const std::string& item : split(sweep.substr(prefix.size()), ',')) {
            if (item.empty()) {
                throw std::invalid_argument("--sweep '" + sweep + "': empty " + name + " item");
            }
            items.push_back(item);
        }
        it = sweeps.erase(it);
    }
    return items;
}

/// The values of the sweep `name`, each a finite number >= 0 (`what` names them in the error).
std::vector<float> take_nonnegative_sweep(std::vector<std::string>& sweeps, const std::string& name,
                                          const std::string& what) {
    std::vector<float> values;
    for (const std::string& item : take_sweep(sweeps, name)) {
        const std::string sweep = name + "=" + item;
        const double value = parse_number(item, sweep);
        if (!(value >= 0.0) || !std::isfinite(float(value))) {
            throw std::invalid_argument("--sweep '" + sweep + "': " + what + " are finite numbers >= 0");
        }
        values.push_back(float(value));
    }
    return values;
}

}  // namespace

std::vector<float> take_adaptive_sweep(std::vector<std::string>& sweeps) {
    return take_nonnegative_sweep(sweeps, "adaptive", "adaptive tolerances");
}

std::vector<int> take_spp_sweep(std::vector<std::string>& sweeps) {
    std::vector<int> values;
    for (const std::string& item : take_sweep(sweeps, "spp")) {
        const double value = parse_number(item, "spp=" + item);
        if (!(value >= 1.0 && value <= PixelSampling::kMaxSamplesPerPixel) || value != std::floor(value)) {
            throw std::invalid_argument("--sweep 'spp=" + item + "': samples per pixel are whole numbers from 1 to " +
                                        std::to_string(PixelSampling::kMaxSamplesPerPixel));
        }
        values.push_back(int(value));
    }
    return values;
}

std::vector<float> take_aa_sweep(std::vector<std::string>& sweeps) {
    return take_nonnegative_sweep(sweeps, "aa", "adaptive anti-aliasing contrasts");
}

std::vector<float> take_lod_sweep(std::vector<std::string>& sweeps) {
    return take_nonnegative_sweep(sweeps, "lod", "levels of detail (pixels)");
}

std::vector<ReuseSettings> take_reuse_sweep(std::vector<std::string>& sweeps) {
    std::vector<ReuseSettings> values;
    for (const std::string& item : take_sweep(sweeps, "reuse")) {
        try {
            values.push_back(parse_reuse(item));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument("--sweep 'reuse=" + item + "': " + e.what());
        }
    }
    return values;
}

const char* to_string(BenchUpdate update) {
    return update == BenchUpdate::refit ? "refit" : "rebuild";
}

std::vector<BenchUpdate> take_update_sweep(std::vector<std::string>& sweeps) {
    std::vector<BenchUpdate> updates;
    for (const std::string& item : take_sweep(sweeps, "update")) {
        if (item == "rebuild") {
            updates.push_back(BenchUpdate::rebuild);
        } else if (item == "refit") {
            updates.push_back(BenchUpdate::refit);
        } else {
            throw std::invalid_argument("--sweep 'update=" + item + "': '" + item +
                                        "' is not an update (rebuild, refit)");
        }
    }
    return updates;
}

BenchRow bench_configuration(const Scene& scene, const Camera& camera,
                             const RenderOptions& options, int repeat, int warmup,
                             RenderedFrame* last_frame, int frame, BenchUpdate update) {
    if (repeat < 1) throw std::invalid_argument("bench: repeat must be at least 1");
    if (frame < 0) throw std::invalid_argument("bench: the frame must be >= 0");
    // Each run times a whole frame from scratch: without reset() the renderer would keep the
    // trees of the previous run, and a still scene would cost no build at all. With refit, the
    // frames before bring the trees to the state a sequence would have; their updates are
    // outside the frame's stats, so outside its timings.
    const auto render_frame = [&](Renderer& renderer, RenderedFrame& out) {
        renderer.forget_trees();
        if (update == BenchUpdate::refit) {
            for (int f = 0; f < frame; ++f) renderer.update(scene, f);
        }
        renderer.render(scene, camera, frame, out);
    };
    restart_peak_resident();  // this row's peak, not an earlier row's
    Renderer renderer(options);
    RenderedFrame local_frame;
    RenderedFrame& out = last_frame ? *last_frame : local_frame;
    // The first frame reads the textures (decoded and MIP-mapped) and builds every tree: what
    // a render pays once, at start-up, reported apart from the runs.
    const Stopwatch first_clock;
    render_frame(renderer, out);
    const double first_ms = first_clock.elapsed_ms();
    const TextureFigures textures = renderer.texture_figures();
    for (int i = 0; i < warmup; ++i) render_frame(renderer, out);
    std::vector<double> update_stage, build, trace, primary, shadow, shade, secondary, total, mrays;
    for (int i = 0; i < repeat; ++i) {
        render_frame(renderer, out);
        const FrameStats& s = out.stats;
        const double trace_ms = s.primary_ms + s.shadow_ms;
        update_stage.push_back(s.update_ms);
        build.push_back(s.build_ms);
        trace.push_back(trace_ms);
        primary.push_back(s.primary_ms);
        shadow.push_back(s.shadow_ms);
        shade.push_back(s.shade_ms);
        secondary.push_back(s.secondary_ms);
        total.push_back(s.total_ms);
        mrays.push_back(trace_ms > 0 ? double(s.primary_rays + s.shadow_rays) / (trace_ms * 1e3)
                                     : 0.0);
    }
    BenchRow row;
    row.build = options.build;
    row.adaptive_tolerance = options.adaptive_tolerance;
    row.lod_pixels = options.lod_pixels;
    row.triangles = out.stats.triangles;
    row.update_ms = spread_of(update_stage);
    row.build_ms = spread_of(build);
    row.trace_ms = spread_of(trace);
    row.primary_ms = spread_of(primary);
    row.shadow_ms = spread_of(shadow);
    row.shade_ms = spread_of(shade);
    row.secondary_ms = spread_of(secondary);
    row.total_ms = spread_of(total);
    row.mrays_per_s = spread_of(mrays);
    row.first_ms = first_ms;
    row.textures = textures;
    // The tree is the same on every repeat (the builder is deterministic in shape).
    row.sah_cost = out.stats.sah_cost;
    row.leaf_tris_mean = out.stats.leaf_tris_mean;
    row.depth = out.stats.depth;
    // Memory as the runs left it, before another renderer below holds trees of its own.
    const MemoryStats memory = out.stats;
    const std::size_t scene_triangles = out.stats.triangles;
    if (last_frame && !options.hit_buffers) {
        // The caller compares hits: one more frame, untimed, with the hit buffers filled.
        RenderOptions with_hits = options;
        with_hits.hit_buffers = true;
        Renderer hits(with_hits);
        render_frame(hits, *last_frame);
    }
    const std::size_t kept = out.stats.triangles - out.stats.degenerate_skipped;
    // What was built, not what was asked: no wide tree exists over oversized leaves.
    row.tree_width = out.stats.wide_tree_bytes > 0 ? bvh::kWideWidth : 2;
    row.bytes_per_triangle =
        kept > 0 ? double(out.stats.binary_tree_bytes + out.stats.wide_tree_bytes) / double(kept)
                 : 0.0;
    const double per = 1.0 / double(std::max<std::size_t>(scene_triangles, 1));
    row.scene_bytes_per_triangle = double(memory.scene_bytes) * per;
    row.renderer_bytes_per_triangle = double(memory.renderer_bytes) * per;
    row.peak_bytes_per_triangle = double(memory.peak_rss_bytes) * per;
    if (options.tracer == Tracer::packet) {
        std::string culling = options.packet.culling.to_string();
        std::replace(culling.begin(), culling.end(), ',', '+');
        row.packet_culling = culling;
    }
    // Counting costs a little time per ray: a separate render, outside the timings.
    RenderOptions counting = options;
    counting.count_packet_work = true;
    Renderer counter(counting);
    RenderedFrame counted;
    render_frame(counter, counted);
    row.ray_triangle_tests = counted.stats.ray_triangle_tests;
    row.ray_triangle_culled = counted.stats.ray_triangle_culled;
    row.nodes_visited = counted.stats.nodes_visited;
    row.rays = counted.stats.primary_rays + counted.stats.shadow_rays;
    return row;
}

void print_start_up(std::ostream& out, double load_ms, double first_ms, const TextureFigures& textures) {
    std::ostringstream line;
    line << std::fixed << std::setprecision(1) << "start-up (not in the runs): scene loaded in "
         << load_ms << " ms; first frame " << first_ms
         << " ms (textures read, trees built from nothing)";
    if (textures.count > 0) line << "; textures: " << describe_textures(textures);
    out << line.str() << '\n';
}

void print_bench_table(std::ostream& out, const std::vector<BenchRow>& rows) {
    out << std::left << std::setw(8) << "cost" << std::setw(6) << "leaf" << std::right
        << std::setw(10) << "tris" << std::setw(22) << "update ms" << std::setw(22) << "build ms"
        << std::setw(22) << "trace ms"
        << std::setw(22) << "shade ms" << std::setw(22) << "secondary ms" << std::setw(22) << "total ms" << std::setw(22)
        << "Mrays/s" << std::setw(9) << "SAH" << std::setw(7) << "leaf" << std::setw(6)
        << "depth" << std::setw(7) << "adapt" << std::setw(6) << "lod" << "  " << std::left << std::setw(14) << "culling" << std::right
        << std::setw(10) << "tests M" << std::setw(10) << "culled M" << std::setw(7) << "width"
        << std::setw(7) << "B/tri" << std::setw(11) << "nodes/ray" << std::setw(10) << "tris/ray"
        << std::setw(12) << "scene B/tri" << std::setw(12) << "held B/tri" << std::setw(12) << "peak B/tri"
        << '\n';
    for (const BenchRow& r : rows) {
        std::ostringstream cost;
        cost << r.build.cost_ratio;
        out << std::left << std::setw(8) << cost.str() << std::setw(6) << r.build.leaf_size_max
            << std::right << std::setw(10) << r.triangles << ' ' << std::setw(21)
            << format_spread(r.update_ms, 2) << ' ' << std::setw(21) << format_spread(r.build_ms, 2) << ' ' << std::setw(21) << format_spread(r.trace_ms, 2)
            << ' ' << std::setw(21) << format_spread(r.shade_ms, 2) << ' ' << std::setw(21)
            << format_spread(r.secondary_ms, 2) << ' ' << std::setw(21)
            << format_spread(r.total_ms, 2) << ' ' << std::setw(21) << format_spread(r.mrays_per_s, 2)
            << std::fixed << std::setprecision(1) << std::setw(9) << r.sah_cost
            << std::setprecision(2) << std::setw(7) << r.leaf_tris_mean << std::setw(6)
            << r.depth << std::setw(7) << r.adaptive_tolerance << std::setw(6) << r.lod_pixels << "  "
            << std::left << std::setw(14)
            << (r.packet_culling.empty() ? "-" : r.packet_culling) << std::right
            << std::setw(10) << double(r.ray_triangle_tests) / 1e6 << std::setw(10)
            << double(r.ray_triangle_culled) / 1e6 << std::setw(7) << r.tree_width
            << std::setprecision(0) << std::setw(7) << r.bytes_per_triangle << std::setprecision(2)
            << std::setw(11) << (r.rays ? double(r.nodes_visited) / double(r.rays) : 0.0)
            << std::setw(10) << (r.rays ? double(r.ray_triangle_tests) / double(r.rays) : 0.0)
            << std::setprecision(0) << std::setw(12) << r.scene_bytes_per_triangle << std::setw(12)
            << r.renderer_bytes_per_triangle << std::setw(12) << r.peak_bytes_per_triangle << '\n';
    }
}

std::string bench_csv(const std::vector<BenchRow>& rows) {
    std::ostringstream out;
    out << std::setprecision(9);
    bench_columns::csv_header(out, rows.empty() ? BenchRow{} : rows.front(), for_each_column);
    out << '\n';
    for (const BenchRow& row : rows) {
        bench_columns::csv_values(out, row, for_each_column);
        out << '\n';
    }
    return out.str();
}

std::string bench_json(const std::vector<BenchRow>& rows) {
    nlohmann::ordered_json doc;
    doc["rows"] = nlohmann::ordered_json::array();
    for (const BenchRow& row : rows) {
        nlohmann::ordered_json j;
        bench_columns::json_fields(j, row, for_each_column);
        doc["rows"].push_back(j);
    }
    return doc.dump(2) + "\n";
}

}  // namespace dynrt
