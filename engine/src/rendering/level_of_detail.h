#pragma once
// Level of detail as a measured approximation (RenderOptions::lod_pixels, `--lod`): each frame,
// every object that has simplified levels (simplified_levels.h) is traced with the coarsest one
// whose error, projected at the object's nearest distance from the camera, stays within the
// allowed pixels. The screen-space error bound is the classic view-dependent criterion (Luebke
// et al., "Level of Detail for 3D Graphics", 2003, ch. 4); Yoon et al.'s R-LODs (2006) make the
// same trade for ray tracing. Off by default; its cost in image error is what `bench --error
// --sweep lod=...` measures against exact frames.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/update_plan.h"
#include "rendering/simplified_levels.h"

#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

namespace dynrt {

/// One sequence's levels and this frame's choice among them.
class LevelOfDetail {
public:
    /// The scene to update and trace this frame: a copy of `scene` (made once per scene, its
    /// mesh arrays shared, its nodes, skins and clips left out) in which each object with levels holds the triangles of the one chosen.
    /// An object has levels while it is static or rigid, neither skinned nor morphed, and its
    /// mesh has some (simplified_levels); those objects become rigid in `states`, so that a
    /// change of level rebuilds one object's tree (or takes a copy's at that level), never the
    /// static group. With a null `camera` every object keeps the level it had. `changed` gets
    /// the objects whose triangles are not the last call's: their trees and reused pixels are
    /// stale. `height` is the image's in pixels; `max_pixels` > 0.
    const Scene& choose(const Scene& scene, std::span<ObjectState> states, const Camera* camera,
                        int height, float max_pixels, std::vector<std::size_t>& changed);

    /// Forgets the scene and its levels.
    void reset();

    /// Bytes held: the levels' index triples and the per-object choice.
    std::size_t memory_bytes() const;

private:
    /// A mesh's levels and its bounding sphere in object space.
    struct MeshLevels {
        std::vector<SimplifiedLevel> levels;
        glm::vec3 centre{0.0f};
        float radius = 0.0f;
    };
    const MeshLevels* levels_of(const Mesh& mesh);

    const Scene* source_ = nullptr;
    Scene scene_;
    /// By the mesh's triangles (copies of a mesh share them, and so their levels).
    std::unordered_map<const glm::uvec3*, std::unique_ptr<MeshLevels>> meshes_;
    /// Per object: 0 its mesh, k its k-th level.
    std::vector<std::size_t> chosen_;
};

}  // namespace dynrt
