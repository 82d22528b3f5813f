#pragma once
// Procedural motions for any scene (`--anim MOTION[:OBJECT]`), with exact definitions that
// other tools reproduce. f is the frame index; R and c are the object's frame-0 bounding radius
// (half the diagonal of its frame-0 world box) and box centre. "Frame 0" is the object's pose at
// frame 0 before any procedural motion (its glTF animation at t = 0, if any). A motion is always
// evaluated from the object's pose at frame f, never from the previous frame's result.
//   rigid:   p' = c + RotY(2f degrees)(p - c), RotY(a): x' = x cos a + z sin a, y' = y,
//            z' = -x sin a + z cos a.
//   wave:    p' = p + 0.05 R sin(6 p.x / R + 0.5 f) (0, 1, 0).
//   explode: triangle i (unshared first) moves by f * 0.02 R (0.5 + h(i)) n_i, n_i its unit
//            face normal at frame 0 (0 for a degenerate triangle), h(i) = (hash32(i) >> 8) / 2^24.
// Several motions on one object apply in the order given, each to the previous one's result.
// A zero-size object (R = 0) does not wave or explode.

#include "dynrt/scene/scene.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dynrt::anim {

/// The integer hash of the explode motion (32-bit unsigned arithmetic throughout):
/// x ^= x >> 16; x *= 0x7feb352d; x ^= x >> 15; x *= 0x846ca68b; x ^= x >> 16.
constexpr std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/// h(i) = (hash32(i) >> 8) / 2^24, in [0, 1) and exact in double.
constexpr double explode_hash(std::uint32_t triangle) {
    return static_cast<double>(hash32(triangle) >> 8) / 16777216.0;
}

/// Centre c and radius R of a frame-0 world box.
struct MotionReference {
    glm::dvec3 centre{0.0};
    double radius = 0.0;
};

/// c = (min + max) / 2 and R = |max - min| / 2 of the box around `world_positions` (in double).
/// Precondition: not empty.
MotionReference motion_reference(std::span<const glm::vec3> world_positions);

/// The rigid motion as a matrix: T(c) * RotY(2f degrees) * T(-c).
glm::dmat4 rigid_motion_matrix(const MotionReference& reference, int frame);

/// c + RotY(2f degrees)(p - c).
glm::dvec3 rigid_motion(const glm::dvec3& p, const MotionReference& reference, int frame);

/// p + 0.05 R sin(6 p.x / R + 0.5 f) (0, 1, 0); p itself when R = 0.
glm::dvec3 wave_motion(const glm::dvec3& p, const MotionReference& reference, int frame);

/// f * 0.02 R (0.5 + h(i)) n_i for triangle i with unit normal n_i (0 for degenerate).
glm::dvec3 explode_offset(const glm::dvec3& unit_normal, std::uint32_t triangle, const MotionReference& reference,
                          int frame);

/// normalize(cross(b - a, c - a)) in double, or 0 when the cross product is zero (degenerate).
glm::dvec3 face_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

/// True when triangle i of `object` is (3i, 3i + 1, 3i + 2) and it has 3 vertices per triangle.
bool has_unshared_triangles(const Object& object);

/// Rewrites `object` so triangle i uses its own vertices 3i, 3i + 1, 3i + 2 (copying their
/// positions, skin influences and morph data), so it can explode with a fixed vertex count.
/// The geometry is unchanged. Does nothing when the object already is unshared.
void unshare_triangles(Object& object);

/// Parses `--anim` specs "MOTION[:OBJECT]" (split at the first ':'; MOTION is rigid, wave or
/// explode) and appends one ProceduralMotion per matching object to scene.motions, in spec
/// order; without OBJECT the motion goes to every object. OBJECT selects the objects whose full
/// name equals it, or whose name starts with OBJECT + "/" (every primitive of that node) or
/// OBJECT + "#" (every primitive of that mesh). Objects that explode are unshared once (their
/// mesh is rewritten here, so vertex counts stay fixed over frames). Every spec is checked
/// before the scene changes: a malformed spec, unknown motion or unknown object throws
/// std::invalid_argument naming the spec, and leaves `scene` as it was.
void add_procedural_motions(Scene& scene, std::span<const std::string> specs);

}  // namespace dynrt::anim
