// AlphaCutouts and CutoutTracer (alpha_cutouts.h).

#include "rendering/alpha_cutouts.h"

#include "dynrt/engine/alpha_mask.h"

#include <cmath>
#include <limits>

namespace dynrt::detail {

bool AlphaCutouts::cut(const bvh::InstanceHit& hit) const {
    const auto index = std::uint32_t(object_material_[hit.object]);
    const Material& material = materials_[index];
    if (!material.alpha_cutoff) return false;
    glm::vec2 st;
    const glm::vec2* at = nullptr;
    if (textures_ != nullptr) {
        const ObjectTexcoords& uv = textures_->objects[hit.object];
        if (!uv.texcoords.empty()) {
            // As the shading interpolates them (tint_lanes).
            const glm::uvec3& corner = uv.triangles[hit.hit.prim];
            const float u = hit.hit.u, v = hit.hit.v;
            st = (1.0f - u - v) * uv.texcoords[corner.x] + u * uv.texcoords[corner.y] + v * uv.texcoords[corner.z];
            at = &st;
        }
    }
    return cut_out(material, surface_alpha(material, index, textures_ != nullptr ? &textures_->set : nullptr, at));
}

int CutoutTracer::closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                          TraceWork* work) const {
    const int packed = inner_.closest(rays, coherence, hits, work);
    packet::LaneMask cut;
    rays.active.for_each([&](int lane) {
        if (hits[lane].is_hit() && cutouts_.cut(hits[lane])) cut.set(lane);
    });
    if (!cut.any()) return packed;
    // The cut lanes again, each from the next float past its cut hit (two triangles at
    // exactly that t count as one layer), until none is left on a cut hit.
    thread_local packet::RayPacket again;
    thread_local LaneHits beyond;
    again = rays;
    for (int layer = 0; layer < kLayersMax && cut.any(); ++layer) {
        again.active = cut;
        cut.for_each([&](int lane) {
            again.tmin[lane] = std::nextafter(hits[lane].hit.t, std::numeric_limits<float>::infinity());
        });
        inner_.closest(again, coherence, HitTarget(beyond), work);
        packet::LaneMask next;
        cut.for_each([&](int lane) {
            hits[lane] = beyond[lane];
            if (beyond[lane].is_hit() && cutouts_.cut(beyond[lane])) next.set(lane);
        });
        cut = next;
    }
    return packed;
}

packet::LaneMask CutoutTracer::occluded(const packet::RayPacket& rays, RayCoherence coherence,
                                        TraceWork* work) const {
    const packet::LaneMask blocked = inner_.occluded(rays, coherence, work);
    if (!blocked.any()) return blocked;
    thread_local packet::RayPacket some;
    thread_local LaneHits first;
    some = rays;
    some.active = blocked;
    closest(some, coherence, HitTarget(first), work);
    packet::LaneMask result;
    blocked.for_each([&](int lane) {
        if (first[lane].is_hit()) result.set(lane);
    });
    return result;
}

}  // namespace dynrt::detail
