#pragma once
// Linear blend skinning (glTF 2.0 section 3.7.3; Magnenat-Thalmann et al. 1988, "Joint-dependent
// local deformations for hand animation and object grasping"):
//   p' = sum_k w_k * J_k * p,   J_j = world(joint_j) * inverse_bind_j.
// Computed in homogeneous double coordinates and divided by the resulting w, which equals the
// weight sum for affine joints: weights that do not sum to exactly 1 are normalised for free.
// Normals go through the cofactor matrix of the blended matrix's linear part (its inverse
// transpose up to scale, vertex_normals.h) and are normalised by the caller.
// ScenePoser runs this per vertex in parallel blocks (oneTBB); every vertex is computed on its
// own, so results do not depend on the thread count.

#include "dynrt/scene/skin.h"
#include "dynrt/scene/vertex_normals.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace dynrt::anim {

/// J_j = node_world[skin.joints[j]] * skin.inverse_bind_matrices[j] for every joint, into
/// `out` (resized; storage reused). Precondition: every joint indexes node_world.
void compute_joint_matrices(const Skin& skin, std::span<const glm::dmat4> node_world,
                            std::vector<glm::dmat4>& out);

/// The skinned position of vertex v, whose unskinned object-space position is p.
/// Zero weights are skipped. Preconditions: v is a vertex of `weights`, whose joint indices
/// index `joint_matrices`.
inline glm::dvec3 skinned_position(const SkinWeights& weights, std::span<const glm::dmat4> joint_matrices,
                                   std::size_t v, const glm::dvec3& p) {
    const glm::dvec4 h(p, 1.0);
    glm::dvec4 sum(0.0);
    const std::size_t first = v * weights.influences;
    for (std::size_t k = first; k < first + weights.influences; ++k) {
        const double w = weights.weights[k];
        if (w != 0.0) sum += w * (joint_matrices[weights.joints[k]] * h);
    }
    return glm::dvec3(sum) / sum.w;
}

/// The skinned normal of vertex v, whose unskinned normal is n: cof(B) n for the linear part B
/// of sum_k w_k J_k (vertex_normals.h), not normalised. Preconditions as skinned_position.
inline glm::dvec3 skinned_normal(const SkinWeights& weights, std::span<const glm::dmat4> joint_matrices,
                                 std::size_t v, const glm::dvec3& n) {
    glm::dmat3 blended(0.0);
    const std::size_t first = v * weights.influences;
    for (std::size_t k = first; k < first + weights.influences; ++k) {
        const double w = weights.weights[k];
        if (w != 0.0) blended += w * glm::dmat3(joint_matrices[weights.joints[k]]);
    }
    return normal_matrix(blended) * n;
}

}  // namespace dynrt::anim
