// The `dynrt` command line: render a scene to an image with a timing report, or describe a scene.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/bench.h"
#include "dynrt/engine/bench_plot.h"
#include "dynrt/engine/bench_sequence.h"
#include "dynrt/engine/hit_agreement.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/report.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/engine/sequence.h"
#include "dynrt/engine/sequence_output.h"
#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/scene/scene_error.h"

#include "error_bench.h"

#if DYNRT_HAVE_EMBREE
#include "dynrt/embree/embree_tracer.h"
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

/// What `render` and `bench` share: the scene, the view and the build settings.
struct FrameArgs {
    std::string scene;
    /// Empty: the scene file's own image size (BART's `v`), else 1024x1024.
    std::string res;
    std::string camera;
    std::vector<std::string> lights;
    float cost_ratio = dynrt::bvh::BuildConfig{}.cost_ratio;
    unsigned leaf_size = dynrt::bvh::BuildConfig{}.leaf_size_max;
    int threads = 0;
    std::string tracer = "packet";
    std::string bvh = "wide";
    std::string packet_culling = "all";
    float adaptive = 0.0f;
    // Animation: which motions, clips and classes, at what rate, which frames.
    std::vector<std::string> anims;
    std::vector<std::string> treats;
    std::vector<std::string> clips;
    bool loop = false;
    /// 0: the scene file's own frame rate (BART's `a`), else dynrt::anim::kDefaultFps.
    double fps = 0.0;
    std::string frames;
    double rebuild_threshold = dynrt::RenderOptions{}.rebuild_threshold;
    float cost_ratio_exploding = dynrt::RenderOptions{}.cost_ratio_exploding;
};

struct RenderArgs : FrameArgs {
    std::string out = "dynrt.png";
    std::string contact_sheet;
    std::string report;
    std::string aov;
};

struct BenchArgs : FrameArgs {
    /// 0: not given; 5 runs of a still frame, 1 run of a sequence (--frames).
    int repeat = 0;
    int warmup = 1;
    std::vector<std::string> sweeps;
    std::string csv;
    std::string json;
    std::string vs;
    std::string plot;
    std::string diff_image;
    bool hit_buffers = false;
    /// --error: each configuration's error against the exact reference beside its time.
    bool error = false;
    int error_block = 8;
    /// -1: not given; 24 when the scene moves, else 0.
    int error_frame = -1;
};

/// Splits "a,b,c" into finite floats; `what` names the flag in errors.
std::vector<float> parse_floats(const std::string& text, const std::string& what) {
    std::vector<float> values;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        float v = 0.0f;
        const char* first = text.data() + start;
        const char* last = text.data() + comma;
        const auto [ptr, ec] = std::from_chars(first, last, v);
        if (ec != std::errc() || ptr != last || !std::isfinite(v)) {
            throw std::invalid_argument(what + " '" + text + "': '" + std::string(first, last) +
                                        "' is not a finite number");
        }
        values.push_back(v);
        if (comma == text.size()) break;
        start = comma + 1;
    }
    return values;
}

void parse_resolution(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find('x');
    int w = 0, h = 0;
    const auto parse = [](const char* first, const char* last, int& v) {
        const auto [ptr, ec] = std::from_chars(first, last, v);
        return ec == std::errc() && ptr == last;
    };
    if (x == std::string::npos || !parse(text.data(), text.data() + x, w) ||
        !parse(text.data() + x + 1, text.data() + text.size(), h) || w < 1 || h < 1 ||
        w > 16384 || h > 16384) {
        throw std::invalid_argument("--res '" + text +
                                    "': expected WIDTHxHEIGHT, each from 1 to 16384");
    }
    width = w;
    height = h;
}

dynrt::PointLight parse_light(const std::string& text) {
    const std::vector<float> v = parse_floats(text, "--light");
    if (v.size() != 3 && v.size() != 4) {
        throw std::invalid_argument("--light '" + text + "': expected x,y,z or x,y,z,intensity");
    }
    if (v.size() == 4 && !(v[3] >= 0.0f)) {
        throw std::invalid_argument("--light '" + text + "': the intensity must be >= 0");
    }
    return dynrt::PointLight{glm::vec3(v[0], v[1], v[2]), v.size() == 4 ? v[3] : 1.0f};
}

