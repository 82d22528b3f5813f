#pragma once
// `dynrt bench`: renders a scene repeatedly under each build configuration of a sweep and
// summarises every stage's time as median, min and max over the repeats.

#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/spread.h"
#include "dynrt/engine/texture_figures.h"
#include "dynrt/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace dynrt {

/// One configuration's figures over `repeat` renders of the same frame.
struct BenchRow {
    bvh::BuildConfig build;
    std::size_t triangles = 0;
    /// The frame's update except its builds (FrameStats::update_ms: posing, gathering).
    Spread update_ms;
    Spread build_ms;
    Spread trace_ms;  ///< primary + shadow rays
    Spread primary_ms;  ///< primary rays alone
    Spread shadow_ms;   ///< shadow rays alone
    Spread shade_ms;
    /// Reflection and refraction rays with their shadows and shading (FrameStats::secondary_ms;
    /// 0 without them).
    Spread secondary_ms;
    Spread total_ms;
    Spread mrays_per_s;  ///< primary + shadow rays per trace time
    /// The configuration's first frame, untimed by the runs: its textures read and first
    /// touched, its trees built from nothing. A start-up cost, which a render pays once.
    double first_ms = 0.0;
    /// The textures that first frame read (Renderer::texture_figures), once per configuration;
    /// not a CSV or JSON column.
    TextureFigures textures{};
    double sah_cost = 0;
    double leaf_tris_mean = 0;
    std::uint32_t depth = 0;
    /// The packet tracer's culling stages, as a culling sweep item ("ab+bp+nf", "none", "all";
    /// "" for the single-ray tracer).
    std::string packet_culling;
    /// RenderOptions::adaptive_tolerance of the configuration (0: exact).
    float adaptive_tolerance = 0.0f;
    /// RenderOptions::lod_pixels of the configuration (0: exact).
    float lod_pixels = 0.0f;
    /// Primary and shadow ray/triangle pairs the packet tracer tested, and pairs its culling
    /// stages removed (FrameStats), from one extra untimed render with counting on, so the
    /// timed runs are not perturbed. 0 for the single-ray tracer.
    std::uint64_t ray_triangle_tests = 0;
    std::uint64_t ray_triangle_culled = 0;
    /// Node visits of the same counted render (FrameStats::nodes_visited), and the rays it
    /// traced (primary + shadow), for per-ray figures.
    std::uint64_t nodes_visited = 0;
    std::uint64_t rays = 0;
    /// The tree traced: 8 (wide) or 2 (binary), and the bytes per triangle of all
    /// the trees kept (binary tree, plus the wide tree when built).
    int tree_width = 2;
    double bytes_per_triangle = 0;
    /// Memory per triangle (FrameStats' MemoryStats after the last run): the scene model,
    /// everything the renderer holds, and the process's resident peak over the row's renders
    /// (the first, which builds every tree, included; each row's peak starts afresh where
    /// Linux allows, restart_peak_resident).
    double scene_bytes_per_triangle = 0;
    double renderer_bytes_per_triangle = 0;
    double peak_bytes_per_triangle = 0;
};

/// Expands sweep specs such as "cost-ratio=0.1,1" and "leaf=4,8" into the cross product of
/// their values applied to `base`, in order (the first sweep varies slowest). No sweep gives
/// {base}. Throws std::invalid_argument naming a malformed spec, an unknown parameter, a value
/// out of range or a parameter swept twice.
std::vector<bvh::BuildConfig> expand_sweeps(const std::vector<std::string>& sweeps,
                                            const bvh::BuildConfig& base);

/// Takes the culling sweep, if any, out of `sweeps` (leaving the build sweeps for
/// expand_sweeps) and returns its items in order: "culling=none,ab,ab+bp,ab+bp+nf", where
/// commas separate configurations and '+' joins the stages of one. Each item is checked with
/// packet::PacketCulling::parse (its '+' read as ','). No culling sweep gives {}. Throws
/// std::invalid_argument for an empty list or item, an unknown stage, or culling swept twice.
std::vector<std::string> take_culling_sweep(std::vector<std::string>& sweeps);

/// A culling sweep item as packet::PacketCulling reads it ('+' -> ',').
packet::PacketCulling parse_culling_item(const std::string& item);

