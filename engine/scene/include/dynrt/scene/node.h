#pragma once
// The node hierarchy of a scene (glTF 2.0 section 3.5): each node has a rest local transform
// and a parent, and an object's world transform is the product of the local transforms from
// its root down. Animation replaces a node's translation, rotation or scale over time.

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace dynrt {

/// One node of the hierarchy. Scene::nodes lists parents before their children.
struct Node {
    /// For messages: the glTF name, or "node<i>" after its glTF index when unnamed.
    std::string name;
    /// Index of the parent in Scene::nodes (always below this node's own index), -1 for a root.
    std::int32_t parent = -1;
    /// The rest local transform given as a matrix. A node with a matrix is never animated
    /// (glTF 2.0 section 3.11.1 forbids animating it), and then the TRS fields are unused.
    std::optional<glm::dmat4> matrix;
    glm::dvec3 translation{0.0};
    /// Rotation quaternion (x, y, z, w) as in glTF: finite, not zero, normalised where used.
    glm::dvec4 rotation{0.0, 0.0, 0.0, 1.0};
    glm::dvec3 scale{1.0};

    /// `matrix` when set, else trs_matrix(translation, rotation, scale).
    glm::dmat4 rest_local() const;
};

/// Rotation matrix of the quaternion q = (x, y, z, w), normalised first because files and
/// interpolation round the components. Precondition: q is finite and not zero.
glm::dmat3 quaternion_matrix(const glm::dvec4& q);

/// T * R * S: scale first, then rotate by the quaternion (x, y, z, w), then translate.
/// Precondition: rotation is finite and not zero.
glm::dmat4 trs_matrix(const glm::dvec3& translation, const glm::dvec4& rotation, const glm::dvec3& scale);

}  // namespace dynrt
