#include "dynrt/anim/posed_scene.h"

#include "dynrt/scene/scene_error.h"

#include <glm/mat4x4.hpp>

#include <cmath>
#include <string>

namespace dynrt::anim {

void pose_scene(const Scene& scene, int frame, PosedScene& out) {
    out.frame = frame;
    out.objects.resize(scene.objects.size());
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& object = scene.objects[i];
        std::vector<glm::vec3>& posed = out.objects[i].positions;
        posed.resize(object.mesh.positions.size());
        // Transform in double so that a large translation does not cost the small geometry its
        // precision twice (once in the matrix product, once in the rounding).
        const glm::dmat4 m(object.transform);
        for (std::size_t v = 0; v < posed.size(); ++v) {
            const glm::dvec4 p = m * glm::dvec4(glm::dvec3(object.mesh.positions[v]), 1.0);
            posed[v] = glm::vec3(glm::dvec3(p) / p.w);
            if (!std::isfinite(posed[v].x) || !std::isfinite(posed[v].y) ||
                !std::isfinite(posed[v].z)) {
                throw SceneError(scene.source + ": object '" + object.name + "', frame " +
                                 std::to_string(frame) + ": vertex " + std::to_string(v) +
                                 " has a non-finite position");
            }
        }
    }
}

}  // namespace dynrt::anim
