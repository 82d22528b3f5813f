#pragma once
// Per-vertex shading normals for meshes whose file gives none: at each vertex the average of
// the normals of the triangles that use it, weighted by their areas (the sum of the
// unnormalised cross products (v1 - v0) x (v2 - v0), normalised; Gouraud 1971, "Continuous
// Shading of Curved Surfaces", with the area weighting of Max 1999, "Weights for Computing
// Vertex Normals from Facet Normals", section 1). Triangles that do not share a vertex do not
// smooth each other, so a non-indexed mesh (a triangle soup, BART's polygons) keeps its facets
// and only shared vertices are smoothed. There is no crease angle: a mesh whose hard edges
// share vertices (a cube with 8 corners) is shaded round; such files should carry normals.
//
// Also the normal transforms every stage shares: a normal goes through the cofactor matrix of
// the linear part M of a transform, cof(M) = det(M) M^-T, which keeps it perpendicular to the
// transformed surface and on the side of the transformed winding normal ((M a) x (M b) =
// cof(M) (a x b)), even for a mirroring M.

#include "dynrt/scene/scene.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace dynrt {

/// Area-weighted vertex normals of `triangles` over `positions` (computed in double, rounded
/// once): unit length, or 0 at a vertex no triangle of non-zero area uses. Precondition:
/// every index is below positions.size().
std::vector<glm::vec3> area_weighted_normals(std::span<const glm::vec3> positions,
                                             std::span<const glm::uvec3> triangles);

/// The normals a mesh whose file (or caller) gives none is shaded with: its area-weighted
/// normals, or none (empty) for a soup (no vertex used twice), whose area-weighted normals
/// would be its faces' own: it is shaded with its posed triangles' geometric normals instead
/// (flat, as renderer.h describes). The library API uses it too.
std::vector<glm::vec3> missing_normals(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles);

/// Gives every object of `scene` without Mesh::normals its missing_normals (of its rest
/// shape: morph targets without NORMAL displacements do not move them). The loaders call it
/// last.
void add_missing_normals(Scene& scene);

/// cof(M) for the linear part M of a transform: normals transform as cof(M) n (see above).
template <typename T, glm::qualifier Q>
glm::mat<3, 3, T, Q> normal_matrix(const glm::mat<3, 3, T, Q>& m) {
    return glm::mat<3, 3, T, Q>(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]),
                                glm::cross(m[0], m[1]));
}

/// v / |v|, or 0 when |v| is 0 or not finite.
template <typename T, glm::qualifier Q>
glm::vec<3, T, Q> normalize_or_zero(const glm::vec<3, T, Q>& v) {
    const T length2 = glm::dot(v, v);
    if (!(length2 > T(0)) || !(length2 < std::numeric_limits<T>::infinity())) {
        return glm::vec<3, T, Q>(T(0));
    }
    return v / std::sqrt(length2);
}

}  // namespace dynrt
