#pragma once
// What the `dynrt` commands share: the flags of `render` and `bench` (a frame, its view and its
// build settings), the scene they load with them, its camera, and the summaries they print.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/sequence.h"
#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace dynrt::cli {

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
    /// The tracer behind the trace seam: dynrt, or embree[-QUALITY] (RenderOptions::backend).
    std::string backend = "dynrt";
    std::string bvh = "wide";
    /// The static group's leaves: full (triangles copied into SIMD blocks) or compact.
    std::string leaves = "full";
    /// The static group's nodes: float or quantized.
    std::string nodes = "float";
    /// A budget for resident memory that picks the static group's layout (empty: none; then
    /// leaves and nodes say it).
    std::string memory_budget;
    std::string packet_culling = "all";
    float adaptive = 0.0f;
    /// RenderOptions::lod_pixels (`--lod`): 0, off.
    float lod = 0.0f;
    /// Shading normals (TraceSettings::smooth_normals): smooth (the vertex normals) or flat.
    std::string normals = "smooth";
    /// TraceSettings::occluder_cache: on or off.
    std::string occluder_cache = "off";
    /// TraceSettings::sampling: samples per pixel, the reconstruction filter and adaptive
    /// anti-aliasing's contrast (0: every pixel takes every sample).
    int spp = 1;
    std::string filter = dynrt::pixel_filter_name(dynrt::PixelSampling{}.filter);
    float aa_contrast = 0.0f;
    /// TraceSettings::background, "r,g,b" (linear, each finite and >= 0); empty: the scene
    /// file's own (BART's `b`), else the default.
    std::string background;
    /// TraceSettings::environment: an equirectangular image file, and what its texels are
    /// multiplied by; empty: none (the background).
    std::string environment;
    float environment_scale = 1.0f;
    /// TraceSettings::environment_lights: the environment as this many suns (0: none).
    int environment_lights = 0;
    /// Whitted secondary rays (TraceSettings::secondary): deepest bounce and path-weight cut-off.
    int depth = dynrt::SecondaryRays{}.max_depth;
    float cutoff = dynrt::SecondaryRays{}.cutoff;
    int secondary_packet_min = dynrt::SecondaryRays{}.min_packet_rays;
    /// Pixel reuse between frames (dynrt/engine/pixel_reuse.h): off, exact, cache[:BUDGET],
    /// frameless[:BUDGET].
    std::string reuse = "exact";
    // Animation: which motions, clips and classes, at what rate, which frames.
    std::vector<std::string> anims;
    std::vector<std::string> treats;
    std::vector<std::string> clips;
    bool loop = false;
    /// 0: the scene file's own frame rate (BART's `a`), else dynrt::anim::kDefaultFps.
    double fps = 0.0;
    std::string frames;
    std::string update = "auto";
    std::string builder = "sah";
    double rebuild_threshold = dynrt::RenderOptions{}.rebuild_threshold;
    float cost_ratio_exploding = dynrt::RenderOptions{}.exploding_cost_ratio;
};

struct RenderArgs : FrameArgs {
    std::string out = "dynrt.png";
    std::string contact_sheet;
    std::string report;
    std::string aov;
    /// The 8-bit files' exposure (stops) and tone curve (DisplayTransform); float files stay
    /// linear.
    float exposure = 0.0f;
    std::string tone = "linear";
    /// Across processes (`mpirun dynrt render`): "frames" (handed out in runs, the default
    /// under mpirun) or "tiles" (each frame's tiles shared); empty: not given.
    std::string distribute;
    /// Skip the frames an earlier run of the same job finished (their image and record).
    bool resume = false;
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
    /// 0: not given; 8 (one frame, --error without --frames).
    int error_block = 0;
    /// -1: not given; 24 when the scene moves, else 0.
    int error_frame = -1;
};

/// Splits "a,b,c" into finite floats; `what` names the flag in errors.
std::vector<float> parse_floats(const std::string& text, const std::string& what);

/// Parses --res WIDTHxHEIGHT (each 1..16384).
void parse_resolution(const std::string& text, int& width, int& height);

/// Parses --memory-budget: a byte count with an optional K, M, G or T (powers of 1000), at
/// least 1M.
std::size_t parse_memory_budget(const std::string& text);

