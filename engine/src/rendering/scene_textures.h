#pragma once
// The textures of the scene traced last, as FramePipeline keeps them between traces: opened
// (read, decoded and MIP-mapped, TextureSet) at a scene's first textured trace, and kept while
// the same scene's materials map the same textures the same way; opened again when one maps
// another, or a new material maps one (the library API's one scene gains textures and
// textured meshes over its life). Each trace it also gives the lookups each object's texture
// coordinates, through the triangles the trees hold.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/texture_figures.h"
#include "dynrt/engine/texture_set.h"
#include "dynrt/scene/scene.h"
#include "rendering/tile_shading.h"
#include "update/shading_geometry.h"

#include <cstddef>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace dynrt::detail {

class SceneTextures {
public:
    /// What texture lookups need to trace `scene` as `camera` sees it in an image `height`
    /// pixels tall, over the triangles of `shading` (the last update's: a scene object's may
    /// have gone since); the textures are opened first when they are not those of `scene` as
    /// its materials map them now. nullopt for a scene that maps no texture. The result
    /// borrows from this object until the next call.
    std::optional<SurfaceTextures> for_trace(const Scene& scene, const ShadingGeometry& shading,
                                             const Camera& camera, int height);

    /// Forgets the textures: the next textured trace opens them again.
    void clear() {
        set_.reset();
        scene_ = nullptr;
        maps_.clear();
    }

    /// Heap bytes held: the textures (TextureSet::bytes, every MIP level) and the records.
    std::size_t memory_bytes() const;

    /// The figures of the textures held (texture_figures.h); zeros when none are.
    TextureFigures figures() const;

private:
    /// Whether set_ was opened for `scene` as its materials map textures now.
    bool current(const Scene& scene) const;

    std::unique_ptr<TextureSet> set_;
    /// The scene the set was opened for, and each of its mapped materials' index and map then.
    const Scene* scene_ = nullptr;
    std::vector<std::pair<std::size_t, TextureMap>> maps_;
    /// Per object, its texture coordinates, refreshed per trace.
    std::vector<ObjectTexcoords> objects_;
};

}  // namespace dynrt::detail
