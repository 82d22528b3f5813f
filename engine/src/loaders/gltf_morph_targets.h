#pragma once
// glTF morph targets (glTF 2.0 section 3.7.2.2) into the scene model.

#include "dynrt/scene/morph_targets.h"

#include <tiny_gltf.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace dynrt {

/// The number of morph targets of `mesh`: every primitive must have the same. Throws
/// GltfDataError otherwise.
std::size_t gltf_morph_target_count(const tinygltf::Mesh& mesh);

/// The position morph targets of `primitive` (of `mesh`, on `node`), whose POSITION values are
/// `base`; nullopt when no target has a POSITION. Checks: each target POSITION is FLOAT VEC3
/// with base.size() finite elements; node.weights (else mesh.weights), when given, has one
/// finite number per target. Throws GltfDataError naming the target or weights list.
std::optional<MorphTargets> read_morph_targets(const tinygltf::Model& model, const tinygltf::Node& node,
                                               const tinygltf::Mesh& mesh, const tinygltf::Primitive& primitive,
                                               const std::vector<glm::vec3>& base);

}  // namespace dynrt
