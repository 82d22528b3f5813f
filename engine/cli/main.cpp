// The `dynrt` command line: its flags and subcommands. Each command is a file of its own
// (render_command.cpp, bench_command.cpp, info_command.cpp); what they share is frame_args.h.

#include "command_warnings.h"
#include "distributed/distributed_render.h"
#include "frame_args.h"
#include "view_command.h"
#include "../viewer/viewer_script.h"

#include "dynrt/engine/environment_lights.h"

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

using dynrt::cli::BenchArgs;
using dynrt::cli::FrameArgs;
using dynrt::cli::RenderArgs;

namespace {

/// The arguments CLI11 names in "The following argument(s) were not expected: a b".
std::string join_args(const std::string& message) {
    const std::size_t colon = message.rfind(": ");
    return colon == std::string::npos ? message : message.substr(colon + 2);
}

/// The exit codes (docs/rendering.md, "Exit codes" under "Command line"): 0 done, 1 a failure while running (a scene file that
/// cannot be read, an output that cannot be written, a failing MPI rank), 2 a usage error (a
/// bad flag or value, found by CLI11 or by our own checks before anything is rendered).
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

/// The error line, written at once: under mpirun each write is forwarded on its own and
/// another process's output could otherwise land in the middle of the line.
void print_error(const std::string& text) {
    std::cerr << ("dynrt: error: " + text + "\n") << std::flush;
}

/// CLI11's message for a bad command line, in plain words where its own are not: an option
/// given twice ("--res: At Most 1 required but received 2") or an unexpected argument.
std::string usage_error_text(const CLI::ParseError& e) {
    const std::string message = e.what();
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
        // CLI11 says "The following argument was not expected: X"; name the rule instead.
        return "unexpected argument(s) '" + join_args(message) + "': render, bench and info "
               "take one SCENE, and every other value follows its option (see --help)";
    }
    const std::size_t at_most = message.find(": At Most 1 required");
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && at_most != std::string::npos) {
        return message.substr(0, at_most) + ": given more than once; give it once (only "
               "--light, --anim, --treat, --clip and --sweep repeat)";
    }
    return message;
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

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"dynrt: real-time ray tracing of animated triangle scenes on CPUs"};
    app.set_version_flag("--version", std::string("dynrt ") + DYNRT_VERSION);
    app.require_subcommand(1);
    app.footer("Exit codes: 0 done; 1 a failure while running (a scene that cannot be read, an "
               "output that cannot be written); 2 a usage error (a bad flag or value, or "
               "--resume with other settings), found before anything is rendered.");
    int threads = 0;
    app.add_option("--threads", threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));

    bool quiet = false, verbose = false;
    const auto add_verbosity = [&](CLI::App* cmd, const std::string& quiet_help) {
        CLI::Option* q = cmd->add_flag("--quiet,-q", quiet, quiet_help);
        cmd->add_flag("--verbose,-v", verbose,
                      "Every warning on a line of its own (by default each kind of problem is "
                      "one line, with a count and the first few names)")
            ->excludes(q);
    };
    const std::string quiet_frames =
        "Errors only: no warnings, progress bar or table (the files written and the exit "
        "status say the rest)";

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
                        "camera, animated; the default for a BART (.aff) scene; or still: the "
                        "scene's camera at the first frame, held still");
        cmd->add_option("--light", args.lights,
                        "Light x,y,z[,intensity], a point, then options: an area light centred there "
                        "with :sphere=RADIUS or :quad=UX,UY,UZ,VX,VY,VZ (its two edges), sampled once "
                        "per pixel sample (soft shadows); :spot=DX,DY,DZ,INNER,OUTER (axis, cone in "
                        "degrees); :directional (x,y,z is the direction of travel); :color=R,G,B; "
                        ":falloff (inverse square); :range=R. Repeatable (default: the scene's lights, "
                        "or one point light above)")
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
        cmd->add_option("--backend", args.backend,
                        "What traces the rays behind the trace seam: dynrt (its own tracers, "
                        "--tracer) or Embree when built with it: embree (medium build quality), "
                        "embree-low, embree-medium, embree-high or embree-refit; the same frames, "
                        "rays and shading either way")
            ->check(CLI::IsMember({"dynrt", "embree", "embree-low", "embree-medium", "embree-high",
                                   "embree-refit"}))
            ->capture_default_str();
        cmd->add_option("--bvh", args.bvh,
                        "Tree packets and single rays trace: wide (8 children per node, "
                        "triangles in SIMD blocks of 4) or binary; the same hits either way")
            ->check(CLI::IsMember({"wide", "binary"}))->capture_default_str();
        CLI::Option* leaves = cmd->add_option("--leaves", args.leaves,
                        "Leaves of the static and moving objects' trees: full (each triangle's "
                        "corners copied into the tree's SIMD blocks) or compact (its index only, "
                        "the corners read from the scene's or the posed vertices: about 40 bytes "
                        "a triangle fewer); the same hits either way")
            ->check(CLI::IsMember({"full", "compact"}))->capture_default_str();
        CLI::Option* nodes = cmd->add_option("--nodes", args.nodes,
                        "Nodes of the static objects' tree: float (child boxes as floats, 256 "
                        "bytes a node) or quantized (8-bit planes on each node's own grid, 128 "
                        "bytes); the same hits either way")
            ->check(CLI::IsMember({"float", "quantized"}))->capture_default_str();
        cmd->add_option("--memory-budget", args.memory_budget,
                        "Resident memory the render may take, e.g. 2G, 1500M (powers of 1000): "
                        "the static objects' tree is built with the fastest layout (full, then "
                        "compact leaves, then compact leaves and quantized nodes) whose build is "
                        "predicted to stay within it; the report gives the choice and the "
                        "prediction. Replaces --leaves and --nodes")
            ->excludes(leaves)
            ->excludes(nodes);
        cmd->add_option("--packet-culling", args.packet_culling,
                        "Packet culling stages: ab,bp,edge,nf (any subset), all or none")
            ->capture_default_str();
        cmd->add_option("--adaptive", args.adaptive,
                        "Approximate: trace each tile on a sparse grid and interpolate cells "
                        "whose samples agree within this tolerance (packet tracer; 0: exact)")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--lod", args.lod,
                        "Approximate: trace each static or rigid mesh with the coarsest of its "
                        "simplified meshes whose error covers at most this many pixels (0: off)")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--normals", args.normals,
                        "Shading normals: smooth (the file's vertex normals interpolated, or "
                        "area-weighted ones where it has none) or flat (each triangle's own)")
            ->check(CLI::IsMember({"smooth", "flat"}))->capture_default_str();
        cmd->add_option("--spp", args.spp,
                        "Samples per pixel, stratified and the same on any number of threads; "
                        "1 (the default) is each pixel's centre")
            ->check(CLI::Range(1, dynrt::PixelSampling::kMaxSamplesPerPixel))->capture_default_str();
        cmd->add_option("--filter", args.filter,
                        "Reconstruction filter of several samples per pixel: box, tent or "
                        "blackman-harris (1.5 pixels wide)")
            ->check(CLI::IsMember({"box", "tent", "blackman-harris"}))->capture_default_str();
        cmd->add_option("--aa-contrast", args.aa_contrast,
                        "Adaptive anti-aliasing: every pixel takes one sample, and only those "
                        "differing from a neighbour by more than this (per channel, or showing "
                        "another object) take --spp (0: every pixel takes --spp)")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--background", args.background,
                        "Colour of pixels whose ray meets nothing, linear r,g,b (default: the scene "
                        "file's own, as BART's files give it, else 0.05,0.06,0.08)");
        cmd->add_option("--environment", args.environment,
                        "Equirectangular image (.exr, .hdr, ...) that rays leaving the scene see, "
                        "camera rays and reflections alike; +Y up, its centre looking down -Z "
                        "(default: none, the --background colour)");
        cmd->add_option("--environment-scale", args.environment_scale,
                        "What the environment's texels are multiplied by")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--environment-lights", args.environment_lights,
                        "Light the scene with the environment as this many suns, cut from it by "
                        "median cut, each casting shadows (0: it lights nothing); needs --environment")
            ->check(CLI::Range(0, dynrt::kEnvironmentLightsMax))->capture_default_str();
        cmd->add_option("--occluder-cache", args.occluder_cache,
                        "Test each packet of shadow rays first against the triangles that last "
                        "blocked its light's rays in those directions (the same image either way)")
            ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
        cmd->add_option("--depth", args.depth,
                        "Deepest reflection or refraction bounce traced (Whitted; 0: camera and "
                        "shadow rays only). Frames with secondary rays trace every pixel")
            ->check(CLI::Range(0, 64))->capture_default_str();
        cmd->add_option("--cutoff", args.cutoff,
                        "A reflection or refraction ray is traced only while a channel of its "
                        "path's weight is at least this")
            ->check(CLI::Range(0.0, 1.0))->capture_default_str();
        cmd->add_option("--secondary-packet-min", args.secondary_packet_min,
                        "Reflection or refraction rays, sorted across the frame into packets of "
                        "up to 256, go as a packet when at least this many of one share a direction "
                        "octant, else one by one (same image; 0: always packets, 257: never)")
            ->check(CLI::Range(0, 257))->capture_default_str();
        cmd->add_option("--reuse", args.reuse,
                        "Reuse of the previous frame's pixels: exact (re-trace only rays that "
                        "may meet what moved; the same image as off), off, or approximate "
                        "cache[:BUDGET] (render cache, for moving cameras) and "
                        "frameless[:BUDGET]; BUDGET is a share of the pixels (0.25) or ms (8ms)")
            ->check([](const std::string& text) {
                try {
                    dynrt::parse_reuse(text);
                    return std::string();
                } catch (const std::invalid_argument& e) {
                    return std::string(e.what());
                }
            })
            ->capture_default_str();
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
                        "N (frame N alone, as Blender's -f N) or A-B (frames A to B, both "
                        "included: 0-47 is 48 frames); default frame 0");
        cmd->add_option("--builder", args.builder,
                        "Builder of the trees that --update does not choose for (static, rigid "
                        "and first builds): sah (binned SAH) or morton (the fast builder)")
            ->check(CLI::IsMember({"sah", "morton"}))->capture_default_str();
        cmd->add_option("--update", args.update,
                        "How deformable and exploding objects' trees are updated: auto (refit, "
                        "fast rebuild or SAH rebuild, whichever the measured build and trace "
                        "times predict cheaper), threshold (refit, SAH rebuild past "
                        "--rebuild-threshold), refit, fast (Morton rebuild every frame) or sah")
            ->check(CLI::IsMember({"auto", "threshold", "refit", "fast", "sah"}))
            ->capture_default_str();
        cmd->add_option("--rebuild-threshold", args.rebuild_threshold,
                        "With --update threshold: rebuild a deformable object's tree when "
                        "refitting has raised its SAH cost by more than this fraction of the "
                        "cost at its last build")
            ->check(CLI::NonNegativeNumber)->capture_default_str();
        cmd->add_option("--cost-ratio-exploding", args.cost_ratio_exploding,
                        "Cost ratio of the per-frame rebuilds of exploding objects")
            ->check(kPositive)->capture_default_str();
    };

    RenderArgs render;
    CLI::App* render_cmd = app.add_subcommand("render", "Render a scene to an image and report timings");
    add_frame_options(render_cmd, render);
    add_verbosity(render_cmd, quiet_frames);
    render_cmd->add_option("--out", render.out,
                           "Output image, format by extension; for several frames a numbered "
                           "name ('frames/%04d.png'), one animated .gif or a video (.mp4, .mov, "
                           ".mkv, .webm, .avi; needs ffmpeg). Files are written on a writer "
                           "thread beside the render, each whole or not at all. A numbered "
                           "render keeps a journal of its frames, so an interrupted one "
                           "(Ctrl-C, SIGTERM: it stops after the frame at hand, exit 130/143) "
                           "can be finished with --resume")
        ->capture_default_str();
    render_cmd->add_option("--contact-sheet", render.contact_sheet,
                           "Also write the frames as thumbnails in a grid (up to 64, spread "
                           "over the sequence) to this image");
    render_cmd->add_option("--report", render.report, "Write the frame report as JSON to this file");
    render_cmd->add_option("--aov", render.aov,
                           "Also write float EXRs next to the image: depth,object,prim,normal,cost "
                           "(cost: each pixel's camera-ray node visits and triangle tests, "
                           "docs/viewer.md)");
    render_cmd->add_option("--exposure", render.exposure,
                           "Exposure of the 8-bit images, GIFs, videos and contact sheet, in stops "
                           "(colours times 2^stops before the tone curve); float images stay linear")
        ->check(CLI::Range(-64.0f, 64.0f))->capture_default_str();
    render_cmd->add_option("--tone", render.tone,
                           "Tone curve of the 8-bit outputs: linear (clips above 1), reinhard or aces "
                           "(filmic); float images stay linear")
        ->check(CLI::IsMember({"linear", "reinhard", "aces"}))->capture_default_str();
    render_cmd->add_option("--distribute", render.distribute,
                           "Under mpirun: frames (the default; each process renders runs of "
                           "frames it asks for) or tiles (every process renders its share of "
                           "each frame's 16x16 tiles, gathered by rank 0)")
        ->check(CLI::IsMember({"frames", "tiles"}));
    render_cmd->add_flag("--resume", render.resume,
                         "Skip the frames whose image and record an earlier run of the same "
                         "render left (its journal: REPORT.frames.jsonl, or .dynrt-frames.jsonl "
                         "beside the frames, which every numbered render keeps), e.g. after a "
                         "render was interrupted (Ctrl-C, SIGTERM) or a job killed");

    BenchArgs bench;
    // A benchmark times tracing: a still frame timed again would reuse every pixel, and a
    // comparison with Embree must trace the same rays. `--reuse exact` measures reuse itself.
    bench.reuse = "off";
    CLI::App* bench_cmd = app.add_subcommand(
        "bench", "Time a scene's frame under one or more build configurations");
    add_frame_options(bench_cmd, bench);
    add_verbosity(bench_cmd, quiet_frames);
    bench_cmd->add_option("--repeat", bench.repeat,
                          "Timed runs per configuration (default 5; with --frames, runs of the "
                          "whole sequence, default 1)")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    bench_cmd->add_option("--warmup", bench.warmup, "Untimed runs before them")
        ->check(CLI::Range(0, 1000))->capture_default_str();
    bench_cmd->add_option("--sweep", bench.sweeps,
                          "cost-ratio=V1,V2,..., leaf=N1,N2,..., culling=C1,C2,... (packet "
                          "culling, '+' joining stages: culling=none,ab,ab+bp,ab+bp+nf), "
                          "adaptive=T1,T2,... (tolerances, packet tracer), lod=P1,P2,... "
                          "(levels of detail, pixels) or, with --error, update=rebuild,refit; with --frames and --error, only "
                          "reuse=off,exact,cache:0.25,frameless:8ms,... (pixel reuse modes "
                          "and budgets), adaptive=... and lod=...; repeatable, combined as a cross "
                          "product")
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
        "without --frames. With --frames A-B: every frame of each reuse/adaptive "
        "configuration against the full render of that frame (PSNR, SSIM, wrong pixels); "
        "--plot draws ms per frame against 1 - mean SSIM");
    bench_cmd->add_option("--error-block", bench.error_block,
                          "With --error: one sampled pixel, chosen at random, per BxB block "
                          "(1: every pixel; default 8; not with --frames)")
        ->check(CLI::Range(1, 1024))->needs(error_flag);
    bench_cmd->add_option("--error-frame", bench.error_frame,
                          "With --error: the frame measured (default 24 when the scene moves, "
                          "else 0); with --sweep update=refit the frames before it are updated "
                          "first")
        ->check(CLI::Range(0, 100000))->needs(error_flag);

    std::string info_scene;
    dynrt::viewer::ViewArgs view;
    view.reuse = "exact";
    CLI::App* view_cmd = app.add_subcommand(
        "view", "Open a window on a scene: orbit (left drag), pan (right drag), zoom (wheel), fly (W A S D "
                "Q E), play or pause (space), step (arrows), reset the view (R), screenshot (F12), with its "
                "figures live and its settings changed on the fly");
    add_frame_options(view_cmd, view);
    add_verbosity(view_cmd, "Errors only: no warnings");
    view_cmd->add_option("--script", view.script,
                         "Drive the window from a file of timed commands, one per line: SECONDS COMMAND ARGS "
                         "(for tests under xvfb-run and demos); the commands:\n" +
                             dynrt::viewer::script_commands_help());
    view_cmd->add_option("--record", view.record,
                         "Write the frames the window draws to an animated .gif or a video (.mp4, ...; "
                         "needs ffmpeg), at the scene's frame rate, the panels left out");
    view_cmd->add_option("--exposure", view.exposure, "Exposure of the shown image, in stops")
        ->check(CLI::Range(-64.0f, 64.0f))->capture_default_str();
    view_cmd->add_option("--tone", view.tone, "Tone curve of the shown image: linear, reinhard or aces")
        ->check(CLI::IsMember({"linear", "reinhard", "aces"}))->capture_default_str();

    CLI::App* info_cmd = app.add_subcommand("info", "Describe a scene: objects, triangles, bounds");
    info_cmd->add_option("scene", info_scene, "glTF file, BART file (.aff) or procedural spec")->required();
    add_verbosity(info_cmd, "No warnings, only the description");

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);  // --help, --version: printed, exit 0
    } catch (const CLI::ParseError& e) {
        print_error(usage_error_text(e));
        return kExitUsage;
    }

    try {
        // Warnings are grouped and printed between the command's steps (command_warnings.h);
        // what is left when it ends or fails comes before the error line.
        const dynrt::cli::Verbosity verbosity = quiet     ? dynrt::cli::Verbosity::quiet
                                                : verbose ? dynrt::cli::Verbosity::verbose
                                                          : dynrt::cli::Verbosity::normal;
        const dynrt::cli::CommandWarnings warnings(verbosity);
        if (quiet && !*info_cmd) std::cout.setstate(std::ios::failbit);
        FrameArgs& frame_args = *bench_cmd  ? static_cast<FrameArgs&>(bench)
                                : *view_cmd ? static_cast<FrameArgs&>(view)
                                            : render;
        const int thread_count = frame_args.threads > 0 ? frame_args.threads : threads;
        std::optional<tbb::global_control> limit;
        if (thread_count > 0) {
            limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(thread_count));
        }
        frame_args.threads = thread_count;
        if (*render_cmd) {
            // Across processes, or resumable: the distributed driver, with this process alone
            // when not started by mpirun.
            if (dynrt::cli::started_by_mpirun() || render.resume || !render.distribute.empty()) {
                if (render.distribute.empty()) render.distribute = "frames";
                std::unique_ptr<dynrt::cli::Cluster> cluster;
                if (dynrt::cli::started_by_mpirun()) cluster = dynrt::cli::mpi_cluster();
                if (!cluster) {
                    if (dynrt::cli::started_by_mpirun()) {
                        dynrt::warn({.kind = "this dynrt was built without MPI",
                                     .effect = "each process started by mpirun renders every "
                                               "frame alone"});
                    }
                    cluster = dynrt::cli::local_cluster();
                }
                return dynrt::cli::run_distributed_render(render, *cluster);
            }
            return dynrt::cli::run_render(render);
        }
        if (*bench_cmd) return dynrt::cli::run_bench(bench);
        if (*view_cmd) return dynrt::cli::run_view(view);
        return dynrt::cli::run_info(info_scene);
    } catch (const std::filesystem::filesystem_error& e) {
        // Not the library's "filesystem error: ..." but what failed, on which path, and why.
        print_error(e.path1().string() + ": " + e.code().message());
        return kExitFailure;
    } catch (const std::invalid_argument& e) {
        // Our own checks of the flags' values (and of --resume against its journal) throw
        // invalid_argument: a usage error, as CLI11's are. A scene file that cannot be read is
        // a SceneError (runtime_error): a failure.
        print_error(e.what());
        return kExitUsage;
    } catch (const std::exception& e) {
        print_error(e.what());
        return kExitFailure;
    }
}