/// The options the flags give. The image size and frame rate are left 0 when not given:
/// load_animated_scene fills them from the scene.
dynrt::RenderOptions render_options(const FrameArgs& args) {
    dynrt::RenderOptions options;
    options.width = options.height = 0;
    if (!args.res.empty()) parse_resolution(args.res, options.width, options.height);
    options.build.cost_ratio = args.cost_ratio;
    options.build.leaf_size_max = args.leaf_size;
    options.build.wide = args.bvh == "wide";
    for (const std::string& light : args.lights) options.lights.push_back(parse_light(light));
    options.tracer = args.tracer == "single" ? dynrt::Tracer::single : dynrt::Tracer::packet;
    options.packet.culling = dynrt::packet::PacketCulling::parse(args.packet_culling);
    options.adaptive_tolerance = args.adaptive;
    options.pose.fps = args.fps;
    options.rebuild_threshold = args.rebuild_threshold;
    options.cost_ratio_exploding = args.cost_ratio_exploding;
    return options;
}

/// What the flags left open, from the scene file when it says (Scene::setup: BART's image
/// size, frame rate and background), else the defaults: 1024x1024 at 24 fps.
void apply_scene_setup(const dynrt::Scene& scene, dynrt::RenderOptions& options) {
    const std::optional<dynrt::SceneSetup>& setup = scene.setup;
    if (options.width == 0) {
        options.width = setup ? setup->width : 1024;
        options.height = setup ? setup->height : 1024;
    }
    if (options.pose.fps == 0.0) options.pose.fps = setup ? setup->fps : dynrt::anim::kDefaultFps;
    if (setup) options.background = setup->background;
}

/// The scene with the user's procedural motions added, and the pose settings that name its
/// objects and clips (class overrides and clip choices are checked against this scene); the
/// options the flags left open are filled from the scene (apply_scene_setup).
dynrt::Scene load_animated_scene(const FrameArgs& args, const std::string& source,
                                 dynrt::RenderOptions& options) {
    dynrt::Scene scene = dynrt::load_scene(source);
    apply_scene_setup(scene, options);
    dynrt::anim::add_procedural_motions(scene, args.anims);
    options.pose.class_overrides = dynrt::anim::parse_class_overrides(scene, args.treats);
    std::vector<std::size_t> clips;
    if (!args.clips.empty()) {
        for (const std::string& clip : args.clips) clips.push_back(dynrt::anim::find_clip(scene, clip));
    } else {
        clips = dynrt::anim::default_clips(scene);
        if (clips.size() == 1 && scene.clips.size() > 1) {
            std::cout << "clips: playing '" << scene.clips[0].name << "', the first of "
                      << scene.clips.size() << " that animate the same nodes (";
            for (std::size_t i = 0; i < scene.clips.size(); ++i) {
                std::cout << (i ? ", " : "") << "'" << scene.clips[i].name << "'";
            }
            std::cout << "); --clip picks others (dynrt info lists them)\n";
        }
    }
    options.pose.clips = clips;
    options.pose.loop = args.loop;
    return scene;
}

/// The last frame that shows new animation: the chosen clips' end at the frame rate (0 without
/// clips, whose scenes change only by procedural motions, which never end).
int animation_end_frame(const dynrt::Scene& scene, const dynrt::anim::PoseSettings& pose) {
    double end = 0.0;
    for (const std::size_t c : pose.clips.value_or(std::vector<std::size_t>{})) {
        end = std::max(end, scene.clips[c].end_time());
    }
    return int(std::min(std::ceil(end * pose.fps), double(dynrt::kFrameMax)));
}

/// Warns on stderr when `range` runs past the end of the scene's animation, whose frames would
/// repeat its last pose (unless --loop plays it again).
void warn_past_the_end(const dynrt::Scene& scene, const dynrt::anim::PoseSettings& pose,
                       const dynrt::FrameRange& range) {
    // A BART file names its own sequence (`a`): frames beyond it repeat its last state too.
    if (scene.setup && range.last >= scene.setup->frame_count && !pose.loop) {
        std::cerr << "warning: frames " << std::max(range.first, scene.setup->frame_count) << "-"
                  << range.last << " are past the file's own sequence (frames 0-"
                  << scene.setup->frame_count - 1 << ")\n";
        return;
    }
    if (pose.loop || !pose.clips || pose.clips->empty()) return;
    const int end = animation_end_frame(scene, pose);
    if (range.last <= end) return;
    std::cerr << "warning: frames " << std::max(range.first, end + 1) << "-" << range.last
              << " are past the end of the animation (frame " << end << " at " << pose.fps
              << " fps) and repeat its last pose; --loop plays it again\n";
}

std::string scene_source(const FrameArgs& args) {
    return args.scene.empty() ? dynrt::default_scene_path().string() : args.scene;
}

