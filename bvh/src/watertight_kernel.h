#pragma once
// The watertight ray/triangle test (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)) as an inline function, so the traversal loop can inline it while
// intersect_watertight exposes the very same arithmetic. The bvh library is compiled with
// -ffp-contract=off: no multiply-add is ever fused, so every copy of this code rounds alike
// (bit-identical t wherever it is inlined) and the edge functions of two triangles sharing an
// edge stay exact negatives of each other, which is what makes the test watertight.

#include "dynrt/bvh/watertight_intersector.h"

namespace dynrt::bvh::detail {

/// The paper's fallback for an edge function that rounds to exactly zero (it may be a tiny
/// value of either sign): all three recomputed in double, where the products of floats are
/// exact and the difference rounds to zero only when it is zero. Shared by the one-triangle
/// test below and the four-lane block test (watertight_block.h), lane by lane.
inline void exact_edge_functions(float ax, float ay, float bx, float by, float cx, float cy,
                                 float& u, float& v, float& w) {
    const double cxby = static_cast<double>(cx) * static_cast<double>(by);
    const double cybx = static_cast<double>(cy) * static_cast<double>(bx);
    u = static_cast<float>(cxby - cybx);
    const double axcy = static_cast<double>(ax) * static_cast<double>(cy);
    const double aycx = static_cast<double>(ay) * static_cast<double>(cx);
    v = static_cast<float>(axcy - aycx);
    const double bxay = static_cast<double>(bx) * static_cast<double>(ay);
    const double byax = static_cast<double>(by) * static_cast<double>(ax);
    w = static_cast<float>(bxay - byax);
}

inline bool watertight_test(const WatertightRay& ray, const Triangle& tri, float tmin, float tmax,
                            Hit& hit) {
    // Vertices relative to the ray origin, in arrays so the per-ray axis permutation can index
    // them.
    const float a[3] = {tri.v0.x - ray.org.x, tri.v0.y - ray.org.y, tri.v0.z - ray.org.z};
    const float b[3] = {tri.v1.x - ray.org.x, tri.v1.y - ray.org.y, tri.v1.z - ray.org.z};
    const float c[3] = {tri.v2.x - ray.org.x, tri.v2.y - ray.org.y, tri.v2.z - ray.org.z};

    // Shear and scale so the ray becomes the +z axis (the paper's section 3).
    const float ax = a[ray.kx] - ray.sx * a[ray.kz];
    const float ay = a[ray.ky] - ray.sy * a[ray.kz];
    const float bx = b[ray.kx] - ray.sx * b[ray.kz];
    const float by = b[ray.ky] - ray.sy * b[ray.kz];
    const float cx = c[ray.kx] - ray.sx * c[ray.kz];
    const float cy = c[ray.ky] - ray.sy * c[ray.kz];

    // Scaled barycentrics: 2D edge functions of the projected triangle at the origin. U weighs
    // v0, V weighs v1, W weighs v2.
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;

    // An edge function that rounds to exactly zero may be a tiny value of either sign.
    if (u == 0.0f || v == 0.0f || w == 0.0f) exact_edge_functions(ax, ay, bx, by, cx, cy, u, v, w);

    // Both faces: the origin must be on the same side of all three edges (zero counts as
    // either side, so points on edges and vertices are inside).
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    const float det = u + v + w;
    // det == 0: the ray lies in the triangle's plane (or the triangle is degenerate).
    if (det == 0.0f) return false;

    const float az = ray.sz * a[ray.kz];
    const float bz = ray.sz * b[ray.kz];
    const float cz = ray.sz * c[ray.kz];
    const float t_scaled = u * az + v * bz + w * cz;
    // Divide before comparing, unlike the paper's division-free sign trick: then the reported
    // t itself satisfies tmin <= t <= tmax exactly, so the bounds mean the same thing to every
    // caller (a brute-force loop, the BVH, a later packet tracer).
    const float t = t_scaled / det;
    if (!(t >= tmin && t <= tmax)) return false;
    hit.t = t;
    hit.u = v / det;
    hit.v = w / det;
    return true;
}

}  // namespace dynrt::bvh::detail
