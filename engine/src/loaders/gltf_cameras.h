#pragma once
// glTF cameras (glTF 2.0 section 3.10) hung on the scene's nodes.

#include "gltf_node_tree.h"

#include "dynrt/scene/scene_camera.h"
#include "dynrt/scene/warnings.h"

#include <tiny_gltf.h>

#include <span>
#include <string>
#include <vector>

namespace dynrt {

/// The perspective cameras of the nodes in `instances`, in that order (SceneCamera::node is the
/// instance index). Orthographic cameras are skipped with a warning in `warnings`. Checks: the
/// camera exists, yfov is finite in (0, pi), aspectRatio is finite and not negative. Throws
/// GltfDataError "camera 'name': ...".
std::vector<SceneCamera> read_cameras(const tinygltf::Model& model, std::span<const GltfNodeInstance> instances,
                                      std::vector<Warning>& warnings);

}  // namespace dynrt
