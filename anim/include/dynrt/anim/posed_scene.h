#pragma once
// The scene evaluated at one frame: world-space vertex positions of every object. This is the
// geometry every tracer (the BVH, the reference, Embree) sees for that frame.
// Today objects are static (positions = transform * rest positions); glTF animation, skinning,
// morphing and procedural motion extend `pose_scene` without changing its output.

#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <vector>

namespace dynrt::anim {

struct PosedObject {
    /// World-space positions, same indexing as the object's mesh.positions.
    std::vector<glm::vec3> positions;
};

struct PosedScene {
    int frame = 0;
    /// One entry per scene object, in scene order.
    std::vector<PosedObject> objects;
};

/// Evaluates `scene` at frame `frame`. Reuses the storage already in `out`, so a caller that
/// poses every frame does not reallocate. Positions are computed in double and rounded to
/// float once. Throws SceneError naming the object, vertex and frame when a posed position is
/// not finite.
void pose_scene(const Scene& scene, int frame, PosedScene& out);

}  // namespace dynrt::anim
