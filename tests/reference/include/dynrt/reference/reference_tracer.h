#pragma once
// The exact reference every fast path is checked against: brute force over all triangles of a
// posed scene, in double precision, with no acceleration structure and no shortcuts.
//
// Cut-out materials (glTF alphaMode MASK, dynrt/engine/alpha_mask.h) are followed: a triangle
// is not there where its alpha is below its material's cutoff, for every query; where a float
// renderer's hit point, as far from the exact one as the tolerances allow, may read its alpha
// on the other side of the cutoff, the answer is ambiguous.
//
// It answers two questions for a ray: what does it hit (closest hit; for a secondary ray
// leaving a surface, closest_leaving), and is a segment blocked (any hit, for shadow rays).
// Beside each answer it says whether the answer is *determined*:
// whether a correct float tracer (the BVH, Embree) must give the same answer, or whether float
// rounding may legitimately change it. Rounding matters only where the ray grazes an edge or a
// vertex, or where two surfaces lie at practically the same distance; everywhere else a
// mismatch is a bug.
//
// The intersection test uses edge functions (Plücker-style signed volumes), the quantities the
// watertight float test of Woop, Benthin and Wald 2013 evaluates in its sheared frame: for a
// ray o + t d and a triangle (v0, v1, v2),
//     E0 = d . ((v1 - o) x (v2 - v1))   E1 = d . ((v2 - o) x (v0 - v2))   E2 = d . ((v0 - o) x (v1 - v0))
// are twice the signed areas of the triangles (ray, edge i) seen along d. They sum to d . N with
// N = (v1 - v0) x (v2 - v0); the ray hits when all three have the sign of d . N (zero counts as
// inside), the barycentrics are E_i / (d . N) and t = N . (v0 - o) / (d . N). |E_i| divided by
// |edge_i x d| is the distance from the ray to the line of edge i, the quantity the ambiguity
// tolerances bound. Each E_i crosses one long vector (vertex - origin) with one short one (an
// edge), so double resolves it ~10^9 times finer than any tolerance below.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/ray.h"
#include "dynrt/engine/texture_set.h"
#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace dynrt::reference {

/// How far a float tracer's answer for a ray may legitimately differ from the reference's.
enum class Ambiguity : std::uint8_t {
    /// Hit or miss, object, primitive and t are all determined: any difference is a bug.
    kNone,
    /// The ray passes through a shared edge or vertex of one object's closed surface, or hits
    /// two triangles of one object at practically the same t: it is certainly a hit on that
    /// object at (nearly) that t, but either triangle may be reported.
    kPrimitive,
    /// A graze of a silhouette edge, or surfaces of different objects at practically the same
    /// t: hit or miss and the object may differ too.
    kAny,
};

const char* to_string(Ambiguity ambiguity);