/// Takes the adaptive sweep, if any, out of `sweeps`: "adaptive=0,0.01,0.05" gives the
/// RenderOptions::adaptive_tolerance values in order. No adaptive sweep gives {}. Throws
/// std::invalid_argument for an empty list, a value that is not a finite number >= 0, or
/// adaptive swept twice.
std::vector<float> take_adaptive_sweep(std::vector<std::string>& sweeps);

/// Takes the samples-per-pixel sweep, if any, out of `sweeps`: "spp=1,4,16" gives
/// PixelSampling::spp values in order; none gives {}. Throws std::invalid_argument for an empty
/// list, a value that is not a whole number from 1 to 4096, or spp swept twice.
std::vector<int> take_spp_sweep(std::vector<std::string>& sweeps);

/// Takes the adaptive anti-aliasing sweep, if any: "aa=0,0.05" gives
/// PixelSampling::adaptive_contrast values in order (0: every pixel takes every sample); none
/// gives {}. Throws as take_adaptive_sweep.
std::vector<float> take_aa_sweep(std::vector<std::string>& sweeps);

/// Takes the level of detail sweep, if any: "lod=0,1,4" gives RenderOptions::lod_pixels values
/// in order (0: off); none gives {}. Throws as take_adaptive_sweep.
std::vector<float> take_lod_sweep(std::vector<std::string>& sweeps);

/// Takes the pixel reuse sweep, if any, out of `sweeps`: "reuse=off,exact,cache:0.25,
/// frameless:8ms" gives the TraceSettings::reuse values in order, each read by parse_reuse.
/// No reuse sweep gives {}. Throws std::invalid_argument for an empty list, an item
/// parse_reuse refuses, or reuse swept twice.
std::vector<ReuseSettings> take_reuse_sweep(std::vector<std::string>& sweeps);

/// How the trees of the measured frame come about.
enum class BenchUpdate {
    /// Renderer::reset() before the frame: every tree is built from scratch.
    rebuild,
    /// The frames before it are updated first (untimed), as a sequence would be: the frame's
    /// trees are what the renderer's update plan makes of them (deformable objects refitted).
    refit,
};

const char* to_string(BenchUpdate update);

/// Takes the update sweep, if any, out of `sweeps`: "update=rebuild,refit" in order. No update
/// sweep gives {}. Throws std::invalid_argument for an empty list, a name other than rebuild
/// and refit, or update swept twice.
std::vector<BenchUpdate> take_update_sweep(std::vector<std::string>& sweeps);

/// Renders frame `frame` (>= 0) of `scene` once untimed (its start-up: textures read, trees
/// built; BenchRow::first_ms), `warmup` more times untimed, then `repeat` times (>= 1)
/// timed, with `options` (whose build config, packet culling and adaptive tolerance are the
/// configuration measured), then, with the packet tracer, once more untimed with
/// count_packet_work on, for the row's ray/triangle counters. Each render starts from empty
/// trees (Renderer::forget_trees: the textures stay read, as in a render after its first
/// frame); with BenchUpdate::refit, frames 0 to frame - 1 are then updated (not traced, not
/// timed) before the frame is rendered, so only the frame's own update and trace are timed. If
/// `last_frame` is not null, it receives a frame of the same configuration with its hit
/// buffers filled (the last timed render, or one more untimed when `options.hit_buffers` is
/// off), for comparing hits with another tracer or the reference.
BenchRow bench_configuration(const Scene& scene, const Camera& camera,
                             const RenderOptions& options, int repeat, int warmup,
                             RenderedFrame* last_frame = nullptr, int frame = 0,
                             BenchUpdate update = BenchUpdate::rebuild);

/// The line above a bench's table: what the command paid once, outside the timed runs:
/// "start-up (not in the runs): scene loaded in L ms; first frame F ms (textures read, trees
/// built from nothing); textures: 3 images, 12.4 MB, read in 85.0 ms" (describe_textures,
/// report.h), without the textures part when `textures` counts none.
void print_start_up(std::ostream& out, double load_ms, double first_ms, const TextureFigures& textures);

/// The table for people: one row per configuration, "median (min-max)" per timed figure.
void print_bench_table(std::ostream& out, const std::vector<BenchRow>& rows);

/// The same rows as CSV (one header line, then a line per row; each Spread as three columns
/// `<key>_median,<key>_min,<key>_max`) and as JSON ({"rows": [...]}, Spreads as objects).
std::string bench_csv(const std::vector<BenchRow>& rows);
std::string bench_json(const std::vector<BenchRow>& rows);

}  // namespace dynrt
