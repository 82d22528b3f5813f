#pragma once
// Whitted's reflection and refraction rays (Whitted 1980, "An Improved Illumination Model for
// Shaded Display"; the model, with its Fresnel term, offsets and cut-offs, is at the top of
// dynrt/engine/renderer.h), traced as a stage of the frame over ray streams.
//
// The tiles of a frame are shaded first; each gathers the first bounce's rays of its hits
// (SecondaryStage::gather). Then the stage traces the whole frame's rays depth by depth, as
// pbrt-v4's wavefront integrator does: a depth's rays are sorted by kind (reflection,
// refraction), direction octant and the Morton order of their origins, so that a planar
// mirror's or a glass pane's rays from all over the image fill whole coherent packets of 256,
// which go through the trace seam (trace_backend.h) as scattered rays for their closest hits.
// Then, sorted again by hit point when the scene has two lights or more (so that a packet's
// shadow rays toward a light span a narrow cone), each hit is lit by its own shadow rays,
// shaded, and spawns the next depth's rays, each packet writing them into its own run.
// Gathered per tile, the same rays made packets of a few dozen, and most shadow rays at
// secondary hits went one by one (Overbeck, Ramamoorthi and Mark 2008, "Large Ray Packets
// for Real-time Whitted Ray Tracing", measure how packets of secondary rays thin out).
//
// Each pixel's colour then gets its rays' shares, weight times what each ray sees, added depth
// first, at every hit the refraction's path before the reflection's: the order of the per-tile
// recursion this stage replaced, so images are bit-identical to its (frame_suite.py checks).
// That recursion had one exception, which none of the suite's scenes meets: in a tile whose
// first lane to spawn anything spawned a refraction alone, it added the reflections first for
// every pixel of the tile. A pixel's colour no longer depends on its tile's other pixels.

#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/secondary_ray_log.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/scene/scene.h"
#include "rendering/pixel_samples.h"
#include "rendering/tile_shading.h"
#include "dynrt/engine/trace_backend.h"
#include "update/scene_accel.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace dynrt::detail {

/// How secondary rays are traced: the scene's shading geometry, the tracer behind the seam
/// (which decides packets or single rays), the depth and cut-off.
struct SecondaryTracing {
    const SceneAccel& accel;
    const TraceBackend& tracer;
    SecondaryRays settings;
    bool count = false;  ///< count traversal work into SecondaryWork::trace
};

/// What a frame's secondary rays read; fixed for the frame.
struct SecondaryFrame {
    SecondaryTracing tracing;
    std::span<const PointLight> lights;
    const TileShading& shading;
    std::span<const Material> materials;  ///< the scene's, same indices as shading.materials
    const std::vector<std::int32_t>& object_material;
    SecondaryRayLog* log = nullptr;  ///< TraceSettings::secondary_log
    /// The pixel samples the frame's rays belong to (which point of an area light they see).
    SamplePass sample = {};
};

/// One thread's secondary work over a frame.
struct SecondaryWork {
    std::size_t reflection_rays = 0;
    std::size_t refraction_rays = 0;
    /// Shadow rays at secondary hits: cast, and not cast by reason.
    ShadowCounts shadows;
    std::size_t packet_rays = 0;      ///< reflection and refraction rays traced in packets
    std::size_t single_rays = 0;      ///< ... and one at a time
    /// rays_per_depth[k]: reflection and refraction rays of depth k + 1.
    std::vector<std::size_t> rays_per_depth;
    /// packet_rays_per_depth[k]: those of them traced in packets.
    std::vector<std::size_t> packet_rays_per_depth;
    /// ms_per_depth[k]: thread time tracing them (closest hits only).
    std::vector<double> ms_per_depth;
    /// Thread time tracing reflection rays, refraction rays (closest hits only), the
    /// secondary hits' shadow rays, and everything else (making rays, shading, bookkeeping).
    double reflection_ms = 0, refraction_ms = 0, shadow_ms = 0, other_ms = 0;
    TraceWork trace;

    /// All of the thread's secondary time.
    double thread_ms() const { return reflection_ms + refraction_ms + shadow_ms + other_ms; }

    SecondaryWork& operator+=(const SecondaryWork& other);
};

/// Whether any hit on the scene can spawn a secondary ray under `settings`.
bool any_secondary(std::span<const Material> materials, const SecondaryRays& settings);

/// What the secondary stage keeps from frame to frame (TraceScratch::secondary): its buffers of
/// rays, a few hundred thousand per depth, so that each frame reuses memory already mapped
/// (mapping it afresh cost a fifth of the stage's time on BART kitchen).
class SecondaryBuffers {
public:
    SecondaryBuffers();
    ~SecondaryBuffers();
    SecondaryBuffers(SecondaryBuffers&&) noexcept;
    SecondaryBuffers& operator=(SecondaryBuffers&&) noexcept;

private:
    friend class SecondaryStage;
    struct Data;
    std::unique_ptr<Data> data_;
};

/// One frame's secondary rays: gathered from its tiles, then traced as a stage of their own.
class SecondaryStage {
public:
    /// `frame` and `buffers` are borrowed for the stage's life (one stage at a time per
    /// SecondaryBuffers).
    SecondaryStage(const SecondaryFrame& frame, SecondaryBuffers& buffers);
    SecondaryStage(const SecondaryStage&) = delete;
    SecondaryStage& operator=(const SecondaryStage&) = delete;

    /// From the tile tasks (thread-safe, each tile once): the first reflection and refraction
    /// rays of `origins`' hit lanes, the camera-ray hits of tile number `tile_index` of the
    /// frame's tiling, `tile`, in an image `width` pixels wide.
    void gather(int tile_index, const packet::Tile& tile, int width, const TileShadowOrigins& origins);

    /// After every tile was shaded into out.color: traces the gathered rays and all they
    /// spawn, to settings.max_depth, and adds each pixel's share to its colour. Sets stats'
    /// secondary fields (secondary_ms: this stage's wall time).
    void trace(RenderedFrame& out, TraceStats& stats);

private:
    /// Traces waves[depth] in two passes, each over packets of its rays sorted anew: closest
    /// hits, then the hits' shadow rays, shading, each ray's share and what each hit spawns.
    void trace_wave(int depth);
    void sort_into_packets(int group_bits);
    void trace_closest(int depth, std::size_t begin, std::size_t end);
    void shade_packet(int depth, std::size_t packet_index);

    const SecondaryFrame& frame_;
    SecondaryBuffers::Data& state_;
};

}  // namespace dynrt::detail
