#pragma once
// Watertight ray/triangle intersection (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)). Rays through a shared edge or vertex of a closed mesh hit at
// least one of the triangles that share it.

#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle.h"

#include <cstdint>

namespace dynrt::bvh {

/// Per-ray constants of the test: the ray is transformed so that it starts at the origin and
/// points along +z, by a permutation of axes (kx, ky, kz) and a shear (sx, sy, sz).
struct WatertightRay {
    glm::vec3 org;
    int kx, ky, kz;
    float sx, sy, sz;

    /// `ray.dir` must be non-zero and finite.
    explicit WatertightRay(const Ray& ray);
};

/// Tests one triangle. On a hit with tmin <= t <= tmax (exclusive of tmax on neither side
/// beyond float rounding), writes t, u, v into `hit` and returns true; `hit.prim` is left to
/// the caller. Back faces are hit too.
bool intersect_watertight(const WatertightRay& ray, const Triangle& tri, float tmin, float tmax,
                          Hit& hit);

}  // namespace dynrt::bvh
