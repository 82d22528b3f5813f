#pragma once
// glTF morph targets (glTF 2.0 section 3.7.2.2) into the scene model.

#include "dynrt/scene/morph_targets.h"

#include <tiny_gltf.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dynrt {

/// The number of morph targets of `mesh`: every primitive must have the same. Throws
/// GltfDataError otherwise.
std::size_t gltf_morph_target_count(const tinygltf::Mesh& mesh);

/// The position morph targets of `primitive` (of `mesh`, on `node`), whose POSITION values are
/// `base` and NORMAL values `base_normals` (empty when it has none); nullopt when no target has
/// a POSITION. With base normals, targets' NORMAL displacements are kept too (normal_deltas,
/// empty when no target has one). Checks: each target POSITION is FLOAT VEC3 and NORMAL
/// VEC3 (FLOAT or normalised integers) with base.size() finite elements; node.weights (else
/// mesh.weights), when given, has one finite number per target. Throws GltfDataError naming
/// the target or weights list.
std::optional<MorphTargets> read_morph_targets(const tinygltf::Model& model, const tinygltf::Node& node,
                                               const tinygltf::Mesh& mesh, const tinygltf::Primitive& primitive,
                                               const std::vector<glm::vec3>& base,
                                               const std::vector<glm::vec3>& base_normals);

/// The VEC3 elements of accessor `accessor` (FLOAT, or normalised integers as
/// KHR_mesh_quantization allows) for an attribute of `vertex_count` vertices named `what`
/// ("NORMAL", "morph target 2 NORMAL"). Throws GltfDataError naming it when the type or count
/// is wrong or a value is not finite.
std::vector<glm::vec3> read_vec3_attribute(const tinygltf::Model& model, int accessor, std::size_t vertex_count,
                                           const std::string& what);

}  // namespace dynrt
