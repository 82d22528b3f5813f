#pragma once
// Skinning data (glTF 2.0 section 3.7.3): a skin is a list of joint nodes with their inverse
// bind matrices; each vertex of a skinned object names up to 8 of those joints with weights.
// The posed vertex is sum_k w_k * world(joint_k) * inverse_bind(joint_k) * p; the transform of
// the skinned object's own node is ignored, as the specification requires.

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace dynrt {

/// One skeleton binding, shared by every object that uses it.
struct Skin {
    /// For messages: the glTF name, or "skin<i>" after its glTF index when unnamed.
    std::string name;
    /// The joints, as indices into Scene::nodes; never empty, no repeats.
    std::vector<std::uint32_t> joints;
    /// One per joint, same order: object space -> the joint's space at bind time. Identity
    /// when the file gives none.
    std::vector<glm::dmat4> inverse_bind_matrices;
};

/// Per-vertex joint influences of one skinned object.
struct SkinWeights {
    /// Index into Scene::skins.
    std::uint32_t skin = 0;
    /// Influences per vertex: 4 (JOINTS_0/WEIGHTS_0) or 8 (also JOINTS_1/WEIGHTS_1).
    std::uint32_t influences = 4;
    /// Influence k of vertex v is at [v * influences + k]: an index into the skin's `joints`.
    std::vector<std::uint16_t> joints;
    /// Same layout as `joints`: finite, non-negative, with a positive sum per vertex.
    std::vector<float> weights;
};

}  // namespace dynrt
