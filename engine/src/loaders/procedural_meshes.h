#pragma once
// The three procedural meshes behind `sphere:N`, `soup:N` and `plane:N`. Their definitions are
// exact (scenes/README.md) so that other tools can rebuild the very same triangles bit for bit;
// change nothing here without changing the README and the tests that recompute them.

#include "dynrt/scene/scene.h"

#include <cstdint>

namespace dynrt {

/// splitmix64 (Steele, Lea, Flood 2014, "Fast splittable pseudorandom number generators"), the
/// random stream of `soup:N`. Plain value type; each copy is an independent stream.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

    /// Next 64-bit output.
    std::uint64_t next();

    /// Next float in [0, 1): the top 24 bits of next() divided by 2^24 (exact in float).
    float next_unit_float();

private:
    std::uint64_t state_;
};

/// Stack count S of `sphere:N`: max(2, round((1 + sqrt(1 + N)) / 2)), in double; the sphere
/// then has L = 2S slices and 2L(S-1) = 4S(S-1) triangles, the count closest to N.
std::uint64_t sphere_stack_count(std::uint64_t n);

/// Triangles `kind:N` makes (sphere 4S(S-1), soup N, plane 2N^2), without building it, so a spec
/// can be rejected before any allocation. Saturates instead of overflowing.
std::uint64_t sphere_triangle_count(std::uint64_t n);
std::uint64_t soup_triangle_count(std::uint64_t n);
std::uint64_t plane_triangle_count(std::uint64_t n);

/// UV sphere of radius 1 at the origin, poles on the Y axis, outward-facing counter-clockwise
/// triangles. Precondition: 1 <= n and sphere_triangle_count(n) fits in memory.
Mesh make_sphere_mesh(std::uint64_t n);

/// N independent random triangles in a cube around [0,1)^3 with edge scale 2/cbrt(N), from
/// SplitMix64(1). Precondition: 1 <= n.
Mesh make_soup_mesh(std::uint64_t n);

/// Square [-1,1]x[-1,1] in XZ at y = 0, n x n quads of two triangles each, facing +Y.
/// Precondition: 1 <= n <= 2^23 (grid coordinates stay exact in float).
Mesh make_plane_mesh(std::uint64_t n);

}  // namespace dynrt
