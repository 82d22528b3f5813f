#pragma once
// One frame's report. Field names are the JSON keys of the report schema (README.md, "Report"):
// later work adds fields but never renames one.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dynrt {

/// Why a bottom-level tree was built (the update planner's reasons, engine/update_plan.h).
enum class RebuildReason : std::uint8_t {
    first_build,             ///< the object's first tree
    class_changed,           ///< its tree moved between object and world space, or left the static group
    static_group_changed,    ///< a static object's group was rebuilt: an object joined or left it
    exploding,               ///< rebuilt every frame it moves
    sah_degraded,            ///< the refit's SAH cost passed the rebuild threshold
    degenerate_gained_area,  ///< a refit could not keep the tree correct
    /// The refits' predicted extra trace time reached a rebuild's cost (update_cost.h)
    refits_cost_more,
    /// The update method rebuilds every frame (`--update fast` or `sah`)
    update_method,
};

/// The reason as the report writes it: "first build", "class changed", "static group
/// changed", "exploding", "sah degraded", "degenerate triangle gained area", "refits cost
/// more", "update method".
inline const char* rebuild_reason_name(RebuildReason reason) {
    switch (reason) {
        case RebuildReason::first_build: return "first build";
        case RebuildReason::class_changed: return "class changed";
        case RebuildReason::static_group_changed: return "static group changed";
        case RebuildReason::exploding: return "exploding";
        case RebuildReason::sah_degraded: return "sah degraded";
        case RebuildReason::degenerate_gained_area: return "degenerate triangle gained area";
        case RebuildReason::refits_cost_more: return "refits cost more";
        case RebuildReason::update_method: return "update method";
    }
    return "unknown";
}

/// The reason rebuild_reason_name gives `name`; false when none does.
bool parse_rebuild_reason(const std::string& name, RebuildReason& reason);

/// One bottom-level tree built this frame, and why. Class changes come from the library API,
/// whose meshes can be raised to another class.
struct TreeRebuild {
    std::size_t object = 0;  ///< index in scene order
    std::string name;        ///< the object's name
    RebuildReason reason = RebuildReason::first_build;
    /// For sah_degraded and refits_cost_more: the refitted tree's SAH cost and the cost at the
    /// previous build.
    double sah_refitted = 0;
    double sah_at_last_build = 0;
    /// The builder: "sah" (binned SAH) or "morton" (the fast builder).
    std::string builder = "sah";
};

/// What the update chose for one changed deformable or exploding object under the automatic
/// method (update_cost.h), and why, e.g. "refit" with "refits' extra trace 3.1 ms so far (0.4
/// this frame) < rebuild (fast) 35.2 ms".
struct TreeChoice {
    std::size_t object = 0;
    std::string name;
    std::string chosen;  ///< "refit", "rebuild (fast)" or "rebuild (sah)"
    std::string why;
};

/// The update stage's figures: posing and gathering, the trees' builds and refits, what each
/// object got (update_plan.h) and why.
struct UpdateStats {
    /// The frame's update except its tree builds: evaluating the scene at the frame (posing),
    /// gathering and checking the triangles, classifying the objects. With build_ms, primary_ms,
    /// shadow_ms and shade_ms it makes up total_ms (the rest is per-frame bookkeeping).
    double update_ms = 0;
    /// BVH construction: build_ms = refit_ms + rebuild_ms + top_level_ms.
    double build_ms = 0;
    double refit_ms = 0;      ///< refitting deformable objects' trees
    double rebuild_ms = 0;    ///< building bottom-level trees (first builds included)
    double top_level_ms = 0;  ///< rebuilding the top level over the objects
    /// Objects and their triangles per motion class.
    std::size_t static_objects = 0;
    std::size_t static_triangles = 0;
    std::size_t rigid_objects = 0;
    std::size_t rigid_triangles = 0;
    std::size_t deformable_objects = 0;
    std::size_t deformable_triangles = 0;
    std::size_t exploding_objects = 0;
    std::size_t exploding_triangles = 0;
    /// Objects whose bottom-level tree was not touched: static ones after their first build,
    /// rigid ones (only their instance moved) and unchanged ones.
    std::size_t objects_skipped = 0;
    std::size_t objects_refitted = 0;
    std::size_t objects_rebuilt = 0;
    std::size_t triangles_refitted = 0;
    std::size_t triangles_rebuilt = 0;
    /// Every bottom-level build of this frame, and why (JSON report only).
    std::vector<TreeRebuild> rebuilds;
    /// The automatic method's choices this frame, with the predictions behind them.
    std::vector<TreeChoice> choices;
    /// When the static group was built this frame under a memory budget
    /// (UpdatePolicy::memory_budget): the layout chosen, e.g. "compact leaves, float nodes",
    /// why, and the peak resident bytes predicted for its build; empty and 0 otherwise.
    std::string static_layout;
    std::string static_layout_why;
    std::size_t static_layout_predicted_peak = 0;
};

