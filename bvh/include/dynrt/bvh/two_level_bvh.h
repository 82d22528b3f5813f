#pragma once
// Two-level BVH: bottom-level trees (TriangleBvh) per object, built or refitted by their owner,
// and a top-level tree over the placed instances, rebuilt every frame they move (Wald, Benthin and
// Slusallek 2003, "Distributed Interactive Ray Tracing of Dynamic Scenes"; the scheme of
// Embree's and OptiX's instances). Rays reach a transformed instance's tree in its object
// space, so a rigid object that moves costs a matrix per frame instead of a refit or rebuild.
//
// Results are exact, not approximations of a flat tree: the closest hit is the lexicographic
// minimum of (t, object, prim) over every hit in [tmin, tmax], each instance's hits being those
// of bvh::intersect_closest on its own tree with the object-space ray of to_object_space.
// Hence a single identity instance gives exactly bvh::intersect_closest's hit, and the packet
// tracer (dynrt/packet/two_level_packet.h) gives exactly these results lane by lane.

#include "dynrt/bvh/bvh.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/triangle_bvh.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace dynrt::bvh {

/// One placed object: a borrowed bottom-level tree and where it sits in the world.
struct Instance {
    /// Borrowed; must outlive every trace. May be empty (no nodes): never hit. Not null.
    const TriangleBvh* blas = nullptr;
    /// True when object space is world space (static, deformable and exploding objects whose
    /// vertices are posed in world space): rays are used as they are, no transform at all.
    bool identity = true;
    /// Affine (last row 0 0 0 1); used only when !identity.
    glm::mat4 object_to_world{1.0f};
    /// Its inverse, supplied by the caller (computed in double and rounded is best). Used only
    /// when !identity. Its accuracy is measured at build_top_level and covered by the padding
    /// of the world box, so a rougher inverse only costs culling, never a hit.
    glm::mat4 world_to_object{1.0f};
    /// Reported in hits and used to break ties between instances; unique per instance.
    std::uint32_t object = 0;
};

/// Closest hit across instances.
struct InstanceHit {
    /// t in world units (the object-space direction is the transformed, unnormalised world
    /// direction, so t is the same parameter), u, v, and prim: the index within the instance's
    /// triangles (the index given to build_triangle_bvh). A default Hit on a miss.
    Hit hit;
    /// Instance::object of the hit; kInvalidId on a miss.
    std::uint32_t object = kInvalidId;

    bool is_hit() const { return object != kInvalidId; }
};

struct TwoLevelBvh {
    /// The instances of the last build_top_level, owned (their trees are borrowed).
    std::vector<Instance> instances;
    /// Per instance: a box containing everything its tree can hit, in world space, padded so
    /// that float rounding in the object-space ray never makes the top level cull a ray the
    /// instance's tree would hit (see two_level_bvh.cpp). Empty for an empty tree.
    std::vector<Aabb> world_boxes;
    /// Over the instances with a non-empty world box, one per leaf: prim ids are indices into
    /// `instances`.
    Bvh top;
    /// Part of the padding that grows with the ray's origin: every top-level box test grows
    /// the boxes by origin_pad_rel * max(|org.x|, |org.y|, |org.z|) on every side (see
    /// top_level_pad). 0 when every instance is an identity instance.
    float origin_pad_rel = 0.0f;
};

/// Rebuilds the top level over `instances` (taken by value: move it in). Call every frame in
/// which an instance's tree or transform changed; costs O(n log n) in instances. Every tree
/// must be non-null and made by build_triangle_bvh (possibly refitted since); transformed
/// instances need finite, invertible matrices. Runs on the calling thread's oneTBB arena. Not
/// thread-safe on one `tlas`.
void build_top_level(TwoLevelBvh& tlas, std::vector<Instance> instances);

/// The object-space ray of a world ray for a transformed instance (identity: the ray itself):
/// world_to_object applied to the origin (as a point) and the direction (as a vector), in float
/// with plain products and sums (the library is built without FMA contraction), so every caller
/// gets the same bits. Same tmin/tmax (t is preserved by an affine map with an unnormalised
/// direction).
Ray to_object_space(const Instance& instance, const Ray& world);

/// The padding the top level's box tests add on every side of every box for a ray starting at
/// `org`: origin_pad_rel * |org|_inf, rounded up; 0 for all-identity scenes.
float top_level_pad(const TwoLevelBvh& tlas, const glm::vec3& org);

/// `box` grown by `pad` >= 0 on every side, each bound rounded outward (one float step further,
/// so a pad below half an ulp of a bound still moves it). `box` itself when pad is 0.
Aabb grow_box(const Aabb& box, float pad);

/// The one instance of a top level that holds exactly one, an identity one (a scene of static
/// objects, or one deformable object); else null. Tracers then use its tree directly: with a
/// single instance there is nothing to order or tie-break, and its world box is its root box,
/// so the results are the same and the top level costs nothing.
const Instance* sole_identity_instance(const TwoLevelBvh& tlas);

/// Closest hit along `ray` within [ray.tmin, ray.tmax] over all instances: the lexicographic
/// minimum of (t, object, prim). Thread-safe on a shared `tlas`.
InstanceHit intersect_closest(const TwoLevelBvh& tlas, const Ray& ray);

/// True when any instance is hit within [ray.tmin, ray.tmax] (shadow rays); always equal to
/// intersect_closest(tlas, ray).is_hit(). Thread-safe.
bool intersect_any(const TwoLevelBvh& tlas, const Ray& ray);

/// The same traversals adding their work to `stats`: top-level nodes visited plus each traced
/// instance's work (TriangleBvh's counting overloads). Thread-safe if `stats` is not shared.
InstanceHit intersect_closest(const TwoLevelBvh& tlas, const Ray& ray, TraversalStats& stats);
bool intersect_any(const TwoLevelBvh& tlas, const Ray& ray, TraversalStats& stats);

}  // namespace dynrt::bvh
