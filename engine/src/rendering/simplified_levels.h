#pragma once
// A mesh's coarser levels of detail, made once per mesh for `--lod` (level_of_detail.h): each
// level is a new list of index triples over the mesh's own vertices, so its positions, normals
// and texture coordinates serve every level unchanged, and a hit on a level is shaded as a hit
// on the mesh. Follows Garland and Heckbert, "Surface Simplification Using Quadric Error
// Metrics" (SIGGRAPH 1997), through meshoptimizer's simplifier (meshopt_simplify), which keeps
// the mesh's borders and attribute seams and reports the error it made.

#include "dynrt/scene/scene.h"

#include <vector>

namespace dynrt {

/// One simplified level of a mesh.
struct SimplifiedLevel {
    /// Index triples into the mesh's vertices (a subset of them), fewer than the mesh's.
    SharedArray<glm::uvec3> triangles;
    /// How far, in object-space units, the level's surface may lie from the mesh's: the
    /// simplifier's own bound on the error it made (meshopt_simplify's result error, scaled by
    /// meshopt_simplifyScale).
    float error = 0.0f;
};

/// Meshes with fewer triangles than this keep no levels: too little to gain.
constexpr std::size_t kSimplifiedTrianglesMin = 256;

/// The mesh's levels, finest first, each about a quarter of the triangles of the one before
/// and never fewer than 32, until the simplifier cannot make a level at least a third smaller
/// than the last. Empty for meshes under kSimplifiedTrianglesMin triangles and for soups (no
/// vertex used twice: there is nothing to collapse without welding, which would merge the
/// corners' normals and texture coordinates).
std::vector<SimplifiedLevel> simplified_levels(const Mesh& mesh);

}  // namespace dynrt