/// The shape of the trees after the update (SAH cost and size of the two levels as one tree).
struct TreeShape {
    std::size_t triangles = 0;           ///< triangles in the scene at this frame
    std::size_t degenerate_skipped = 0;  ///< zero-area triangles kept out of the BVH
    double sah_cost = 0;                 ///< SAH cost of the tree (bvh::sah_cost)
    std::size_t nodes = 0;
    std::size_t leaves = 0;
    double leaf_tris_mean = 0;
    std::uint32_t leaf_tris_max = 0;
    std::uint32_t depth = 0;
    /// Memory of the objects' trees: the binary trees (nodes, primitive ids and triangles in
    /// leaf order) and the wide trees (nodes and triangle blocks; 0 with BuildConfig::wide off).
    std::size_t binary_tree_bytes = 0;
    std::size_t wide_tree_bytes = 0;
};

/// The trace stage's figures: primary and shadow rays, shading, and the tracer's work.
struct TraceStats {
    double primary_ms = 0;               ///< tracing camera rays
    double shadow_ms = 0;                ///< tracing shadow rays
    double shade_ms = 0;                 ///< Phong shading and image assembly
    std::size_t primary_rays = 0;
    std::size_t shadow_rays = 0;
    /// Pixels filled by interpolation instead of traced (TraceSettings::adaptive_tolerance).
    std::size_t interpolated_pixels = 0;
    double primary_mrays_per_s = 0;
    double shadow_mrays_per_s = 0;
    /// Packet tracer work over primary and shadow rays, counted only when
    /// TraceSettings::count_packet_work is set (0 otherwise): ray/triangle tests performed, and
    /// tests the culling stages avoided (packet::PacketStats has the breakdown).
    std::uint64_t ray_triangle_tests = 0;
    std::uint64_t ray_triangle_culled = 0;
    /// Node visits of the same counted trace: packet node visits for the packet tracer; for the
    /// single-ray tracer, every ray's visits (wide inner nodes and leaves, or binary nodes,
    /// plus top-level nodes), whose triangle tests are then in ray_triangle_tests.
    std::uint64_t nodes_visited = 0;
    /// Whitted reflection and refraction rays (TraceSettings::secondary): the stage's wall
    /// time (a stage of its own after the tiles: sorting the rays, tracing them, their hits'
    /// shadow rays and shading, adding their shares to the pixels), the rays of each kind and
    /// their rates (closest-hit tracing only, the stage's wall time split by the workers' time
    /// spent on them), the shadow rays cast at their hits, how many were traced in packets and one
    /// at a time, and the rays per depth (index 0: depth 1, the camera rays' bounces).
    double secondary_ms = 0;
    std::size_t reflection_rays = 0;
    std::size_t refraction_rays = 0;
    double reflection_mrays_per_s = 0;
    double refraction_mrays_per_s = 0;
    std::size_t secondary_shadow_rays = 0;
    /// Their rate: the stage's wall time split by the workers' time spent tracing them.
    double secondary_shadow_mrays_per_s = 0;
    std::size_t secondary_packet_rays = 0;
    std::size_t secondary_single_rays = 0;
    std::vector<std::size_t> secondary_rays_per_depth;
    /// Of those, the rays traced in packets, per depth.
    std::vector<std::size_t> secondary_packet_rays_per_depth;
    /// Their closest-hit rate per depth (as reflection_mrays_per_s).
    std::vector<double> secondary_mrays_per_s_per_depth;
    /// Shadow rays (at camera and secondary hits) left out because their contribution is
    /// exactly zero: the hit faces away from the light (its geometric normal, or else its
    /// shading normal), or the light is dark there (intensity 0, outside a spot's cone, past
    /// its range: shadow_rays_dark_light). Not counted in shadow_rays or
    /// secondary_shadow_rays. Exact reuse counts those of the tiles it traces afresh.
    std::size_t shadow_rays_back_side = 0;
    std::size_t shadow_rays_shading_side = 0;
    std::size_t shadow_rays_dark_light = 0;
    /// Shadow rays traced with the occluder cache (TraceSettings::occluder_cache), and those
    /// answered by its triangles before any traversal.
    std::size_t shadow_rays_cache_tested = 0;
    std::size_t shadow_rays_cache_answered = 0;
    /// Pixel reuse (TraceSettings::reuse, pixel_reuse.h): the mode that ran ("off", "exact",
    /// "cache", "frameless"), and why the frame was traced in full or what it re-traced (e.g.
    /// "first frame", "camera moved", "2 objects changed").
    std::string reuse_mode = "off";
    std::string reuse_reason;
    /// Pixels whose primary ray was traced this frame; pixels that kept the previous frame's
    /// hit but whose shadow rays were traced again (exact); pixels kept from the previous
    /// frame as they were (exact, frameless) or reprojected into the new view (render cache);
    /// pixels filled from their neighbours (render cache and frameless).
    std::size_t pixels_traced = 0;
    std::size_t pixels_shadows_retraced = 0;
    std::size_t pixels_reused = 0;
    std::size_t pixels_filled = 0;
    /// Samples per pixel (TraceSettings::sampling.spp; primary_rays counts the camera rays of
    /// every sample), and with adaptive anti-aliasing the pixels that took all of them (the
    /// others took one); with every pixel sampled alike, all the traced pixels.
    int samples_per_pixel = 1;
    std::size_t pixels_refined = 0;
};