/// Parses --light x,y,z[,intensity][:OPTION]...: a point light there, changed by each option:
/// sphere=RADIUS or quad=UX,UY,UZ,VX,VY,VZ (an area light centred there), spot=DX,DY,DZ,INNER,OUTER
/// (a spot along that axis, cone angles in degrees), directional (x,y,z is the direction of
/// travel), color=R,G,B, falloff (inverse square), range=R.
dynrt::PointLight parse_light(const std::string& text);

/// The options the flags give. The image size and frame rate are left 0 when not given:
/// load_animated_scene fills them from the scene.
dynrt::RenderOptions render_options(const FrameArgs& args);

/// What the flags `args` left open, from the scene file when it says (Scene::setup: BART's
/// image size, frame rate and background), else the defaults: 1024x1024 at 24 fps.
void apply_scene_setup(const dynrt::Scene& scene, const FrameArgs& args, dynrt::RenderOptions& options);

/// Parses --background r,g,b: three finite numbers >= 0.
glm::vec3 parse_background(const std::string& text);

/// dynrt::load_scene, telling on stderr how long it has taken and the memory it holds when it
/// is slow ("loading SOURCE: 6 s, 1.3 GB resident"; stage_progress.h).
dynrt::Scene load_scene_with_progress(const std::string& source);

/// The scene with the user's procedural motions added, and the pose settings that name its
/// objects and clips (class overrides and clip choices are checked against this scene); the
/// options the flags left open are filled from the scene (apply_scene_setup).
dynrt::Scene load_animated_scene(const FrameArgs& args, const std::string& source,
                                 dynrt::RenderOptions& options);

/// The last frame that shows new animation: the chosen clips' end at the frame rate (0 without
/// clips, whose scenes change only by procedural motions, which never end).
int animation_end_frame(const dynrt::Scene& scene, const dynrt::anim::PoseSettings& pose);

/// Warns on stderr when `range` runs past the end of the scene's animation, whose frames would
/// repeat its last pose (unless --loop plays it again).
void warn_past_the_end(const dynrt::Scene& scene, const dynrt::anim::PoseSettings& pose,
                       const dynrt::FrameRange& range);

/// `--frames N` is frame N alone, where dynrt before issue 34 (and some tools) read frames 0
/// to N-1: a render of one number N > 0 prints a line saying which frame it renders and how to
/// write a range, so that a script written for the old meaning is noticed at its first run.
void note_single_frame(std::ostream& out, const std::string& frames);

/// The scene argument, or the bundled scene when it is empty.
std::string scene_source(const FrameArgs& args);

/// `--camera scene` (or `gltf`): the scene's own (animated) camera, evaluated per frame; also
/// the default for a scene file that sets up its own view (BART's `v`).
bool uses_scene_camera(const FrameArgs& args, const dynrt::Scene& scene);

/// Where the camera of frames `frames` comes from: the scene's own when it is used (the renderer
/// reads it from each frame's pose), else the one --camera describes or the default framing,
/// which frames the scene's bounds over all of `frames` (so moving parts stay in the picture).
dynrt::CameraSource camera_source(const dynrt::Scene& scene, const FrameArgs& args,
                                  const dynrt::anim::PoseSettings& pose, dynrt::FrameRange frames);

/// The camera of one frame, `frames.first`, for the still-frame benches, which take a camera:
/// camera_source's, with the scene's own posed at that frame.
dynrt::Camera camera_for(const dynrt::Scene& scene, const FrameArgs& args,
                         const dynrt::anim::PoseSettings& pose, dynrt::FrameRange frames = {});

/// One line per thing the scene file says that dynrt leaves out (Scene::ignored).
void print_ignored(std::ostream& out, const dynrt::Scene& scene);

/// "rebuilds: 3 (first build 2, sah degraded 1)", over all frames.
/// The automatic update method's choices: one line per object and frame for up to 8 frames,
/// "refit: refits' extra trace 3.1 ms so far (0.4 this frame) < rebuild (fast) 35.2 ms", then
/// their counts.
void print_update_choices(std::ostream& out, const std::vector<dynrt::FrameStats>& frames);

void print_rebuild_summary(std::ostream& out, const std::vector<dynrt::FrameStats>& frames);

/// Writes `text` to `path`; throws when it cannot.
void write_text(const std::string& path, const std::string& text);

/// The commands, one file each (render_command.cpp, bench_command.cpp, info_command.cpp);
/// each returns the process's exit code and throws on bad input.
int run_render(const RenderArgs& args);
int run_bench(const BenchArgs& args);
int run_info(const std::string& source);

}  // namespace dynrt::cli
