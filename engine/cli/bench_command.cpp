// `dynrt bench`: a still frame under one or more build configurations (sweeps, --vs embree,
// --error against the exact reference) or a sequence (--frames; with --error, its pixel reuse
// and adaptive configurations against full renders of the same frames).

#include "frame_args.h"

#include "dynrt/bench/bench.h"
#include "dynrt/bench/bench_plot.h"
#include "dynrt/bench/bench_sequence.h"
#include "dynrt/bench/error_bench.h"
#include "dynrt/bench/hit_agreement.h"
#include "dynrt/bench/sequence_error_bench.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/engine/stopwatch.h"

#if DYNRT_HAVE_EMBREE
#include "dynrt/embree/embree_bench.h"
#include "dynrt/embree/stage_bench.h"
#endif

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::cli {

namespace {

/// `bench --frames`: an animated sequence, with Embree's per-frame options beside it.
int run_bench_sequence(const BenchArgs& args) {
    if (!args.sweeps.empty() || !args.csv.empty() || !args.diff_image.empty()) {
        throw std::invalid_argument("bench --frames: --sweep, --csv and --diff-image are not "
                                    "supported for sequences yet");
    }
    dynrt::RenderOptions options = render_options(args);
    const dynrt::FrameRange range = dynrt::parse_frame_range(args.frames);
    const int runs = args.repeat > 0 ? args.repeat : 1;
    const std::string source = scene_source(args);
    const dynrt::Stopwatch load_clock;
    const dynrt::Scene scene = load_animated_scene(args, source, options);
    const double load_ms = load_clock.elapsed_ms();
    warn_past_the_end(scene, options.pose, range);
    note_single_frame(std::cout, args.frames);
    const dynrt::CameraSource view = camera_source(scene, args, options.pose, range);
    std::vector<std::unique_ptr<dynrt::SequenceTracer>> others;
#if DYNRT_HAVE_EMBREE
    if (args.vs == "embree") {
        for (dynrt::embree::BuildQuality q : {dynrt::embree::BuildQuality::refit, dynrt::embree::BuildQuality::low}) {
            others.push_back(dynrt::embree::make_sequence_tracer(scene, options, q));
        }
    }
#endif
    std::cout << "dynrt bench: " << source << ", " << scene.triangle_count() << " triangles, "
              << options.width << "x" << options.height << ", frames " << range.first << "-"
              << range.last << ", median (min-max) over " << range.count() * runs
              << " frames (" << runs << " run(s)) after " << args.warmup << " warm-up\n";
    print_ignored(std::cout, scene);
    const dynrt::SequenceBench bench =
        dynrt::bench_sequence(scene, view, options, range, runs, args.warmup, others);
    dynrt::print_start_up(std::cout, load_ms, bench.first_ms, bench.textures);
    dynrt::print_sequence_table(std::cout, bench);
    print_rebuild_summary(std::cout, bench.frames);
    print_update_choices(std::cout, bench.frames);
    if (!args.plot.empty()) {
        dynrt::plot_timeline(args.plot, bench.frames,
                             "dynrt per frame: " + source + ", " + std::to_string(options.width) +
                                 "x" + std::to_string(options.height));
        std::cout << "plot: " << args.plot << "\n";
    }
    if (!args.json.empty()) write_text(args.json, dynrt::sequence_json(bench));
    return 0;
}

/// The configurations a bench measures, from the base options and the sweeps: culling items
/// vary slowest, then update, then adaptive tolerances, then levels of detail, then the build sweeps as expand_sweeps
/// orders them. Without an update sweep every configuration rebuilds.
std::vector<dynrt::reference::ErrorConfiguration> bench_configurations(
    const BenchArgs& args, const dynrt::RenderOptions& base) {
    std::vector<std::string> build_sweeps = args.sweeps;
    const std::vector<std::string> cullings = dynrt::take_culling_sweep(build_sweeps);
    std::vector<float> adaptives = dynrt::take_adaptive_sweep(build_sweeps);
    std::vector<float> lods = dynrt::take_lod_sweep(build_sweeps);
    std::vector<dynrt::BenchUpdate> updates = dynrt::take_update_sweep(build_sweeps);
    if (!cullings.empty() && base.tracer != dynrt::Tracer::packet) {
        throw std::invalid_argument("--sweep culling=...: the culling stages are the packet "
                                    "tracer's; drop --tracer single");
    }
    if (!updates.empty() && !args.error) {
        throw std::invalid_argument("--sweep update=...: compares how a frame's trees came "
                                    "about by its error, so it needs --error");
    }
    if (adaptives.empty()) adaptives.push_back(base.adaptive_tolerance);
    if (lods.empty()) lods.push_back(base.lod_pixels);
    if (updates.empty()) updates.push_back(dynrt::BenchUpdate::rebuild);
    for (float adaptive : adaptives) {
        if (adaptive > 0.0f && base.tracer != dynrt::Tracer::packet) {
            throw std::invalid_argument("adaptive sampling (--adaptive, --sweep adaptive=...) "
                                        "is the packet tracer's; drop --tracer single");
        }
    }
    const std::vector<dynrt::bvh::BuildConfig> builds =
        dynrt::expand_sweeps(build_sweeps, base.build);
    std::vector<dynrt::reference::ErrorConfiguration> configs;
    const std::vector<std::string> culling_items =
        cullings.empty() ? std::vector<std::string>{""} : cullings;
    for (const std::string& culling : culling_items) {
        for (dynrt::BenchUpdate update : updates) {
            for (float adaptive : adaptives) {
                for (float lod : lods) {
                    for (const dynrt::bvh::BuildConfig& build : builds) {
                        dynrt::reference::ErrorConfiguration config{base, update};
                        config.options.build = build;
                        config.options.adaptive_tolerance = adaptive;
                        config.options.lod_pixels = lod;
                        if (!culling.empty()) {
                            config.options.packet.culling = dynrt::parse_culling_item(culling);
                        }
                        configs.push_back(config);
                    }
                }
            }
        }
    }
    return configs;
}

/// Whether the sweeps name `parameter` ("culling", "adaptive", ...).
bool sweeps_parameter(const BenchArgs& args, const std::string& parameter) {
    return std::any_of(args.sweeps.begin(), args.sweeps.end(), [&](const std::string& s) {
        return s.rfind(parameter + "=", 0) == 0;
    });
}

/// The render options of a still-frame bench (plain or --error).
dynrt::RenderOptions still_frame_options(const BenchArgs& args) {
    dynrt::RenderOptions options = render_options(args);
    options.hit_buffers = args.hit_buffers;
    return options;
}

/// `bench --error`: every configuration's time beside its error against the exact reference
/// of one frame, sampled on one pixel per --error-block square.
int run_bench_error(const BenchArgs& args) {
    if (!args.vs.empty()) {
        throw std::invalid_argument("bench --error measures dynrt against the exact "
                                    "reference: drop --vs");
    }
    const int repeat = args.repeat > 0 ? args.repeat : 5;
    dynrt::RenderOptions base = still_frame_options(args);
    const std::string source = scene_source(args);
    // First the scene: its pose settings (class overrides, clips) and what it sets up (image
    // size, frame rate) go into every row.
    const dynrt::Scene scene = load_animated_scene(args, source, base);
    const std::vector<dynrt::reference::ErrorConfiguration> posed_configs =
        bench_configurations(args, base);
    const bool moves = !scene.motions.empty() || !scene.clips.empty();
    const int frame = args.error_frame >= 0 ? args.error_frame : (moves ? 24 : 0);
    const dynrt::Camera camera = camera_for(scene, args, base.pose, dynrt::FrameRange{frame, frame});
    std::cout << "dynrt bench --error: " << source << ", " << scene.triangle_count()
              << " triangles, " << base.width << "x" << base.height << ", frame " << frame
              << ", " << posed_configs.size() << " configuration(s), median (min-max) of "
              << repeat << " runs after " << args.warmup << " warm-up\n"
              << std::flush;
    const dynrt::reference::SampledReference reference =
        dynrt::reference::sample_reference(scene, camera, base, frame,
                                           args.error_block > 0 ? args.error_block : 8);
    dynrt::reference::print_reference_line(std::cout, reference);
    std::vector<dynrt::reference::ErrorRow> rows;
    for (const dynrt::reference::ErrorConfiguration& config : posed_configs) {
        // One warm-up for the whole sweep, as run_bench does.
        const int warmup = rows.empty() ? args.warmup : 0;
        rows.push_back(
            dynrt::reference::bench_error_row(scene, camera, config, repeat, warmup, reference));
    }
    dynrt::reference::print_error_table(std::cout, rows);
    if (!args.csv.empty()) write_text(args.csv, dynrt::reference::error_csv(rows));
    if (!args.json.empty()) write_text(args.json, dynrt::reference::error_json(rows, reference));
    if (!args.plot.empty()) {
        const std::vector<std::string> labels = dynrt::reference::error_row_labels(rows);
        std::vector<dynrt::ErrorPoint> points;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            points.push_back({labels[i], rows[i].timing.total_ms, rows[i].error.rmse});
        }
        std::ostringstream title;
        title << "dynrt bench --error: " << source << ", " << scene.triangle_count()
              << " triangles, " << base.width << "x" << base.height << ", frame " << frame
              << ", " << reference.pixels.size() << " sampled pixels";
        dynrt::plot_error(args.plot, points, title.str());
        std::cout << "plot: " << args.plot << "\n";
    }
    return 0;
}

/// `bench --frames A-B --error`: each pixel reuse and adaptive configuration renders the
/// sequence with its own renderer, timed per frame and compared with the full render of every
/// frame (sequence_error_bench.h).
int run_bench_sequence_error(const BenchArgs& args) {
    if (!args.vs.empty() || !args.diff_image.empty()) {
        throw std::invalid_argument("bench --frames --error compares dynrt's configurations "
                                    "with its own full renders: drop --vs and --diff-image");
    }
    if (args.error_block > 0 || args.error_frame >= 0) {
        throw std::invalid_argument("bench --frames --error compares every pixel of every "
                                    "frame: --error-block and --error-frame are for one frame "
                                    "(--error without --frames)");
    }
    std::vector<std::string> sweeps = args.sweeps;
    std::vector<dynrt::ReuseSettings> reuses = dynrt::take_reuse_sweep(sweeps);
    std::vector<float> adaptives = dynrt::take_adaptive_sweep(sweeps);
    std::vector<int> spps = dynrt::take_spp_sweep(sweeps);
    std::vector<float> aas = dynrt::take_aa_sweep(sweeps);
    std::vector<float> lods = dynrt::take_lod_sweep(sweeps);
    if (!sweeps.empty()) {
        throw std::invalid_argument("--sweep '" + sweeps.front() + "': with --frames --error "
                                    "only reuse=..., adaptive=..., spp=..., aa=... and lod=... are swept");
    }
    dynrt::RenderOptions base = render_options(args);
    const dynrt::FrameRange range = dynrt::parse_frame_range(args.frames);
    const int runs = args.repeat > 0 ? args.repeat : 1;
    const std::string source = scene_source(args);
    const dynrt::Scene scene = load_animated_scene(args, source, base);
    warn_past_the_end(scene, base.pose, range);
    note_single_frame(std::cout, args.frames);
    const dynrt::CameraSource view = camera_source(scene, args, base.pose, range);
    if (reuses.empty()) reuses.push_back(base.reuse);
    if (adaptives.empty()) adaptives.push_back(base.adaptive_tolerance);
    // Sampling sweeps: the full render keeps --spp (a converged reference, e.g. 256), the rows
    // take the swept values.
    if (spps.empty()) spps.push_back(base.sampling.spp);
    if (aas.empty()) aas.push_back(base.sampling.adaptive_contrast);
    if (lods.empty()) lods.push_back(base.lod_pixels);
    std::vector<dynrt::RenderOptions> configs;
    for (const dynrt::ReuseSettings& reuse : reuses) {
        for (float adaptive : adaptives) {
            if (adaptive > 0.0f && base.tracer != dynrt::Tracer::packet) {
                throw std::invalid_argument("adaptive sampling (--adaptive, --sweep "
                                            "adaptive=...) is the packet tracer's; drop "
                                            "--tracer single");
            }
            for (const int spp : spps) {
                for (const float aa : aas) {
                    // Nothing to refine at one sample; interpolation takes one sample.
                    if ((aa > 0.0f && spp == 1) || (adaptive > 0.0f && spp > 1)) continue;
                    for (const float lod : lods) {
                        dynrt::RenderOptions config = base;
                        config.reuse = reuse;
                        config.adaptive_tolerance = adaptive;
                        config.sampling.spp = spp;
                        config.sampling.adaptive_contrast = aa;
                        config.lod_pixels = lod;
                        configs.push_back(config);
                    }
                }
            }
        }
    }
    if (configs.empty()) {
        throw std::invalid_argument("bench --frames --error: no configuration left to measure (aa=... needs "
                                    "spp above 1, adaptive=... one sample per pixel)");
    }
    std::cout << "dynrt bench --error: " << source << ", " << scene.triangle_count()
              << " triangles, " << base.width << "x" << base.height << ", frames "
              << range.first << "-" << range.last << ", " << configs.size()
              << " configuration(s) against the full render (reuse off) of every frame, "
              << runs << " run(s) after " << args.warmup << " warm-up\n"
              << std::flush;
    print_ignored(std::cout, scene);
    const dynrt::SequenceErrorBench bench =
        dynrt::bench_sequence_error(scene, view, base, configs, range, runs, args.warmup);
    dynrt::print_sequence_error_table(std::cout, bench);
    if (!args.csv.empty()) write_text(args.csv, dynrt::sequence_error_csv(bench));
    if (!args.json.empty()) write_text(args.json, dynrt::sequence_error_json(bench));
    if (!args.plot.empty()) {
        std::ostringstream title;
        title << "dynrt bench --frames " << range.first << "-" << range.last << " --error: "
              << source << ", " << scene.triangle_count() << " triangles, " << base.width
              << "x" << base.height;
        dynrt::plot_error(args.plot, dynrt::sequence_error_points(bench), title.str(),
                          {dynrt::kSequenceErrorAxis, "ms per frame (median, bars min-max)"});
        std::cout << "plot: " << args.plot << "\n";
    }
    return 0;
}

}  // namespace

