#pragma once
// The per-frame report: a fixed-width table for people and a JSON document for tools. The JSON
// schema is documented in README.md ("Report") and only ever grows.

#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/texture_figures.h"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace dynrt {

/// What was rendered, recorded once per report.
struct RunInfo {
    std::string scene;
    int width = 0;
    int height = 0;
    float cost_ratio = 0;
    unsigned leaf_size_max = 0;
    int threads = 0;
    /// Scene::ignored: what the scene file says that dynrt left out.
    std::vector<std::string> ignored;
    /// `dynrt render`: from the start of the command to the first frame (the scene loaded and
    /// checked; the first frame's tree builds and texture decoding are in its own figures).
    double startup_ms = 0;
    /// `dynrt render`: the time the render thread waited for the output stage (FrameWriter)
    /// to take a frame or to finish.
    double writer_wait_ms = 0;
    /// The scene's textures as the render read them once, at its first frame (that frame's
    /// total_ms includes load_ms); zeros for a scene mapping no texture.
    TextureFigures textures{};
};

/// {"dynrt_report_version": 1, "run": {... "textures": {"count", "bytes", "load_ms"}},
///  "frames": [FrameStats...],
///  "summary": {"median": {...}, "min": {...}, "max": {...}}}, pretty-printed.
std::string report_json(const RunInfo& run, const std::vector<FrameStats>& frames);

/// One frame's record as report_json writes it under "frames", on one line: what the library
/// API's Python bindings hand back from update() and render().
std::string frame_report_json(const FrameStats& stats);

/// The figures of a record frame_report_json wrote (the inverse of it: writing them again
/// gives the same text). Throws std::invalid_argument when `record` is not such a record.
FrameStats parse_frame_report_json(const std::string& record);

/// Writes report_json to `path`, atomically (a temporary file beside it, then renamed over it:
/// a run killed while writing leaves the old report or the new one). Throws
/// std::runtime_error naming the file on failure.
void write_report(const std::filesystem::path& path, const RunInfo& run,
                  const std::vector<FrameStats>& frames);

/// The textures in words, for the lines people read: "3 images, 12.4 MB, read in 85.0 ms"
/// ("1 image", bytes in B, kB or MB of 1000 and 1000000 bytes, ms to a tenth).
std::string describe_textures(const TextureFigures& textures);

/// "textures: " and describe_textures on a line of its own (`dynrt render`, under the table).
/// Nothing when no texture was read (textures.count == 0): a scene without textures, or whose
/// textures all failed to read, which its warnings said.
void print_textures(std::ostream& out, const TextureFigures& textures);

/// "memory per triangle: scene 24 B, trees 66 B, build triangles 36 B, renderer in all 150 B;
/// resident peak 304 B (1.2 GB)": the last frame's MemoryStats over its triangles, and the
/// highest resident peak of `frames`. Nothing when no frame measured memory.
void print_memory(std::ostream& out, const std::vector<FrameStats>& frames);

/// The output stage's line under the table: its median and largest ms per frame (write_ms,
/// beside the render) and how long the render waited for it. Nothing without frames.
void print_writer_summary(std::ostream& out, const std::vector<FrameStats>& frames, double wait_ms);

/// Column header of the frame table, then one row per call of print_frame_row.
void print_frame_header(std::ostream& out);
void print_frame_row(std::ostream& out, const FrameStats& stats);
/// The first frame's row ("first": it builds every tree, so it is the cold one), then median,
/// min and max rows over the frames after it (the steady state). Nothing for a single frame.
/// (The report file's summary covers every frame.)
void print_summary(std::ostream& out, const std::vector<FrameStats>& frames);
/// The reflection and refraction rays, medians over the frames: rays and Mrays/s of each kind
/// beside the camera rays' rate, the share traced in packets, the shadow rays at their hits and
/// their Mrays/s, the stage's ms, and per depth the rays, their share in packets and their
/// Mrays/s. Nothing when no frame traced any.
void print_secondary_summary(std::ostream& out, const std::vector<FrameStats>& frames);

/// Prints the shadow rays' line (medians over `frames`): rays cast at camera and secondary
/// hits, rays not cast by reason, and the occluder cache's answers; nothing without shadow
/// rays.
void print_shadow_summary(std::ostream& out, const std::vector<FrameStats>& frames);

/// Prints the samples' line (medians over `frames`) of frames with several samples per pixel:
/// samples per pixel, the pixels that took them all (adaptive anti-aliasing refines some),
/// camera rays per pixel; nothing at one sample per pixel.
void print_sampling_summary(std::ostream& out, const std::vector<FrameStats>& frames);

}  // namespace dynrt
