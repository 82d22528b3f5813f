#pragma once
// A scene's textures, held in memory as MIP pyramids (textures/mip_pyramid.h) and looked up by
// dynrt's own SIMD filter (textures/texture_filter.h): trilinear between the two MIP levels
// nearest the footprint, bilinear within each (Williams 1983, "Pyramidal Parametrics"), with
// the level choice and the levels of OpenImageIO's TextureSystem, which it replaces (the test
// textures_test.cpp compares them: within 1/255 of the same footprints). OpenImageIO reads and
// decodes the files; every mapped texture is read and MIP-mapped once, when the set is made,
// in parallel. Grey images read as grey RGB; colours are as stored (alpha not multiplied in);
// alpha is read on its own, for cut-outs (alpha()).
// The shading of every tracer and the reference renderer in tests/ look textures up here, so
// they see the same colours.
//
// A texture that cannot be read (a missing, truncated or undecodable file, an image too large)
// is reported once, as "dynrt: warning: SCENE: texture cannot be read: FILE (REASON), used by
// material 'M'; the diffuse colour is used alone", and the material then shades as if it had
// no map: never an error.

#include "dynrt/scene/scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dynrt {

/// Which map of a material a lookup reads.
enum class TextureSlot : std::uint8_t { diffuse, emission };

class TextureSet {
public:
    /// Opens the textures `scene`'s materials map (Material::diffuse_map), copying embedded
    /// images' bytes (nothing of `scene` is borrowed). Each material whose texture cannot be
    /// read is reported in warnings(), and through dynrt::warn (dynrt/scene/warnings.h: on
    /// stderr, or grouped by the front end's WarningLog) when `print_warnings`.
    explicit TextureSet(const Scene& scene, bool print_warnings = true);
    ~TextureSet();
    TextureSet(const TextureSet&) = delete;
    TextureSet& operator=(const TextureSet&) = delete;

    /// Whether any material of `scene` maps a texture (so that shading needs a TextureSet).
    static bool needed(const Scene& scene);

    /// Whether material `material` has a diffuse map (or, for TextureSlot::emission, an
    /// emission map) that could be read.
    bool maps(std::uint32_t material, TextureSlot slot = TextureSlot::diffuse) const {
        const std::size_t k = index(material, slot);
        return k < usable_.size() && usable_[k] != 0;
    }
    /// Whether any material has a readable emission map.
    bool any_emission() const { return any_emission_; }

    /// The linear RGB of material `material`'s diffuse map at texture coordinates `st`
    /// (Mesh::texcoords' convention), wrapped by the map's modes, filtered over a square
    /// footprint `width` wide in texture coordinates (0: bilinear at the finest level). sRGB
    /// texels are converted to linear after filtering. Precondition: maps(material).
    /// Thread-safe.
    glm::vec3 diffuse(std::uint32_t material, glm::vec2 st, float width) const;

    /// The same for `count` lookups of material `material` at once, SIMD across them (the
    /// same colours, bit for bit, as one at a time): lookup i at (s[i], t[i]) over width[i]
    /// writes rgb[0][i], rgb[1][i], rgb[2][i].
    void diffuse(std::uint32_t material, std::size_t count, const float* s, const float* t, const float* width,
                 float* const rgb[3]) const {
        lookup(TextureSlot::diffuse, material, count, s, t, width, rgb);
    }
    /// The same lookups in material `material`'s emission map (precondition:
    /// maps(material, TextureSlot::emission)).
    glm::vec3 emission(std::uint32_t material, glm::vec2 st, float width) const;
    /// Lookups in either map, as diffuse() describes.
    void lookup(TextureSlot slot, std::uint32_t material, std::size_t count, const float* s, const float* t,
                const float* width, float* const rgb[3]) const;

    /// The alpha channel of material `material`'s diffuse map at `st`, wrapped by its modes,
    /// bilinear within the finest level whatever the distance (what a MASK material's cut-out
    /// compares, dynrt/engine/alpha_mask.h); 1 for an image without alpha. Precondition:
    /// maps(material). Thread-safe.
    float alpha(std::uint32_t material, glm::vec2 st) const;

    /// Bytes the readable textures hold in memory, every MIP level included.
    std::size_t bytes() const;
    /// Readable textures held (each counted once, however many materials map it).
    std::size_t texture_count() const;
    /// Wall-clock seconds construction took to read, decode and MIP-map the textures.
    double load_seconds() const;

    /// What construction reported, one line per material whose texture cannot be read.
    const std::vector<std::string>& warnings() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    /// Per material and slot (index()), 1 when it maps a readable texture (maps(), inline:
    /// shading asks per hit).
    std::vector<std::uint8_t> usable_;
    std::size_t material_count_ = 0;
    bool any_emission_ = false;
    std::size_t index(std::uint32_t material, TextureSlot slot) const {
        return slot == TextureSlot::diffuse ? material : material_count_ + material;
    }
    glm::vec3 one(std::size_t k, glm::vec2 st, float width) const;
};

/// The footprint of a pixel's ray at a hit, in texture coordinates, as dynrt's shading and
/// the reference compute it (docs/rendering.md "Textures"): the width of the pixel's cone at the hit's
/// distance from the eye, `distance` * `pixel_angle` (radians per pixel, 2 tan(fov_y / 2) /
/// height), scaled from world units to texture units by the hit triangle's
/// sqrt(texture area / world area). Secondary rays use the straight distance from the eye, not
/// their path's length, and the cone ignores curvature, so reflections and refractions are
/// filtered less than a ray differential would; 0 when the triangle has no area.
inline float texture_footprint(float distance, float pixel_angle, float twice_world_area,
                               float twice_texture_area) {
    if (!(twice_world_area > 0.0f)) return 0.0f;
    return distance * pixel_angle * std::sqrt(twice_texture_area / twice_world_area);
}

}  // namespace dynrt