/// The tolerances that decide ambiguity. All lengths are relative to the scene's extent seen
/// from the ray's origin, `scale = |origin - c| + R` (scene box centre c, half-diagonal R):
/// an upper bound on the distance from the origin to any vertex, hence on the size of the
/// coordinate differences a float test forms (vertex - origin, then a shear). Defaults are
/// chosen so that a correct float tracer stays inside them and ambiguous pixels stay rare
/// (a few per 10^4).
struct Tolerances {
    /// Lateral distance, relative to scale, within which a primary ray counts as grazing an
    /// edge or vertex. A float watertight test rounds each vertex - origin difference (0.5 ulp
    /// of |v - o|), shears it (about 1.5 ulp more) and forms 2x2 determinants from the
    /// results; near an edge that moves the decision boundary by a few ulp of |v - o|
    /// (Woop et al. 2013, section 5). One float ulp is 2^-23 = 1.2e-7, so 4e-6 is about 30
    /// ulp: a wide margin that still flags only ~1e-4 of the pixels of a 2000-triangle mesh.
    double edge_rel = 4e-6;
    /// Relative depth within which two triangles count as the same layer: the float tracer may
    /// report either. A float t carries a relative error of a few ulp times (1 + tan(incidence));
    /// 1e-5 covers incidences up to ~88 degrees. On top of it, each triangle's t is known only
    /// to edge_rel * scale * tan(incidence), the change of its plane's t across the lateral
    /// tolerance: that is what separates two triangles meeting at a shared edge seen at a
    /// grazing angle.
    double layer_rel = 1e-5;
    /// Lateral and depth tolerance for shadow rays, relative to scale + |origin|. A renderer
    /// starts its shadow ray from its own float hit point, pushed off the surface to avoid
    /// self-intersection; both the point's rounding and the push are a number of ulps of its
    /// coordinates, so they grow with |origin| as well as with the scene. dynrt pushes by 256
    /// ulps per coordinate (Wächter and Binder 2019), at most 256 * 2^-23 |p| = 3.05e-5 |p|,
    /// plus 16 * 2^-23 = 1.9e-6 of the light's distance (a few ulps of it are how precisely a
    /// ray from the light finds the surface): 1e-5 of the scene for lights 5 scene radii away.
    /// The reference starts from the exact hit point, so an occluder edge within this distance
    /// of the shadow ray, or an occluder this close to the origin, may legitimately change the
    /// answer. Both segments end at the light, so the lateral tolerance shrinks linearly to
    /// edge_rel * scale there. 4e-5 covers that push with the scene's extent as margin, and
    /// still flags under 0.3% of the pixels seen from inside a dense triangle soup, where
    /// every edge is a silhouette. A renderer pushing further (light leaking under objects at
    /// contacts, shadows detached from their casters) fails the comparison.
    double shadow_rel = 4e-5;
    /// The exact shadow segment starts at t = shadow_tmin_rel * scale from the hit point.
    double shadow_tmin_rel = 1e-9;
    /// |n . l| below this makes the light's contribution ambiguous: the terminator, where the
    /// float and double n . l may differ in sign and the specular term jumps. Likewise |n . d|
    /// below it makes a hit that spawns secondary rays ambiguous: at grazing incidence entering
    /// and leaving may swap, and the reflected and refracted directions are ill-conditioned.
    double terminator = 1e-4;
    /// Secondary rays: the angle, in radians, by which a float renderer's reflected or
    /// refracted direction may differ from the exact one for the same incoming direction and
    /// triangle (reference_renderer.h multiplies it by how much refraction magnifies angles).
    /// Rounding the normal, the reflection formula and the normalisation costs a few ulps,
    /// ~1e-6 at worst for reasonably shaped triangles; 1e-5 is some 100 ulps.
    double direction_rel = 1e-5;
    /// |sin2_t - 1| below this makes a transmissive hit ambiguous: at the critical angle a
    /// float renderer may decide total internal reflection the other way, and cos_t =
    /// sqrt(1 - sin2_t), hence the refracted direction and the Fresnel weights, are
    /// ill-conditioned. 1e-3 bounds the refracted direction's rounding to ~1e-7 / (2 *
    /// sqrt(1e-3)) = 2e-6 and is about 0.03 degrees of incidence for glass.
    double critical = 1e-3;
    /// A secondary ray whose path weight's largest channel lies within cutoff_rel * cutoff of
    /// the cutoff may be traced by one renderer and not by the other. The float weights are
    /// products of a few factors, each rounded to a few ulps: 1e-4 leaves a wide margin.
    double cutoff_rel = 1e-4;    /// Smooth shading: how far, relative to scale, a float renderer's hit point may lie from
    /// the exact one along the surface for the same ray (its float barycentrics), so that its
    /// interpolated normal is taken elsewhere. About 8 ulps: a float barycentric coordinate
    /// is rounded to a few ulps of the coordinates it is made from.
    double barycentric_rel = 1e-6;
    /// Smooth shading: where the shading normal may turn (its rate of turning along the
    /// surface times how far the float hit point may lie, barycentric_rel * scale plus a
    /// secondary ray's deviation) enough to change the colour, weighted by the path weight,
    /// by more than this, the pixel's shading is ambiguous: a curved, shiny surface seen in a
    /// mirror. A quarter of ComparisonOptions::color_abs_tol.
    double shading_color = 2.5e-4;
};

/// A ray in double precision with a unit direction; t is distance.
struct RayD {
    glm::dvec3 org{0.0};
    glm::dvec3 dir{0.0, 0.0, 1.0};
    double tmin = 0.0;
    double tmax = std::numeric_limits<double>::infinity();
};

/// How far a float renderer's version of a secondary ray may lie from the exact one
/// (ReferenceTracer::closest_leaving), beyond the float test's own resolution: at distance t
/// from the origin, within `lateral + t * angle` of it sideways; and its origin anywhere within
/// `along` of the exact origin, so that any surface nearer than that may or may not be hit.
struct RayDeviation {
    double lateral = 0.0;
    double angle = 0.0;  ///< radians
    double along = 0.0;
};

