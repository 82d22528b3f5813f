#include "rendering/posed_lights.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <limits>

namespace dynrt::detail {

bool any_on_node(std::span<const PointLight> lights) {
    return std::any_of(lights.begin(), lights.end(), [](const PointLight& l) { return l.node >= 0; });
}

void pose_lights(std::span<const PointLight> lights, std::span<const glm::dmat4> node_world,
                 std::vector<PointLight>& out) {
    out.assign(lights.begin(), lights.end());
    for (PointLight& light : out) {
        if (light.node < 0) continue;
        if (std::size_t(light.node) >= node_world.size()) {
            // Not a pose of this scene: left unplaceable, for the light check to name.
            light.position = glm::vec3(std::numeric_limits<float>::quiet_NaN());
            continue;
        }
        const glm::dmat4& m = node_world[std::size_t(light.node)];
        const glm::dmat3 axes(m);
        light.position = glm::vec3(m * glm::dvec4(glm::dvec3(light.position), 1.0));
        light.direction = glm::vec3(glm::normalize(axes * glm::dvec3(light.direction)));
        light.edge_u = glm::vec3(axes * glm::dvec3(light.edge_u));
        light.edge_v = glm::vec3(axes * glm::dvec3(light.edge_v));
        light.node = -1;  // placed: in world space now
    }
}

}  // namespace dynrt::detail
