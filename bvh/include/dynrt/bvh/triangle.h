#pragma once

#include "dynrt/bvh/aabb.h"

#include <glm/vec3.hpp>

namespace dynrt::bvh {

/// Three vertices, stored by value so a leaf's triangles sit contiguously for intersection.
struct Triangle {
    glm::vec3 v0, v1, v2;

    Aabb bounds() const {
        Aabb b;
        b.extend(v0); b.extend(v1); b.extend(v2);
        return b;
    }
    glm::vec3 centroid() const { return (v0 + v1 + v2) * (1.0f / 3.0f); }
};

/// True when the triangle has zero area: its edge cross product, evaluated exactly enough in
/// double precision, is the zero vector (coincident or collinear vertices). Such a triangle
/// can never be hit and is kept out of every tree.
bool is_degenerate(const Triangle& tri);

/// True when all nine coordinates are finite.
bool is_finite(const Triangle& tri);

}  // namespace dynrt::bvh