/// Where a frame of a render across processes (`mpirun dynrt render`) was made, and what the
/// distribution cost it; rank -1 (and nothing in the report) for a render in one process.
struct DistributionStats {
    /// The process that rendered the frame (`--distribute frames`), or that gathered it (0,
    /// `--distribute tiles`).
    int rank = -1;
    /// `--distribute tiles`: each process's trace time of its share of the tiles, by rank.
    std::vector<double> rank_trace_ms;
    /// `--distribute frames`: the wall time its process spent asking for the run of frames
    /// this one belongs to, shared over the run's frames.
    double handout_ms = 0;
    /// `--distribute tiles`: the wall time rank 0 waited, its own share done, for the slowest
    /// rank's (load imbalance), then spent receiving and unpacking the shares (the gather).
    double wait_ms = 0;
    double gather_ms = 0;
};

/// One holder of memory after the frame: an object with a tree of its own, or all static
/// objects together (they share one tree; object -1, name "static objects (N)").
struct ObjectMemory {
    std::int64_t object = -1;  ///< index in scene order; -1: the static objects' shared tree
    std::string name;
    std::size_t triangles = 0;
    std::size_t scene_bytes = 0;           ///< its meshes' arrays in the scene model
    std::size_t tree_bytes = 0;            ///< its tree's nodes and leaves
    std::size_t build_triangle_bytes = 0;  ///< the triangles its tree is built from (see MemoryStats)

    std::size_t bytes() const { return scene_bytes + tree_bytes + build_triangle_bytes; }
};

/// Memory after the frame (issue 43): what the scene model, the trees and the renderer hold,
/// and the process's resident set, in bytes (the report's "memory" object; `dynrt render`
/// prints them per triangle). Filled by Renderer (`dynrt render`, `dynrt bench`, the viewer);
/// 0 from the library API, whose Engine::memory_bytes() gives what it holds.
struct MemoryStats {
    /// The scene model the frame was rendered from: its meshes (positions, triangles, normals,
    /// texture coordinates, skin weights, morph targets), embedded image files and texel
    /// arrays, animation clips.
    std::size_t scene_bytes = 0;
    /// The trees: every object's nodes and leaves (the wide tree's nodes and triangle blocks,
    /// or a binary tree's nodes, ids and triangles in leaf order) and the top level.
    std::size_t tree_bytes = 0;
    /// The triangles each tree is built and refitted from (per object, in world space, or in
    /// object space for rigid ones: 36 bytes each). The static objects' tree is never refitted
    /// and keeps only an index into its own leaf blocks instead (4 bytes a triangle,
    /// bvh/block_triangles.h).
    std::size_t build_triangle_bytes = 0;
    /// Everything the renderer holds besides the scene model: tree_bytes, build_triangle_bytes,
    /// the shading geometry, the posed scene, decoded textures, pixel reuse's records.
    std::size_t renderer_bytes = 0;
    /// The process's resident set after the frame and its peak so far (Linux's VmRSS and
    /// VmHWM; 0 where they cannot be read). For a one-frame render of a static scene the peak
    /// is the build's.
    std::size_t rss_bytes = 0;
    std::size_t peak_rss_bytes = 0;
    /// The largest holders (ObjectMemory::bytes), largest first, at most kLargestHolders.
    std::vector<ObjectMemory> largest;
    static constexpr std::size_t kLargestHolders = 8;
};

/// One frame's figures: the three stages' parts, each filled by its stage (SceneAccel the
/// update and the tree shape, trace_frame the trace), and the whole frame's wall time. The
/// parts are bases, so every figure is read as stats.<field>, as the report's keys name it.
struct FrameStats : UpdateStats, TreeShape, TraceStats, DistributionStats, MemoryStats {
    int frame = 0;
    double total_ms = 0;  ///< the whole frame, wall clock
    /// `dynrt render`: the output stage's time encoding and writing this frame's files (on its
    /// writer thread, beside the next frame's render; FrameWriter), not part of total_ms.
    double write_ms = 0;
    /// The tracer that answered the frame's rays: "dynrt", or a backend behind the trace seam
    /// (Renderer::use_backend, e.g. "embree-low"), and what loading the frame into that
    /// backend took (its update stage; 0 for dynrt, whose update is update_ms and build_ms,
    /// which still run under another backend for the shading geometry). Part of total_ms.
    std::string backend = "dynrt";
    double backend_load_ms = 0;
    /// The trace was stopped part way (Renderer::cancel, Engine::cancel_render): the frame's
    /// image is incomplete and is not to be shown or written (the library API leaves the
    /// caller's image as it was), and the figures are the update's alone; the next frame
    /// traces in full.
    bool cancelled = false;
};

}  // namespace dynrt
