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
/// double precision, is the zero vector (coincident or collinear vertices). Exact (edges in
/// double, error-free products) unless one triangle's coordinates span a factor above ~2^29.
/// Such a triangle has nothing to hit and is kept out of every tree; the watertight test alone
/// never hits one with coincident vertices, but its rounded shear can give a collinear one a
/// sliver of area.
bool is_degenerate(const Triangle& tri);

/// True when all nine coordinates are finite.
bool is_finite(const Triangle& tri);

}  // namespace dynrt::bvh