int run_bench(const BenchArgs& args) {
    if (!args.vs.empty() && args.vs != "embree") {
        throw std::invalid_argument("--vs '" + args.vs + "': the only tracer to compare with is "
                                    "'embree'");
    }
    if (args.vs == "embree" && (args.lod > 0.0f || sweeps_parameter(args, "lod"))) {
        throw std::invalid_argument("--vs embree compares tracers on the same triangles; levels of "
                                    "detail (--lod, --sweep lod=...) trace others: measure them with --error");
    }
#if !DYNRT_HAVE_EMBREE
    if (!args.vs.empty()) {
        throw std::runtime_error("--vs embree: this dynrt was built without Embree "
                                 "(install libembree-dev and reconfigure)");
    }
#endif
    if (!args.diff_image.empty()) {
        if (args.vs.empty()) {
            throw std::invalid_argument("--diff-image: shows where dynrt and another tracer "
                                        "disagree, so it needs --vs embree");
        }
        dynrt::check_image_path(args.diff_image);
    }
    if (!args.plot.empty() && std::filesystem::path(args.plot).extension() != ".png") {
        throw std::invalid_argument("--plot '" + args.plot + "': charts are written as .png");
    }
    if (sweeps_parameter(args, "reuse") && !(args.error && !args.frames.empty())) {
        throw std::invalid_argument("--sweep reuse=...: pixel reuse works across frames and "
                                    "is measured by its error: give --frames A-B and --error");
    }
    if (args.error) {
        return args.frames.empty() ? run_bench_error(args) : run_bench_sequence_error(args);
    }
    if (!args.frames.empty()) return run_bench_sequence(args);
    if (!args.anims.empty() || !args.treats.empty() || !args.clips.empty()) {
        // Refused rather than ignored: a still frame would time something other than asked.
        throw std::invalid_argument("bench: --anim, --treat and --clip animate a sequence: give "
                                    "--frames too");
    }
    const int repeat = args.repeat > 0 ? args.repeat : 5;
    dynrt::RenderOptions base = still_frame_options(args);
    const std::string source = scene_source(args);
    const dynrt::Stopwatch load_clock;
    const dynrt::Scene scene = load_scene_with_progress(source);
    const double load_ms = load_clock.elapsed_ms();
    apply_scene_setup(scene, args, base);
    // Culling items (if swept) vary slowest, then the build sweeps as expand_sweeps orders them.
    const std::vector<dynrt::reference::ErrorConfiguration> configs =
        bench_configurations(args, base);
    if (!args.plot.empty() &&
        (sweeps_parameter(args, "culling") || sweeps_parameter(args, "adaptive") || sweeps_parameter(args, "lod"))) {
        throw std::invalid_argument("--plot draws against a build parameter; it does not take "
                                    "a culling, adaptive or lod sweep (with --error it draws time "
                                    "against error for any sweep)");
    }
    const dynrt::Camera camera = camera_for(scene, args, base.pose);
    std::cout << "dynrt bench: " << source << ", " << scene.triangle_count() << " triangles, "
              << base.width << "x" << base.height << ", " << configs.size()
              << " configuration(s), median (min-max) of " << repeat << " runs after "
              << args.warmup << " warm-up\n";
    std::vector<dynrt::BenchRow> rows;
    // The first configuration's frame, to compare Embree's hits with.
    dynrt::RenderedFrame first_frame;
    for (const dynrt::reference::ErrorConfiguration& config : configs) {
        // One warm-up for the whole sweep: it pays for first-touch costs (thread pool
        // start, code and page faults) once; later configurations' medians do not need
        // their own.
        const int warmup = rows.empty() ? args.warmup : 0;
        rows.push_back(dynrt::bench_configuration(scene, camera, config.options, repeat, warmup,
                                                  rows.empty() ? &first_frame : nullptr));
    }
    dynrt::print_start_up(std::cout, load_ms, rows.front().first_ms, rows.front().textures);
    dynrt::print_bench_table(std::cout, rows);
    // CSV stays dynrt-only: its one-row-per-configuration layout has no place for Embree rows.
    if (!args.csv.empty()) write_text(args.csv, dynrt::bench_csv(rows));
    if (!args.plot.empty()) {
        std::ostringstream title;
        title << "dynrt bench: " << source << ", " << scene.triangle_count() << " triangles, "
              << base.width << "x" << base.height;
        dynrt::plot_bench(args.plot, rows, title.str());
        std::cout << "plot: " << args.plot << "\n";
    }
    std::string json = args.json.empty() ? std::string() : dynrt::bench_json(rows);
#if DYNRT_HAVE_EMBREE
    if (args.vs == "embree") {
        std::vector<dynrt::PixelAgreement> disagreement;
        const std::vector<dynrt::embree::EmbreeRow> embree_rows = dynrt::embree::bench_embree(
            scene, camera, base, repeat, args.warmup, first_frame,
            args.diff_image.empty() ? nullptr : &disagreement);
        std::cout << "\n";
        dynrt::embree::print_embree_table(std::cout, embree_rows, rows.front());
        if (!args.diff_image.empty()) {
            dynrt::write_disagreement_image(args.diff_image, first_frame, disagreement);
            const dynrt::HitAgreement counts = dynrt::count_disagreements(disagreement);
            std::cout << "diff image: " << args.diff_image << " (" << counts.object_differs
                      << " red pixels: hit/object differs; " << counts.prim_only_differs
                      << " yellow: primitive only; over all Embree qualities)\n";
        }
        // Whole frames through each backend behind the trace seam, stage by stage.
        const std::vector<dynrt::embree::StageRow> stages =
            dynrt::embree::bench_stages(scene, camera, base, repeat, args.warmup);
        std::cout << "\n";
        dynrt::embree::print_stage_table(std::cout, stages);
        // The reflection and refraction rays, when the frame has any.
        const dynrt::embree::SecondaryComparison secondary =
            dynrt::embree::bench_secondary_embree(scene, camera, base, repeat, args.warmup);
        if (secondary.packets > 0) {
            std::cout << "\n";
            dynrt::embree::print_secondary_table(std::cout, secondary);
        }
        if (!json.empty()) {
            nlohmann::ordered_json doc = nlohmann::ordered_json::parse(json);
            doc["embree"] = nlohmann::ordered_json::parse(dynrt::embree::embree_json(embree_rows));
            doc["stages"] = nlohmann::ordered_json::parse(dynrt::embree::stages_json(stages));
            if (secondary.packets > 0) {
                doc["embree_secondary"] = nlohmann::ordered_json::parse(dynrt::embree::secondary_json(secondary));
            }
            json = doc.dump(2) + "\n";
        }
    }
#endif
    if (!args.json.empty()) write_text(args.json, json);
    return 0;
}

}  // namespace dynrt::cli
