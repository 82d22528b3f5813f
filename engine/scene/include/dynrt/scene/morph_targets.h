#pragma once
// Morph targets (glTF 2.0 section 3.7.2.2): the posed vertex is
// base + sum_i weight_i * delta_i, with weights from the node, the mesh or an animation; its
// normal likewise, renormalised, when targets carry NORMAL displacements.

#include <glm/vec3.hpp>

#include <vector>

namespace dynrt {

/// Position morph targets of one object. An object has them only when some target moves
/// positions; then every target is kept (a NORMAL-only one as zero displacements), so weight i
/// is target i's.
struct MorphTargets {
    /// The mesh's own POSITION attribute. Mesh::positions holds these with `default_weights`
    /// applied (computed in double, rounded once), so code that never animates weights sees
    /// the morphed rest shape.
    std::vector<glm::vec3> base_positions;
    /// One displacement per vertex for each target, in target order; all zero for a target
    /// without POSITION.
    std::vector<std::vector<glm::vec3>> position_deltas;
    /// One weight per target: the node's `weights`, else the mesh's, else all zero.
    std::vector<double> default_weights;
    /// The mesh's own normals before morphing (Mesh::normals holds them with default_weights
    /// applied and renormalised), empty when the mesh has none.
    std::vector<glm::vec3> base_normals;
    /// Empty when no target moves normals (or the mesh has none); otherwise one normal
    /// displacement per vertex for each target, in target order, all zero for a target
    /// without NORMAL. The posed normal is normalize(base + sum_i weight_i * delta_i).
    std::vector<std::vector<glm::vec3>> normal_deltas;
};

}  // namespace dynrt
