#pragma once
// glTF KHR_lights_punctual lights (point, spot, directional) hung on the scene's nodes.
//
// glTF gives photometric units: a point or spot light's intensity in candela (lm/sr), falling
// off with the inverse square of the distance; a directional light's in lux (lm/m^2). Its
// materials' diffuse term is the Lambertian kd / pi, where dynrt's Phong has kd alone
// (renderer.h), so each light's intensity is divided by pi here: a white surface facing a
// 1-lux sun then shows 1 / pi, as glTF viewers (the Khronos sample viewer, three.js) show it.

#include "gltf_node_tree.h"

#include "dynrt/scene/scene.h"

#include <tiny_gltf.h>

#include <span>
#include <vector>

namespace dynrt {

/// The lights of the nodes in `instances`, in that order, each on its node (PointLight::node is
/// the instance index): at the node's origin, pointing down its -Z. Checks: the light exists,
/// its type is known, intensity finite and >= 0, colour finite and >= 0, range (when given)
/// finite and > 0, a spot's 0 <= innerConeAngle < outerConeAngle <= pi / 2. Throws
/// GltfDataError "light 'name': ...".
std::vector<PointLight> read_lights(const tinygltf::Model& model, std::span<const GltfNodeInstance> instances);

/// The light index node `node` refers to through KHR_lights_punctual, or -1.
int node_light(const tinygltf::Node& node);

}  // namespace dynrt