/// `--camera scene` (or `gltf`): the scene's own (animated) camera, evaluated per frame; also
/// the default for a scene file that sets up its own view (BART's `v`).
bool uses_scene_camera(const FrameArgs& args, const dynrt::Scene& scene) {
    if (args.camera == "gltf" || args.camera == "scene") {
        if (scene.cameras.empty()) {
            throw std::invalid_argument("--camera " + args.camera + ": " + scene.source + " has no camera");
        }
        return true;
    }
    return args.camera.empty() && scene.setup && !scene.cameras.empty();
}

/// The camera of frames `frames`: the scene's own when it is used (posed at the first frame
/// with `pose`'s frame rate), else the one --camera describes or the default framing, which
/// frames the scene's bounds over all of `frames` (so moving parts stay in the picture).
dynrt::Camera camera_for(const dynrt::Scene& scene, const FrameArgs& args,
                         const dynrt::anim::PoseSettings& pose, dynrt::FrameRange frames = {}) {
    const int frame = frames.first;
    if (uses_scene_camera(args, scene)) {
        dynrt::anim::PoseSettings settings;
        settings.fps = pose.fps;
        settings.clips = pose.clips;
        dynrt::anim::PosedScene posed;
        dynrt::anim::pose_scene(scene, settings, frame, posed);
        return dynrt::camera_from_scene(*posed.camera);
    }
    const dynrt::Camera camera =
        dynrt::default_camera(dynrt::sequence_bounds(scene, pose, frames.first, frames.last));
    return args.camera.empty() ? camera : dynrt::parse_camera(args.camera, camera);
}

/// A one-line progress bar on stderr, redrawn in place, with the time left at the mean pace so
/// far; used only when stderr is a terminal.
void draw_progress(int done, int total, double ms_per_frame) {
    constexpr int kWidth = 30;
    const int filled = total > 0 ? done * kWidth / total : kWidth;
    const double left_s = double(total - done) * ms_per_frame / 1000.0;
    std::cerr << "\r[" << std::string(std::size_t(filled), '#')
              << std::string(std::size_t(kWidth - filled), ' ') << "] " << done << "/" << total
              << " frames, " << std::fixed << std::setprecision(1) << ms_per_frame
              << " ms/frame, " << std::setprecision(0) << left_s << " s left  " << std::flush;
    if (done == total) std::cerr << "\n";
}

/// One line per thing the scene file says that dynrt leaves out (Scene::ignored).
void print_ignored(std::ostream& out, const dynrt::Scene& scene) {
    for (const std::string& what : scene.ignored) out << "ignored: " << what << "\n";
}

/// "rebuilds: 3 (first build 2, sah degraded 1)", over all frames.
void print_rebuild_summary(std::ostream& out, const std::vector<dynrt::FrameStats>& frames) {
    std::vector<std::pair<std::string, int>> reasons;
    int total = 0;
    std::size_t skipped = 0, refitted = 0;
    for (const dynrt::FrameStats& f : frames) {
        skipped += f.objects_skipped;
        refitted += f.objects_refitted;
        for (const dynrt::TreeRebuild& r : f.rebuilds) {
            ++total;
            auto it = std::find_if(reasons.begin(), reasons.end(),
                                   [&](const auto& p) { return p.first == r.reason; });
            if (it == reasons.end()) reasons.emplace_back(r.reason, 1);
            else ++it->second;
        }
    }
    out << "object updates over " << frames.size() << " frame(s): " << skipped << " skipped, "
        << refitted << " refitted, " << total << " rebuilt";
    for (std::size_t i = 0; i < reasons.size(); ++i) {
        out << (i == 0 ? " (" : ", ") << reasons[i].first << " " << reasons[i].second;
    }
    out << (reasons.empty() ? "\n" : ")\n");
}

/// Fails before any rendering when a file could not be written afterwards because its folder
/// is missing; `label` names it in the message ("--report r.json").
void require_folder(const std::filesystem::path& path, const std::string& label) {
    const std::filesystem::path parent = path.parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent)) {
        throw std::invalid_argument(label + ": folder " + parent.string() + " does not exist");
    }
}

/// Fails before any rendering when the report could not be written afterwards: its folder
/// missing, or the path a folder.
void check_report_path(const std::filesystem::path& path) {
    if (std::filesystem::is_directory(path)) {
        throw std::invalid_argument("--report " + path.string() + ": is a folder");
    }
    require_folder(path, "--report " + path.string());
}

