#pragma once
// Cut-out materials (glTF alphaMode MASK, Material::alpha_cutoff): the one rule every tracer
// of dynrt and the reference in tests/ apply to decide whether a hit on such a material is
// there. A hit whose alpha is below the material's cutoff is not: the ray goes on as if the
// triangle were not there. The alpha is the material's base_alpha times its diffuse map's
// alpha at the hit's texture coordinates, read bilinearly within the map's finest level
// (TextureSet::alpha), so that where a mask is cut does not depend on distance or on the
// footprint of the ray.

#include "dynrt/engine/texture_set.h"
#include "dynrt/scene/scene.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <span>

namespace dynrt {

/// Whether any material of `materials` is a cut-out.
inline bool any_cutout(std::span<const Material> materials) {
    for (const Material& m : materials) {
        if (m.alpha_cutoff) return true;
    }
    return false;
}

/// The alpha of a hit on `material` (index `index` in its scene): base_alpha, times the
/// diffuse map's alpha at `st` when `textures` can read the map and the hit has texture
/// coordinates (`st` not null).
inline float surface_alpha(const Material& material, std::uint32_t index, const TextureSet* textures,
                           const glm::vec2* st) {
    float alpha = material.base_alpha;
    if (textures != nullptr && st != nullptr && textures->maps(index)) alpha *= textures->alpha(index, *st);
    return alpha;
}

/// Whether a hit of alpha `alpha` on `material` is cut out: the material is a cut-out and
/// the alpha is below its cutoff (glTF: "rendered fully transparent").
inline bool cut_out(const Material& material, float alpha) {
    return material.alpha_cutoff.has_value() && alpha < *material.alpha_cutoff;
}

}  // namespace dynrt
