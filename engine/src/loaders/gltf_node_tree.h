#pragma once
// The node tree of a glTF scene flattened into a list with world matrices. Kept apart from mesh
// loading so animation (a later issue) can re-evaluate the same instances with animated local
// transforms.

#include "dynrt/scene/node.h"

#include <tiny_gltf.h>

#include <glm/mat4x4.hpp>

#include <string>
#include <vector>

namespace dynrt {

/// One node reached from the scene roots.
struct GltfNodeInstance {
    int node = -1;          ///< Index into model.nodes.
    int parent = -1;        ///< Index of the parent in the instance list, -1 for a root.
    glm::dmat4 local{1.0};  ///< The node's own matrix: `matrix`, or T * R * S.
    glm::dmat4 world{1.0};  ///< Parent's world * local.
};

/// "name" of node `index`, or "node<index>" when it has none.
std::string gltf_node_name(const tinygltf::Model& model, int index);

/// The node's local matrix: its column-major `matrix`, or translation * rotation * scale.
/// Throws GltfDataError for wrong array lengths, non-finite values or a zero quaternion.
glm::dmat4 gltf_local_matrix(const tinygltf::Node& node);

/// The node's rest transform as a scene node (matrix, or TRS),
/// without name or parent. Throws like gltf_local_matrix.
Node gltf_scene_node(const tinygltf::Node& node);

/// The nodes of the default scene (`scene`, else scene 0; with no scenes at all, every node
/// that is nobody's child) in depth-first pre-order, parents before children. Throws
/// GltfDataError for a missing scene or node index and for a node reached twice (the glTF node
/// graph must be a forest, and this also stops cycles).
std::vector<GltfNodeInstance> flatten_node_tree(const tinygltf::Model& model);

}  // namespace dynrt