/// Closest hit of one ray.
struct ReferenceHit {
    /// In units of the input ray's direction (for a unit float direction: distance);
    /// +inf on a miss.
    double t = std::numeric_limits<double>::infinity();
    std::int32_t object = -1;  ///< object index in scene order; -1 on a miss
    std::int32_t prim = -1;    ///< triangle index within the object; -1 on a miss
    /// Barycentrics of the hit point: p = (1 - u - v) v0 + u v1 + v v2.
    double u = 0.0, v = 0.0;
    Ambiguity ambiguity = Ambiguity::kNone;
    /// For kPrimitive: the largest relative difference between t and the t of any triangle the
    /// float tracer may report instead. 0 otherwise.
    double t_spread_rel = 0.0;

    bool is_hit() const { return object >= 0; }
};

/// Whether a segment is blocked.
struct ReferenceOcclusion {
    bool occluded = false;
    /// True when a correct float tracer may answer the other way (an occluder's silhouette
    /// within tolerance of the segment, or an occluder within tolerance of either end).
    bool ambiguous = false;
    /// What reaches the far end when not occluded: the product of the transmittances of the
    /// transmissive triangles crossed (1 when none; ReferenceTracer::occluded).
    glm::dvec3 transmittance{1.0};
};

/// A triangle of the scene, as (object, prim).
struct TriangleRef {
    std::int32_t object = -1;
    std::int32_t prim = -1;
};

/// The scene flattened for brute force: every non-degenerate triangle of the posed scene in
/// double precision, with the bounding sphere used to skip triangles far from a ray and the
/// edge adjacency used to tell shared edges from silhouettes. Build once per posed frame;
/// queries are const and thread-safe.
class ReferenceTracer {
public:
    /// Borrows nothing: copies what it needs from `scene` (object count and mesh indices, and
    /// for cut-out materials their alpha, texture coordinates and textures, read again) and
    /// `posed` (world-space float positions and, where it has them, vertex normals, converted
    /// exactly to double). Triangles whose edge
    /// cross product is exactly zero in double (zero area, as bvh::is_degenerate) are dropped:
    /// no tracer can hit them.
    ReferenceTracer(const Scene& scene, const anim::PosedScene& posed);

    /// Closest hit of a float ray (origin and direction converted exactly to double), within
    /// [ray.tmin, ray.tmax]. Ties at exactly equal t go to the lower (object, prim).
    ReferenceHit closest(const bvh::Ray& ray, const Tolerances& tol = {}) const;
    /// Same for a double ray (unit direction, t is distance).
    ReferenceHit closest(const RayD& ray, const Tolerances& tol = {}) const;

    /// Closest hit of a secondary ray (unit direction, t is distance) leaving the surface of
    /// triangle `from` at ray.org, a point on it. `from` is never hit, and neither is any
    /// triangle lying entirely behind its plane as seen along the ray or in that plane (within
    /// edge_rel * (scale + |org|)), as in occluded(). The answer is ambiguous wherever a float
    /// renderer's ray within `deviation` of this one may see otherwise: an edge within the
    /// float test's resolution (edge_rel * scale) plus deviation.lateral + t * deviation.angle
    /// of the ray (the depth bands widen to match), or any triangle within deviation.along of
    /// the origin (kAny). With a zero deviation and no `from` it is closest(ray). Ties as
    /// closest().
    ReferenceHit closest_leaving(const RayD& ray, TriangleRef from, const RayDeviation& deviation,
                                 const Tolerances& tol = {}) const;

    /// Is the segment from `from` to `to` blocked by a triangle hit at distance t in
    /// (shadow_tmin_rel * (scale + |from|), |to - from|)? `exclude` (the triangle `from` lies on) is never
    /// an occluder, and neither is any triangle lying entirely on its far side from `to` or in
    /// its plane (within edge_rel * (scale + |from|)): a ray leaving a surface cannot reach such a
    /// triangle, and its mesh neighbours (coplanar or bent away) would otherwise be grazed
    /// right at the origin. `origin_error` widens the tolerance at the origin (shadow_rel *
    /// (scale + |from|)) by that distance: how far a float renderer's own point may lie from
    /// `from` beyond the rounding shadow_rel already covers (a secondary ray's hit point, whose
    /// ray deviates from the exact one). 0 for camera-ray hits.
    /// With `object_transmittance` (per object in scene order; empty: everything opaque), a
    /// triangle of an object whose transmittance is not 0 does not block the segment but
    /// filters it (ReferenceOcclusion::transmittance): a shadow ray passing through glass,
    /// unrefracted (renderer.h, "Lights").
    ReferenceOcclusion occluded(const glm::dvec3& from, const glm::dvec3& to,
                                TriangleRef exclude = {}, const Tolerances& tol = {},
                                double origin_error = 0.0,
                                std::span<const glm::dvec3> object_transmittance = {}) const;

