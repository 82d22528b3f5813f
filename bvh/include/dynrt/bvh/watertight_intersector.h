#pragma once
// Watertight ray/triangle intersection (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)). Rays through a shared edge or vertex of a closed mesh hit at
// least one of the triangles that share it.

#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"

#include <cmath>
#include <cstdint>
#include <utility>

namespace dynrt::bvh {

/// Per-ray constants of the test: the ray is transformed so that it starts at the origin and
/// points along +z, by a permutation of axes (kx, ky, kz) and a shear (sx, sy, sz).
struct WatertightRay {
    glm::vec3 org;
    int kx, ky, kz;
    float sx, sy, sz;

    /// `ray.dir` must be non-zero and finite. Inline: traversal builds one per ray.
    explicit WatertightRay(const Ray& ray) : org(ray.org) {
        // kz: the dimension where the direction is largest in magnitude, so the divisions below
        // are by the largest component (ties go to the lowest axis).
        const float mx = std::fabs(ray.dir.x), my = std::fabs(ray.dir.y), mz = std::fabs(ray.dir.z);
        kz = (mx >= my && mx >= mz) ? 0 : (my >= mz ? 1 : 2);
        kx = kz == 2 ? 0 : kz + 1;
        ky = kx == 2 ? 0 : kx + 1;
        const float dz = ray.dir[kz];
        // Swapping x and y for a negative z direction keeps the winding, hence the sign of the
        // edge functions, independent of the ray's direction.
        if (dz < 0.0f) std::swap(kx, ky);
        sx = ray.dir[kx] / dz;
        sy = ray.dir[ky] / dz;
        sz = 1.0f / dz;
    }
};

/// Tests one triangle. On a hit whose t (the very float written to `hit.t`) satisfies
/// tmin <= t <= tmax, writes t, u, v into `hit` and returns true; `hit.prim` is left to the
/// caller. Back faces are hit too; rays in the triangle's plane and degenerate triangles with
/// coincident vertices never hit (see is_degenerate for the collinear case). Points on edges
/// and vertices count as inside, and a ray through an edge or vertex shared by two triangles
/// with bit-identical vertex coordinates hits at least one of them.
bool intersect_watertight(const WatertightRay& ray, const Triangle& tri, float tmin, float tmax,
                          Hit& hit);

}  // namespace dynrt::bvh
