#pragma once
// A tile's rays through the trace seam (trace_backend.h), as every mode of the frame traces
// them: its camera rays' closest hits into the frame's per-pixel hits, and its hit points'
// shadow rays toward each light.

#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "rendering/tile_shading.h"
#include "dynrt/engine/trace_backend.h"

#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace dynrt::detail {

/// Closest hits of `rays`' active lanes (camera rays of `tile`'s pixels), resolved, into
/// hits[y * width + x]; other pixels' hits are left alone.
inline void trace_tile_hits(const TraceBackend& tracer, const packet::Tile& tile, int width,
                            const packet::RayPacket& rays, std::vector<bvh::InstanceHit>& hits,
                            TraceWork* work) {
    tracer.closest(rays, RayCoherence::tile,
                   HitTarget(hits.data() + std::size_t(tile.y0) * std::size_t(width) + std::size_t(tile.x0),
                             std::size_t(width)),
                   work);
}

/// Shadow rays through glass (Whitted 1980's rule, as most classic ray tracers): a shadow ray
/// blocked only by transmissive surfaces reaches its light, filtered by the product of their
/// transmittances; refraction of the shadow ray is ignored (it goes straight on). For the
/// lanes `blocked` of `shadow` (rays toward light l that met something), their closest hits
/// are found layer by layer, each layer starting just past the last hit (the next float t,
/// so two triangles at exactly the same t count once), up to kGlassLayersMax: a lane reaches
/// the light when it leaves the last layer without meeting an opaque surface. Returns those
/// lanes; their filters go into origins.filter_of(l). `glass` is TileShading::glass.
/// The first layer's closest hits also answer what an any-hit test would (an opaque first
/// hit blocks the ray), so in a scene with glass the shadow rays are traced this way alone
/// (shadow_reach): an any-hit test first would trace every blocked ray twice.
constexpr int kGlassLayersMax = 16;

inline packet::LaneMask through_glass(const TraceBackend& tracer, RayCoherence coherence,
                                      std::span<const glm::vec3> glass, const packet::RayPacket& shadow,
                                      const packet::LaneMask& blocked, TileShadowOrigins& origins, std::size_t l,
                                      std::size_t light_count, TraceWork* work) {
    thread_local packet::RayPacket rays;
    thread_local LaneHits hits;
    rays = shadow;
    rays.active = blocked;
    packet::LaneMask through;
    float (*filter)[packet::kPacketRays] = nullptr;
    for (int layer = 0; layer < kGlassLayersMax && rays.active.any(); ++layer) {
        tracer.closest(rays, coherence, HitTarget(hits), work);
        packet::LaneMask next;
        rays.active.for_each([&](int lane) {
            const bvh::InstanceHit& hit = HitTarget(hits)[lane];
            if (!hit.is_hit()) {
                through.set(lane);
                return;
            }
            const glm::vec3& kt = glass[hit.object];
            if (kt == glm::vec3(0.0f)) return;  // opaque: the light is blocked
            if (filter == nullptr) filter = origins.filter_of(l, light_count).rgb;
            for (int a = 0; a < 3; ++a) filter[a][lane] *= kt[a];
            rays.tmin[lane] = std::nextafter(hit.hit.t, std::numeric_limits<float>::infinity());
            next.set(lane);
        });
        rays.active = next;
    }
    return through;
}

/// The active lanes of `shadow` (rays toward light l) that reach it: those nothing blocks, and
/// in a scene with glass (`glass` not empty) those only glass blocks, filtered (through_glass).
inline packet::LaneMask shadow_reach(const TraceBackend& tracer, RayCoherence coherence,
                                     std::span<const glm::vec3> glass, const packet::RayPacket& shadow,
                                     TileShadowOrigins& origins, std::size_t l, std::size_t light_count,
                                     TraceWork* work) {
    if (glass.empty()) return shadow.active & ~tracer.occluded(shadow, coherence, work);
    return through_glass(tracer, coherence, glass, shadow, shadow.active, origins, l, light_count, work);
}

/// visible[l]: the hit lanes of `origins` that light l of `lights` (TileShading::lights)
/// reaches (the lit side of their surface
/// and nothing opaque in between), one shadow batch per light of `coherence` (`shadow` holds
/// the last); lanes reached through glass get their filter in `origins` (through_glass).
/// Returns the shadow rays traced and those not cast (TileShadowOrigins::rays_to).
inline ShadowCounts trace_tile_shadows(const TraceBackend& tracer, RayCoherence coherence,
                                       TileShadowOrigins& origins, std::span<const packet::ShadingLight> lights,
                                       std::span<const glm::vec3> glass, packet::RayPacket& shadow,
                                       std::vector<packet::LaneMask>& visible, TraceWork* work) {
    visible.assign(lights.size(), packet::LaneMask{});
    ShadowCounts counts;
    const auto hits = std::size_t(origins.surface.hit.count());
    for (std::size_t l = 0; l < lights.size() && hits > 0; ++l) {
        const TileShadowOrigins::LeftOut left = origins.rays_to(lights[l], l, shadow);
        const auto cast = std::size_t(shadow.active.count());
        counts.add(lights[l], hits, cast, left);
        if (cast == 0) continue;
        visible[l] = shadow_reach(tracer, coherence, glass, shadow, origins, l, lights.size(), work);
    }
    return counts;
}

}  // namespace dynrt::detail
