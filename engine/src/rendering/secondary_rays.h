#pragma once
// Whitted's reflection and refraction rays for one 16x16 tile (Whitted 1980, "An Improved
// Illumination Model for Shaded Display"; the model, with its Fresnel term, offsets and
// cut-offs, is at the top of dynrt/engine/renderer.h).
//
// The tile's rays stay in their pixel's lane from bounce to bounce, so a bounce's reflection
// rays are one 256-lane packet and its refraction rays another, each lane carrying its path's
// weight; a depth-first stack of such packets holds the bounces still to trace. Before a
// packet is traced its rays are grouped by direction octant: a group of at least
// SecondaryRays::min_packet_rays rays (a planar mirror's or a glass pane's, which stay as
// coherent as the camera rays) is traced as a packet, and the rest (what a curved surface
// scatters) one ray at a time (CpuTracer::as_packet). Both tracers give the same bits, so the
// choice changes only the time; the report counts the rays each way (Overbeck, Ramamoorthi and Mark 2008, "Large Ray
// Packets for Real-time Whitted Ray Tracing", measure how packets of secondary rays thin out).

#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/secondary_ray_log.h"
#include "dynrt/packet/packet_config.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/scene/scene.h"
#include "rendering/tile_shading.h"
#include "rendering/trace_backend.h"
#include "update/scene_accel.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
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
};

/// One thread's secondary work over a frame's tiles.
struct SecondaryWork {
    std::size_t reflection_rays = 0;
    std::size_t refraction_rays = 0;
    std::size_t shadow_rays = 0;      ///< shadow rays cast at secondary hits
    std::size_t packet_rays = 0;      ///< reflection and refraction rays traced in packets
    std::size_t single_rays = 0;      ///< ... and one at a time
    /// rays_per_depth[k]: reflection and refraction rays of depth k + 1.
    std::vector<std::size_t> rays_per_depth;
    /// packet_rays_per_depth[k]: those of them traced in packets.
    std::vector<std::size_t> packet_rays_per_depth;
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

/// Adds to `colors` the secondary rays' share of every hit lane of `primary` (the tile's
/// camera-ray hits, as TileShadowOrigins computed them from the unit camera rays):
/// wr color(reflected) + wt color(refracted), recursively to settings.max_depth.
void add_secondary(const SecondaryFrame& frame, const TileShadowOrigins& primary,
                   packet::ShadedColors& colors, SecondaryWork& work);

/// Fills the report's secondary-ray fields from the threads' summed work; `scale` turns the
/// threads' summed milliseconds into the frame's wall time (the parallel loop's wall time over
/// its workers' total).
void report_secondary(const SecondaryWork& work, double scale, TraceStats& stats);

}  // namespace dynrt::detail
