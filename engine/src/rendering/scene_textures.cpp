#include "rendering/scene_textures.h"

#include "update/held_bytes.h"

#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace dynrt::detail {

namespace {

/// Material m's diffuse map for slot m < M, its emission map for slot M + m (TextureSet's order).
const std::optional<TextureMap>& map_in_slot(const Scene& scene, std::size_t slot) {
    const std::size_t count = scene.materials.size();
    const Material& material = scene.materials[slot % count];
    return slot < count ? material.diffuse_map : material.emission_map;
}

}  // namespace

bool SceneTextures::current(const Scene& scene) const {
    if (!set_ || scene_ != &scene) return false;
    // Materials are few; comparing their maps per trace costs nothing next to the trace.
    std::size_t k = 0;
    for (std::size_t slot = 0; slot < 2 * scene.materials.size(); ++slot) {
        const std::optional<TextureMap>& map = map_in_slot(scene, slot);
        if (!map) continue;
        if (k == maps_.size() || maps_[k].first != slot || !(maps_[k].second == *map)) return false;
        ++k;
    }
    return k == maps_.size();
}

std::optional<SurfaceTextures> SceneTextures::for_trace(const Scene& scene, const ShadingGeometry& shading,
                                                        const Camera& camera, int height) {
    if (!TextureSet::needed(scene)) return std::nullopt;
    if (!current(scene)) {
        set_ = std::make_unique<TextureSet>(scene);
        scene_ = &scene;
        maps_.clear();
        for (std::size_t slot = 0; slot < 2 * scene.materials.size(); ++slot) {
            if (const std::optional<TextureMap>& map = map_in_slot(scene, slot)) maps_.emplace_back(slot, *map);
        }
    }
    objects_.clear();
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        objects_.push_back(ObjectTexcoords{scene.objects[i].mesh.texcoords, shading.object_triangles(i)});
    }
    const float pixel_angle =
        2.0f * std::tan(0.5f * glm::radians(camera.fov_y_deg)) / float(std::max(height, 1));
    return SurfaceTextures{*set_, objects_, camera.eye, pixel_angle};
}

std::size_t SceneTextures::memory_bytes() const {
    return held_bytes(objects_) + held_bytes(maps_) + (set_ ? set_->bytes() : 0);
}

TextureFigures SceneTextures::figures() const {
    if (!set_) return {};
    return TextureFigures{set_->texture_count(), set_->bytes(), 1e3 * set_->load_seconds()};
}

}  // namespace dynrt::detail
