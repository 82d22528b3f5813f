#pragma once
// What `dynrt view` shows, without the window: the scene loaded as `dynrt render` loads it
// with the same flags, a Renderer kept for the whole session (its trees, pose state and
// textures survive every setting change), the orbit camera, the animation's clock, the
// settings the panel changes and the figures of recent frames. The window (viewer_window.h)
// draws its frames and turns input into its calls; tests drive it directly.

#include "orbit_camera.h"
#include "../cli/frame_args.h"

#include "dynrt/engine/display_transform.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/sequence_output.h"
#include "dynrt/scene/scene.h"

#include <deque>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace dynrt::viewer {

/// `dynrt view`'s flags: those of every frame command, and the viewer's own.
struct ViewArgs : cli::FrameArgs {
    /// A script of timed inputs (viewer_script.h); empty: the user drives.
    std::string script;
    /// The displayed image's exposure (stops) and tone curve, as `dynrt render`'s 8-bit files.
    float exposure = 0.0f;
    std::string tone = "linear";
    /// A GIF or video (.gif, .mp4, ...) the window's frames are written to as they are drawn,
    /// at the scene's frame rate; empty: none.
    std::string record;
    /// What the window shows (`set view`): "image", or the cost view's heat map of each
    /// pixel's camera-ray "nodes" (node visits) or "triangles" (triangle tests),
    /// dynrt/engine/pixel_cost.h.
    std::string view = "image";
    /// The heat map's white: this many visits or tests; 0 picks it per frame (cost_scale).
    int cost_scale = 0;
};

class ViewerSession {
public:
    /// Loads `args.scene` (the bundled scene when empty) with its motions, clips and camera as
    /// `dynrt render` would; the image is args.res or 640x480. Throws as the render command
    /// does: SceneError for a scene that cannot be read, std::invalid_argument for bad flags.
    explicit ViewerSession(const ViewArgs& args);

    // ---- Camera ----
    OrbitCamera& camera() { return camera_; }
    /// Back to the first view (the flags' or the scene's camera, else the default framing).
    void reset_camera() { camera_ = OrbitCamera(first_camera_); }
    /// The scene file's cameras, by name (glTF's, BART's view), in Scene::cameras order.
    std::vector<std::string> camera_names() const;
    /// Looks through the file's camera `index` as it is at the last frame rendered (frame 0
    /// before any): the orbit's target straight ahead of it, at the scene's centre's depth.
    /// Throws std::out_of_range for an index the scene does not have.
    void use_scene_camera(std::size_t index);

    // ---- Time ----
    void play() { playing_ = true; }
    void pause() { playing_ = false; }
    bool playing() const { return playing_; }
    /// Pauses and moves `frames` frames on (back when negative), within the animation.
    void step(int frames);
    /// Pauses at `frame` (clamped to the animation).
    void seek(int frame);
    void set_speed(double speed) { speed_ = speed; }
    double speed() const { return speed_; }
    void set_loop(bool loop) { loop_ = loop; }
    bool loop() const { return loop_; }
    /// While playing, moves the clock on by `seconds` of wall time times the speed: the frame
    /// shown is the one of that time, however many were skipped to keep it (never blocking).
    void advance(double seconds);
    /// The frame the clock is at, and the last frame with new animation (0 for a still scene;
    /// procedural motions never end: then the clock runs on).
    int frame() const;
    int last_frame() const { return last_frame_; }
    double fps() const { return options_.pose.fps; }

    // ---- Settings ----
    /// Changes a setting as its flag would (`tracer`, `depth`, `reuse`, `spp`, `culling`,
    /// `update`, `cost-ratio`, `normals`, `backend`, `environment-lights`...): the next frame
    /// uses it, with the same trees. Throws std::invalid_argument naming the setting for an
    /// unknown one or a bad value, leaving the settings as they were.
    void set(const std::string& name, const std::string& value);
    /// The settings `set` takes, with their values now.
    std::vector<std::pair<std::string, std::string>> settings() const;

    // ---- Image size ----
    /// Renders the next frames at `width` x `height` (the window's new size), with the same
    /// trees, camera and settings. Throws std::invalid_argument for a size outside
    /// [1, kMaxSize], changing nothing.
    void resize(int width, int height);
    static constexpr int kMaxSize = 16384;

    // ---- Frames ----
    /// Renders the clock's frame from the camera, with `samples` samples per pixel (0: the
    /// settings', target_samples()); returns it (valid until the next call). A recorder set
    /// gets the frame. A render stopped part way (cancel_render) returns with
    /// stats.cancelled: its image is incomplete, kept out of the history and the recording,
    /// and complete() is false until the next render that finishes.
    const RenderedFrame& render(int samples = 0);
    /// Stops the render running now on another thread, if one is (Renderer::cancel).
    /// Thread-safe: the one call another thread may make while a worker renders.
    void cancel_render() { renderer_.cancel(); }
    /// Whether the last render finished (its image whole).
    bool complete() const { return complete_; }
    /// The settings' samples per pixel (`--spp`, `set spp`): what a still view refines to.
    int target_samples() const { return options_.sampling.spp; }
    /// Where every frame rendered is also written (a GIF or video), or null.
    void set_recorder(SequenceFile* recorder) { recorder_ = recorder; }
    const RenderedFrame& image() const { return frame_; }
    /// The figures of the last frames rendered, oldest first (at most kHistory).
    const std::deque<FrameStats>& history() const { return history_; }
    static constexpr std::size_t kHistory = 240;
    const DisplayTransform& display() const { return display_; }
    /// What the window shows of the last frame as 8-bit RGB, rows from the top: the image in
    /// sRGB through the display transform (what `dynrt render` writes to a PNG), or in a cost
    /// view its heat map (cost_heat_rgb8).
    std::vector<unsigned char> display_bytes() const;
    /// In a cost view, what its colours mean ("node visits per pixel: white 50 or more; mean
    /// 12.3, max 87"); "" showing the image.
    std::string legend() const;
    /// Writes what the window shows of the last frame to `path` (the image as `dynrt render
    /// --out` writes it to a PNG, or the cost view's heat map) and beside it `path` with .json:
    /// the frame's report, the camera as --camera text, the frame and the view. When the last
    /// render was stopped part way, the frame is rendered again first.
    void screenshot(const std::filesystem::path& path);

    const Scene& scene() const { return scene_; }
    const RenderOptions& options() const { return options_; }
    const Renderer& renderer() const { return renderer_; }

private:
    /// The heat map's measure and white in a cost view (CostMeasure, cost_scale).
    CostMeasure cost_measure() const;
    std::uint32_t heat_scale() const;

    ViewArgs args_;
    RenderOptions options_;
    Scene scene_;
    Renderer renderer_;
    Camera first_camera_;
    OrbitCamera camera_;
    DisplayTransform display_;
    RenderedFrame frame_;
    std::deque<FrameStats> history_;
    double time_ = 0.0;  ///< animation seconds
    int last_frame_ = 0;
    bool endless_ = false;  ///< procedural motions: the clock never wraps or stops
    bool playing_ = false;
    bool loop_ = true;
    double speed_ = 1.0;
    int rendered_frame_ = 0;
    Camera rendered_camera_;  ///< the camera of the last frame rendered
    SequenceFile* recorder_ = nullptr;
    bool complete_ = false;
    int last_samples_ = 0;
};

}  // namespace dynrt::viewer
