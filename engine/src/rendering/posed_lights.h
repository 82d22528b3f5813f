#pragma once
// The lights of a frame: a light on a node (a glTF light, PointLight::node) moves with it. Its
// position, direction and area edges are given in the node's space and carried to world space
// by the node's world matrix at the frame, as glTF places a light at its node's origin
// pointing down the node's -Z.

#include "dynrt/scene/scene.h"

#include <glm/mat4x4.hpp>

#include <span>
#include <vector>

namespace dynrt::detail {

/// Whether any of `lights` hangs on a node (then pose_lights must run every frame).
bool any_on_node(std::span<const PointLight> lights);

/// `lights` at a frame whose node world matrices are `node_world` (Scene::nodes' indexing),
/// into `out`: lights on no node as they are; the others with position = M (position, 1),
/// direction = normalize(M3 direction) and edges M3 edge, M the node's matrix, in double.
/// A node matrix that is not finite or collapses the direction gives a non-finite light,
/// which Renderer::update refuses, naming the light and the frame.
void pose_lights(std::span<const PointLight> lights, std::span<const glm::dmat4> node_world,
                 std::vector<PointLight>& out);

}  // namespace dynrt::detail