int run_render(const RenderArgs& args) {
    dynrt::RenderOptions options = render_options(args);
    const std::vector<dynrt::Aov> aovs = dynrt::parse_aov_list(args.aov);
    options.hit_buffers = !aovs.empty();
    const dynrt::FrameRange range =
        args.frames.empty() ? dynrt::FrameRange{} : dynrt::parse_frame_range(args.frames);
    // One file for the whole sequence: an animated GIF or a video, named without a frame number.
    const bool animated = dynrt::is_sequence_file(args.out) && !dynrt::has_frame_number(args.out);
    if (animated) dynrt::check_sequence_file(args.out);
    if (range.count() > 1 && !dynrt::has_frame_number(args.out) && !animated) {
        throw std::invalid_argument("--out '" + args.out + "': several frames need a frame "
                                    "number in the name, e.g. 'frames/%04d.png', or an "
                                    "animated .gif or a video (.mp4)");
    }
    if (animated && range.count() > 1 && !aovs.empty()) {
        throw std::invalid_argument("--aov with an animated --out '" + args.out +
                                    "': AOVs are one file per frame, so they need numbered "
                                    "frames ('frames/%04d.png')");
    }
    if (!args.contact_sheet.empty()) dynrt::check_image_path(args.contact_sheet);
    const std::filesystem::path first_path = dynrt::frame_path(args.out, range.first);
    // A numbered output ('frames/%04d.png', one frame or many) goes to a folder of its own,
    // which is made as renderers do, but only once the scene has loaded: a run that fails
    // before rendering leaves nothing behind. Until then only the format is checked.
    const bool makes_folder = dynrt::has_frame_number(args.out) && first_path.has_parent_path();
    if (animated) {
        // A sequence file's format was checked above (a video is not an image format).
        require_folder(first_path, args.out);
    } else {
        dynrt::check_image_path(makes_folder ? first_path.filename() : first_path);
    }
    if (!args.report.empty()) check_report_path(args.report);

    const std::string source = scene_source(args);
    const dynrt::Scene scene = load_animated_scene(args, source, options);
    warn_past_the_end(scene, options.pose, range);
    if (makes_folder) {
        std::filesystem::create_directories(first_path.parent_path());
        dynrt::check_image_path(first_path);
    }
    const bool scene_camera = uses_scene_camera(args, scene);
    const dynrt::Camera fixed_camera = camera_for(scene, args, options.pose, range);

    dynrt::Renderer renderer(options);
    dynrt::RenderedFrame frame;
    std::vector<dynrt::FrameStats> frames;
    const bool progress = range.count() > 1 && isatty(fileno(stderr));
    std::cout << "dynrt: " << source << ": " << scene.objects.size() << " objects, "
              << scene.triangle_count() << " triangles, " << options.width << "x"
              << options.height << ", frames " << range.first << "-" << range.last << " -> "
              << args.out << std::endl;
    double total_ms = 0.0;
    std::unique_ptr<dynrt::SequenceFile> sequence_file;
    if (animated) sequence_file = dynrt::open_sequence_file(args.out, options.pose.fps);
    std::optional<dynrt::ContactSheet> sheet;
    if (!args.contact_sheet.empty()) sheet.emplace(range.count());
    for (int f = range.first; f <= range.last; ++f) {
        renderer.update(scene, f);
        const dynrt::Camera camera =
            scene_camera ? dynrt::camera_from_scene(*renderer.posed().camera) : fixed_camera;
        renderer.trace(camera, frame);
        const std::string path = dynrt::frame_path(args.out, f);
        if (sequence_file) {
            sequence_file->add(frame);
        } else {
            dynrt::write_image(path, frame);
        }
        if (sheet) sheet->add(f - range.first, frame);
        for (dynrt::Aov aov : aovs) dynrt::write_aov(path, aov, frame);
        frames.push_back(frame.stats);
        total_ms += frame.stats.total_ms;
        if (progress) draw_progress(f - range.first + 1, range.count(), total_ms / double(frames.size()));
    }

    if (sequence_file) sequence_file->close();
    if (sheet) {
        sheet->write(args.contact_sheet);
        std::cout << "contact sheet: " << args.contact_sheet << " (" << sheet->size()
                  << " frames)\n";
    }
    if (frames.front().degenerate_skipped > 0) {
        std::cout << "degenerate triangles skipped: " << frames.front().degenerate_skipped << "\n";
    }
    print_ignored(std::cout, scene);
    dynrt::print_frame_header(std::cout);
    // A sequence prints its summary; every frame's figures are in the --report file.
    if (frames.size() <= 8) {
        for (const dynrt::FrameStats& f : frames) dynrt::print_frame_row(std::cout, f);
    }
    dynrt::print_summary(std::cout, frames);
    print_rebuild_summary(std::cout, frames);
    if (!args.report.empty()) {
        const dynrt::RunInfo run{source, options.width, options.height, options.build.cost_ratio,
                                 options.build.leaf_size_max,
                                 args.threads > 0 ? args.threads
                                                  : tbb::info::default_concurrency(),
                                 scene.ignored};
        dynrt::write_report(args.report, run, frames);
        std::cout << "report: " << args.report << "\n";
    }
    return 0;
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream file(path);
    file << text;
    if (!file) throw std::runtime_error(path + ": cannot write");
}

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
    const dynrt::Scene scene = load_animated_scene(args, source, options);
    warn_past_the_end(scene, options.pose, range);
    // The scene's own camera moves with the frames: nullopt asks for it frame by frame.
    std::optional<dynrt::Camera> camera;
    if (!uses_scene_camera(args, scene)) camera = camera_for(scene, args, options.pose, range);
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
        dynrt::bench_sequence(scene, camera, options, range, runs, args.warmup, others);
    dynrt::print_sequence_table(std::cout, bench);
    print_rebuild_summary(std::cout, bench.frames);
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
/// vary slowest, then update, then adaptive tolerances, then the build sweeps as expand_sweeps
/// orders them. Without an update sweep every configuration rebuilds.
std::vector<dynrt::reference::ErrorConfiguration> bench_configurations(
    const BenchArgs& args, const dynrt::RenderOptions& base) {
    std::vector<std::string> build_sweeps = args.sweeps;
    const std::vector<std::string> cullings = dynrt::take_culling_sweep(build_sweeps);
    std::vector<float> adaptives = dynrt::take_adaptive_sweep(build_sweeps);
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
                for (const dynrt::bvh::BuildConfig& build : builds) {
                    dynrt::reference::ErrorConfiguration config{base, update};
                    config.options.build = build;
                    config.options.adaptive_tolerance = adaptive;
                    if (!culling.empty()) {
                        config.options.packet.culling = dynrt::parse_culling_item(culling);
                    }
                    configs.push_back(config);
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
    if (!args.vs.empty() || !args.frames.empty()) {
        throw std::invalid_argument("bench --error measures one frame against the exact "
                                    "reference: drop --vs and --frames (pick the frame with "
                                    "--error-frame)");
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
        dynrt::reference::sample_reference(scene, camera, base, frame, args.error_block);
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

int run_bench(const BenchArgs& args) {
    if (!args.vs.empty() && args.vs != "embree") {
        throw std::invalid_argument("--vs '" + args.vs + "': the only tracer to compare with is "
                                    "'embree'");
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
    if (args.error) return run_bench_error(args);
    if (!args.frames.empty()) return run_bench_sequence(args);
    if (!args.anims.empty() || !args.treats.empty() || !args.clips.empty()) {
        // Refused rather than ignored: a still frame would time something other than asked.
        throw std::invalid_argument("bench: --anim, --treat and --clip animate a sequence: give "
                                    "--frames too");
    }
    const int repeat = args.repeat > 0 ? args.repeat : 5;
    dynrt::RenderOptions base = still_frame_options(args);
    const std::string source = scene_source(args);
    const dynrt::Scene scene = dynrt::load_scene(source);
    apply_scene_setup(scene, base);
    // Culling items (if swept) vary slowest, then the build sweeps as expand_sweeps orders them.
    const std::vector<dynrt::reference::ErrorConfiguration> configs =
        bench_configurations(args, base);
    if (!args.plot.empty() && (sweeps_parameter(args, "culling") ||
                               sweeps_parameter(args, "adaptive"))) {
        throw std::invalid_argument("--plot draws against a build parameter; it does not take "
                                    "a culling or adaptive sweep (with --error it draws time "
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
        if (!json.empty()) {
            nlohmann::ordered_json doc = nlohmann::ordered_json::parse(json);
            doc["embree"] = nlohmann::ordered_json::parse(dynrt::embree::embree_json(embree_rows));
            json = doc.dump(2) + "\n";
        }
    }
#endif
    if (!args.json.empty()) write_text(args.json, json);
    return 0;
}

int run_info(const std::string& source) {
    const dynrt::Scene scene = dynrt::load_scene(source);
    dynrt::anim::PosedScene posed;
    dynrt::anim::pose_scene(scene, 0, posed);
    std::cout << source << "\n";
    std::cout << std::left << std::setw(40) << "object" << std::right << std::setw(12)
              << "triangles" << std::setw(12) << "degenerate" << "  bounds (frame 0)\n";
    dynrt::bvh::Aabb all;
    std::size_t degenerate_total = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const dynrt::Object& object = scene.objects[i];
        const std::vector<glm::vec3>& p = posed.objects[i].positions;
        dynrt::bvh::Aabb bounds;
        std::size_t degenerate = 0;
        for (const glm::uvec3& t : object.mesh.triangles) {
            const dynrt::bvh::Triangle tri{p[t.x], p[t.y], p[t.z]};
            degenerate += dynrt::bvh::is_degenerate(tri);
            bounds.extend(tri.bounds());
        }
        all.extend(bounds);
        degenerate_total += degenerate;
        std::cout << std::left << std::setw(40) << object.name << std::right << std::setw(12)
                  << object.mesh.triangles.size() << std::setw(12) << degenerate << "  ["
                  << bounds.lo.x << ", " << bounds.lo.y << ", " << bounds.lo.z << "] - ["
                  << bounds.hi.x << ", " << bounds.hi.y << ", " << bounds.hi.z << "]\n";
    }
    std::cout << std::left << std::setw(40) << "total" << std::right << std::setw(12)
              << scene.triangle_count() << std::setw(12) << degenerate_total << "  ["
              << all.lo.x << ", " << all.lo.y << ", " << all.lo.z << "] - [" << all.hi.x << ", "
              << all.hi.y << ", " << all.hi.z << "]\n"
              << scene.objects.size() << " objects, " << scene.materials.size()
              << " materials, " << scene.lights.size() << " lights\n";
    // The timeline: frame rate and clips, as render and bench would play them.
    const double fps = scene.setup ? scene.setup->fps : dynrt::anim::kDefaultFps;
    std::cout << "frame rate: " << fps << " fps ("
              << (scene.setup ? "the file's" : "dynrt's default; the file gives none")
              << "; --fps changes it)\n";
    if (scene.setup) {
        std::cout << "sequence: frames 0-" << scene.setup->frame_count - 1 << " (the file's)\n";
    }
    if (scene.clips.empty()) {
        std::cout << "clips: none\n";
        return 0;
    }
    const std::vector<std::size_t> plays = dynrt::anim::default_clips(scene);
    std::cout << "clips: " << scene.clips.size();
    if (scene.clips.size() > 1) {
        std::cout << (plays.size() == 1 ? " (by default only the first plays: they animate the same nodes"
                                        : " (by default all play together: they animate different nodes")
                  << "; --clip NAME or index picks)";
    }
    std::cout << "\n" << std::left << std::setw(7) << "  index" << "  " << std::setw(32) << "name"
              << std::right << std::setw(10) << "start s" << std::setw(10) << "end s"
              << std::setw(12) << "duration s" << "  frames at " << fps << " fps\n";
    for (std::size_t i = 0; i < scene.clips.size(); ++i) {
        const dynrt::AnimationClip& clip = scene.clips[i];
        std::cout << "  " << std::left << std::setw(5) << i << "  " << std::setw(32) << clip.name
                  << std::right << std::fixed << std::setprecision(3) << std::setw(10)
                  << clip.start_time() << std::setw(10) << clip.end_time() << std::setw(12)
                  << clip.end_time() - clip.start_time() << "  "
                  << int(std::floor(clip.start_time() * fps)) << "-"
                  << int(std::ceil(clip.end_time() * fps)) << "\n"
                  << std::defaultfloat;
    }
    return 0;
}

}  // namespace

/// The arguments CLI11 names in "The following argument(s) were not expected: a b".
std::string join_args(const std::string& message) {
    const std::size_t colon = message.rfind(": ");
    return colon == std::string::npos ? message : message.substr(colon + 2);
}

/// CLI11's PositiveNumber prints its range bounds in full (300 digits); this says it plainly.
const CLI::Validator kPositive(
    [](std::string& value) -> std::string {
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || ptr != value.data() + value.size() || !std::isfinite(v) || !(v > 0.0)) {
            return "'" + value + "' is not a positive number";
        }
        return {};
    },
    "POSITIVE");

int main(int argc, char** argv) {
    CLI::App app{"dynrt: real-time ray tracing of animated triangle scenes on CPUs"};
    app.set_version_flag("--version", std::string("dynrt ") + DYNRT_VERSION);
    app.require_subcommand(1);
    int threads = 0;
    app.add_option("--threads", threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));

    const auto add_frame_options = [](CLI::App* cmd, FrameArgs& args) {
        cmd->add_option("scene", args.scene,
                        "glTF file (.gltf/.glb), BART file (.aff) or procedural spec (e.g. "
                        "sphere:100000); default: the bundled scene");
        cmd->add_option("--res", args.res,
                        "Image size WIDTHxHEIGHT (default: the scene file's own, as BART's "
                        "files give it, else 1024x1024)");
        cmd->add_option("--camera", args.camera,
                        "eye=x,y,z,target=x,y,z,up=x,y,z,fov=deg (any subset; default framing "
                        "from the scene bounds), or scene (also 'gltf'): the scene's first "
                        "camera, animated; the default for a BART (.aff) scene");
        cmd->add_option("--light", args.lights,
                        "Point light x,y,z[,intensity]; repeatable (default: one light above)")
            ->allow_extra_args(false);
        cmd->add_option("--cost-ratio", args.cost_ratio,
                        "SAH intersection:traversal cost (0.1 big shallow leaves, 1 small deep)")
            ->check(kPositive)->capture_default_str();
        cmd->add_option("--leaf-size", args.leaf_size, "Maximum triangles per leaf")
            ->check(CLI::Range(1u, 1024u))->capture_default_str();
        cmd->add_option("--threads", args.threads, "Worker threads (default: all cores)")
            ->check(CLI::Range(1, 1024));
        cmd->add_option("--tracer", args.tracer, "packet (16x16 ray packets) or single (one ray at a time)")
            ->check(CLI::IsMember({"packet", "single"}))->capture_default_str();
        cmd->add_option("--bvh", args.bvh,
                        "Tree packets and single rays trace: wide (8 children per node, "
                        "triangles in SIMD blocks of 4) or binary; the same hits either way")
            ->check(CLI::IsMember({"wide", "binary"}))->capture_default_str();
        cmd->add_option("--packet-culling", args.packet_culling,
                        "Packet culling stages: ab,bp,edge,nf (any subset), all or none")
            ->capture_default_str();
        cmd->add_option("--adaptive", args.adaptive,
                        "Approximate: trace each tile on a sparse grid and interpolate cells "
                        "whose samples agree within this tolerance (packet tracer; 0: exact)")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--anim", args.anims,
                        "Procedural motion MOTION[:OBJECT]: rigid, wave or explode, on every "
                        "object or the named one; repeatable")
            ->allow_extra_args(false);
        cmd->add_option("--treat", args.treats,
                        "NAME=CLASS: update object NAME as static, rigid, deformable or "
                        "exploding (only raising the class its animation implies); repeatable")
            ->allow_extra_args(false);
        cmd->add_option("--clip", args.clips,
                        "glTF animation to play, by name or index; repeatable (default: all "
                        "clips together)")
            ->allow_extra_args(false);
        cmd->add_flag("--loop", args.loop,
                      "Play the clips again from the start when the frames run past their end "
                      "(default: hold the last pose, with a warning)");
        cmd->add_option("--fps", args.fps,
                        "Frames per second: frame f is time f / fps (default: the scene file's "
                        "own, as BART's 'a' gives it, else 24)")
            ->check(kPositive);
        cmd->add_option("--frames", args.frames,
                        "A-B (frames A to B) or N (frames 0 to N-1); default frame 0");
        cmd->add_option("--rebuild-threshold", args.rebuild_threshold,
                        "Rebuild a deformable object's tree when refitting has raised its SAH "
                        "cost by more than this fraction of the cost at its last build")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--cost-ratio-exploding", args.cost_ratio_exploding,
                        "Cost ratio of the per-frame rebuilds of exploding objects")
            ->check(kPositive)->capture_default_str();
    };

    RenderArgs render;
    CLI::App* render_cmd = app.add_subcommand("render", "Render a scene to an image and report timings");
    add_frame_options(render_cmd, render);
    render_cmd->add_option("--out", render.out,
                           "Output image, format by extension; for several frames a numbered "
                           "name ('frames/%04d.png'), one animated .gif or a video (.mp4, .mov, "
                           ".mkv, .webm, .avi; needs ffmpeg)")
        ->capture_default_str();
    render_cmd->add_option("--contact-sheet", render.contact_sheet,
                           "Also write the frames as thumbnails in a grid (up to 64, spread "
                           "over the sequence) to this image");
    render_cmd->add_option("--report", render.report, "Write the frame report as JSON to this file");
    render_cmd->add_option("--aov", render.aov,
                           "Also write float EXRs next to the image: depth,object,prim,normal");

    BenchArgs bench;
    CLI::App* bench_cmd = app.add_subcommand(
        "bench", "Time a scene's frame under one or more build configurations");
    add_frame_options(bench_cmd, bench);
    bench_cmd->add_option("--repeat", bench.repeat,
                          "Timed runs per configuration (default 5; with --frames, runs of the "
                          "whole sequence, default 1)")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    bench_cmd->add_option("--warmup", bench.warmup, "Untimed runs before them")
        ->check(CLI::Range(0, 1000))->capture_default_str();
    bench_cmd->add_option("--sweep", bench.sweeps,
                          "cost-ratio=V1,V2,..., leaf=N1,N2,..., culling=C1,C2,... (packet "
                          "culling, '+' joining stages: culling=none,ab,ab+bp,ab+bp+nf), "
                          "adaptive=T1,T2,... (tolerances, packet tracer) or, with --error, "
                          "update=rebuild,refit; repeatable, combined as a cross product")
        ->allow_extra_args(false);
    bench_cmd->add_option("--csv", bench.csv, "Also write the rows as CSV to this file");
    bench_cmd->add_option("--json", bench.json,
                          "Also write the rows as JSON to this file (with --vs embree, the "
                          "Embree rows too, as \"embree\")");
    bench_cmd->add_option("--plot", bench.plot,
                          "Also draw build, trace and total ms against the swept parameter "
                          "into this PNG (with gnuplot; the script is kept as FILE.gp)");
    bench_cmd->add_option("--diff-image", bench.diff_image,
                          "With --vs embree: write an image marking the pixels whose hit "
                          "differs (red: hit/object, yellow: primitive only)");
    bench_cmd->add_option("--vs", bench.vs,
                          "Also bench another tracer on the same rays: embree (Embree 3 builds "
                          "low/medium/high, rtcIntersect1/16, rtcOccluded16, hit agreement)");
    bench_cmd->add_flag("--hit-buffers", bench.hit_buffers,
                        "Time frames that also fill the per-pixel depth, object, primitive and "
                        "normal buffers, as render --aov does (default: the colour only, as "
                        "render without --aov)");
    CLI::Option* error_flag = bench_cmd->add_flag(
        "--error", bench.error,
        "Also measure each configuration's error against the exact reference image of the "
        "same frame (on sampled pixels): share of hits that differ, RMSE and PSNR; --plot then "
        "draws total ms against RMSE with the Pareto front. Allows --anim, --treat and --clip "
        "without --frames");
    bench_cmd->add_option("--error-block", bench.error_block,
                          "With --error: one sampled pixel, chosen at random, per BxB block "
                          "(1: every pixel)")
        ->check(CLI::Range(1, 1024))->capture_default_str()->needs(error_flag);
    bench_cmd->add_option("--error-frame", bench.error_frame,
                          "With --error: the frame measured (default 24 when the scene moves, "
                          "else 0); with --sweep update=refit the frames before it are updated "
                          "first")
        ->check(CLI::Range(0, 100000))->needs(error_flag);

    std::string info_scene;
    CLI::App* info_cmd = app.add_subcommand("info", "Describe a scene: objects, triangles, bounds");
    info_cmd->add_option("scene", info_scene, "glTF file, BART file (.aff) or procedural spec")->required();

    try {
        app.parse(argc, argv);
    } catch (const CLI::ExtrasError& e) {
        // CLI11 says "The following argument was not expected: X"; name the rule instead.
        std::cerr << "dynrt: error: unexpected argument(s) '" << join_args(e.what()) << "': "
                  << "render, bench and info take one SCENE, and every other value follows its "
                     "option (see --help)\n";
        return 1;
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }

    try {
        FrameArgs& frame_args = *bench_cmd ? static_cast<FrameArgs&>(bench) : render;
        const int thread_count = frame_args.threads > 0 ? frame_args.threads : threads;
        std::optional<tbb::global_control> limit;
        if (thread_count > 0) {
            limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(thread_count));
        }
        frame_args.threads = thread_count;
        if (*render_cmd) return run_render(render);
        if (*bench_cmd) return run_bench(bench);
        return run_info(info_scene);
    } catch (const std::filesystem::filesystem_error& e) {
        // Not the library's "filesystem error: ..." but what failed, on which path, and why.
        std::cerr << "dynrt: error: " << e.path1().string() << ": " << e.code().message() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "dynrt: error: " << e.what() << "\n";
        return 1;
    }
}
