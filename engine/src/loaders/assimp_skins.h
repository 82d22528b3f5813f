#pragma once
// An assimp mesh's bones (aiBone: a node name, the offset matrix from mesh space to the bone's
// space at bind time, and per-vertex weights) as a Skin and the object's SkinWeights, the same
// model glTF skins load into (dynrt/scene/skin.h).

#include "assimp_convert.h"

#include "dynrt/scene/skin.h"

#include <assimp/mesh.h>

#include <cstdint>
#include <string>
#include <vector>

namespace dynrt {

/// The mesh's bones as a new skin appended to `skins` (named "<object> skin": assimp shares no
/// skin between meshes), and each vertex's influences: the 8 largest of its weights, scaled to
/// the sum of all, when it has more (counted in `vertices_truncated`); 4 per vertex when no
/// vertex has more than 4.
/// A vertex no bone weighs, or weighs only with zeros, follows the mesh's own node
/// (`mesh_node`, added as a joint with an identity inverse bind matrix), which is where
/// assimp leaves it. Checks: each bone names a node, no node is named twice, offset matrices
/// and weights are finite, weights are not negative, vertex ids are below the vertex count.
/// Throws AssimpDataError "bone 'name': ...".
SkinWeights read_assimp_skin(const aiMesh& mesh, const std::string& object, std::int32_t mesh_node,
                             const AssimpNodeNames& nodes, std::vector<Skin>& skins,
                             std::size_t& vertices_truncated);

}  // namespace dynrt
