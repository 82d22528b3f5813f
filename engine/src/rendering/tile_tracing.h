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

#include <cstddef>
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

/// visible[l]: the hit lanes of `origins` that light l reaches (the lit side of their surface
/// and nothing in between), one shadow batch per light of `coherence` (`shadow` holds the
/// last). Returns the shadow rays traced and those not cast (TileShadowOrigins::rays_to).
inline ShadowCounts trace_tile_shadows(const TraceBackend& tracer, RayCoherence coherence,
                                       const TileShadowOrigins& origins,
                                       std::span<const PointLight> lights, packet::RayPacket& shadow,
                                       std::vector<packet::LaneMask>& visible, TraceWork* work) {
    visible.assign(lights.size(), packet::LaneMask{});
    ShadowCounts counts;
    const auto hits = std::size_t(origins.surface.hit.count());
    for (std::size_t l = 0; l < lights.size() && hits > 0; ++l) {
        const auto shading_away = std::size_t(origins.rays_to(lights[l], l, shadow));
        const auto cast = std::size_t(shadow.active.count());
        counts.add(lights[l], hits, cast, shading_away);
        if (cast == 0) continue;
        visible[l] = shadow.active & ~tracer.occluded(shadow, coherence, work);
    }
    return counts;
}

}  // namespace dynrt::detail