    /// Unit geometric normal of a triangle ((v1 - v0) x (v2 - v0), normalised).
    glm::dvec3 normal(TriangleRef tri) const;
    /// The posed vertex normals of a triangle's corners, in double; false when its object's
    /// PosedObject had none.
    bool vertex_normals(TriangleRef tri, glm::dvec3 out[3]) const;
    /// Vertices of a triangle, in double.
    void vertices(TriangleRef tri, glm::dvec3 out[3]) const;

    /// Length scale for tolerances of rays starting at `origin`: |origin - c| + R.
    double scale_at(const glm::dvec3& origin) const;

    std::size_t triangle_count() const { return tris_.size(); }
    std::size_t degenerate_count() const { return degenerate_; }
    std::size_t object_count() const { return prim_to_tri_.size(); }
    glm::dvec3 bounds_center() const { return center_; }
    double bounds_radius() const { return radius_; }

private:
    struct Tri {
        glm::dvec3 v[3];
        /// edge[i] runs from v[(i+1)%3] to v[(i+2)%3], opposite vertex i.
        glm::dvec3 edge[3];
        glm::dvec3 n;  ///< (v1 - v0) x (v2 - v0), not normalised
        std::int32_t object, prim;
    };
    struct Sphere {
        glm::dvec3 c;
        double r;
    };
    struct Candidate;
    /// The lateral tolerance along a ray, and the zone near its origin where anything is open.
    struct Reach;

    /// Edge function test of one triangle against a unit-direction ray, with `lateral` the
    /// grazing tolerance. Returns false when the ray passes farther than `lateral` outside it.
    bool evaluate(std::uint32_t tri, const RayD& ray, double lateral, Candidate& out) const;
    /// Whether a cut-out triangle is there where `ray` meets candidate `c` (its plane), a
    /// float renderer's point there lying within `error` (world units) of the exact one.
    enum class Cover : std::uint8_t { solid, cut, open };
    Cover cover(const Candidate& c, const RayD& ray, double error) const;
    /// closest() and closest_leaving(): `excluded` (an index into tris_, or none) and the
    /// triangles behind or in its plane are skipped.
    ReferenceHit closest_within(const RayD& ray, const Reach& reach, std::uint32_t excluded,
                                const Tolerances& tol) const;
    /// Keeps only candidates each of whose near edges (within its `reach` of the ray) is
    /// shared with another kept candidate lying on the other side of that edge as seen along
    /// the ray; true when any remain, which means the candidates' union covers a disk of that
    /// radius around the ray, so a watertight float test hits at least one of them.
    bool covered(const std::vector<Candidate>& set) const;
    std::uint32_t index_of(TriangleRef tri) const;

    std::vector<Tri> tris_;
    /// Per triangle (as tris_): its corners' posed normals, when has_vertex_normals_.
    std::vector<std::array<glm::dvec3, 3>> vertex_normals_;
    std::vector<std::uint8_t> has_vertex_normals_;
    std::vector<Sphere> spheres_;
    /// Edge adjacency: slot 3 * tri + i is edge i of tri. Slots with bitwise-equal endpoint
    /// positions (in either order) share a group.
    std::vector<std::uint32_t> slot_group_;
    /// Whether the slot's edge, in the group's canonical endpoint order, runs opposite to the
    /// triangle's winding (v[(i+1)%3] -> v[(i+2)%3]).
    std::vector<std::uint8_t> slot_flipped_;
    std::vector<std::uint32_t> group_first_;  ///< CSR: group g's slots are
    std::vector<std::uint32_t> group_slots_;  ///< group_slots_[group_first_[g] .. g + 1)
    /// Per object and prim: index into tris_, or kNoTri for a degenerate triangle.
    std::vector<std::vector<std::uint32_t>> prim_to_tri_;
    std::size_t degenerate_ = 0;
    /// Cut-outs, when any material is one: the scene's materials, and per object its material
    /// index and (for a cut-out) texture coordinates and triangles; the textures their alpha
    /// is read from (null when none can be).
    std::vector<Material> materials_;
    std::vector<std::uint32_t> object_material_;
    std::vector<std::vector<glm::vec2>> texcoords_;
    std::vector<std::vector<glm::uvec3>> triangles_;
    std::shared_ptr<const TextureSet> textures_;
    glm::dvec3 center_{0.0};
    double radius_ = 0.0;
};

}  // namespace dynrt::reference
