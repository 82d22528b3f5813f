// Brute-force double-precision tracer with ambiguity classification. See reference_tracer.h for
// the test itself; this file is organised as: building the flat triangle list and the edge
// adjacency, the per-triangle test, the coverage argument, and the two queries.

#include "dynrt/reference/reference_tracer.h"

#include "dynrt/engine/alpha_mask.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dynrt::reference {
namespace {

constexpr std::uint32_t kNoTri = 0xffffffffu;

// Bit pattern of a coordinate, with -0 folded into +0: the two compare equal, so a float
// tracer treats vertices differing only in the sign of a zero as the same point.
std::uint64_t coordinate_bits(double x) { return std::bit_cast<std::uint64_t>(x + 0.0); }

using PointKey = std::array<std::uint64_t, 3>;
PointKey point_key(const glm::dvec3& p) {
    return {coordinate_bits(p.x), coordinate_bits(p.y), coordinate_bits(p.z)};
}

}  // namespace

const char* to_string(Ambiguity ambiguity) {
    switch (ambiguity) {
        case Ambiguity::kNone: return "none";
        case Ambiguity::kPrimitive: return "primitive";
        case Ambiguity::kAny: return "any";
    }
    return "?";
}

/// One triangle's relation to one ray.
struct ReferenceTracer::Candidate {
    std::uint32_t tri = 0;
    /// Exact hits: the plane's t. Near misses: the plane's t clamped to the triangle's depth
    /// range along the ray, i.e. roughly where the ray passes it.
    double t = 0.0;
    /// Signed distance from the ray to the line of edge i, positive on the inside.
    double s[3] = {0.0, 0.0, 0.0};
    /// Sign of d . N: which way the triangle faces the ray; 0 when seen exactly edge-on.
    int sigma = 0;
    /// All s >= 0 and not edge-on: the double test hits it (t range not yet checked).
    bool inside = false;
    /// Lateral tolerance at this candidate's depth: an edge closer than this to the ray is
    /// "near" (set by the query).
    double reach = 0.0;
    /// tan of the angle between the ray and the triangle's normal (+inf edge-on): how fast the
    /// plane's t changes as the ray moves sideways.
    double tan_incidence = 0.0;

    double s_min() const { return std::min({s[0], s[1], s[2]}); }
    /// How far a float tracer's t for this triangle may lie from `t`: its relative rounding
    /// (layer_rel) plus the change of t across the lateral tolerance.
    double depth_band(double layer_rel) const {
        return layer_rel * std::abs(t) + reach * tan_incidence;
    }
};

// ---- Building ------------------------------------------------------------------------------

ReferenceTracer::ReferenceTracer(const Scene& scene, const anim::PosedScene& posed) {
    if (posed.objects.size() != scene.objects.size()) {
        throw std::invalid_argument("ReferenceTracer: posed scene has " +
                                    std::to_string(posed.objects.size()) + " objects, scene has " +
                                    std::to_string(scene.objects.size()));
    }

    // Scene box over every posed vertex: the coordinates a float tracer works with.
    glm::dvec3 lo(std::numeric_limits<double>::infinity());
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (const anim::PosedObject& object : posed.objects) {
        for (const glm::vec3& p : object.positions) {
            lo = glm::min(lo, glm::dvec3(p));
            hi = glm::max(hi, glm::dvec3(p));
        }
    }
    if (lo.x <= hi.x) {
        center_ = (lo + hi) * 0.5;
        radius_ = glm::length(hi - lo) * 0.5;
    }

    prim_to_tri_.resize(scene.objects.size());
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const std::vector<glm::uvec3>& indices = scene.objects[o].mesh.triangles;
        const std::vector<glm::vec3>& positions = posed.objects[o].positions;
        const std::vector<glm::vec3>& normals = posed.objects[o].normals;
        const bool with_normals = normals.size() == positions.size() && !normals.empty();
        prim_to_tri_[o].assign(indices.size(), kNoTri);
        for (std::size_t p = 0; p < indices.size(); ++p) {
            Tri tri;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t index = indices[p][k];
                if (index >= positions.size()) {
                    throw std::invalid_argument("ReferenceTracer: object " + std::to_string(o) +
                                                " triangle " + std::to_string(p) +
                                                " has vertex index out of range");
                }
                tri.v[k] = glm::dvec3(positions[index]);
            }
            // Differences of floats are exact in double (for exponents within 29 of each
            // other), and products of two such 25-bit differences are exact too, so N is zero
            // exactly when the float triangle has zero area.
            for (int i = 0; i < 3; ++i) tri.edge[i] = tri.v[(i + 2) % 3] - tri.v[(i + 1) % 3];
            tri.n = glm::cross(tri.v[1] - tri.v[0], tri.v[2] - tri.v[0]);
            if (tri.n == glm::dvec3(0.0)) {
                ++degenerate_;
                continue;
            }
            tri.object = static_cast<std::int32_t>(o);
            tri.prim = static_cast<std::int32_t>(p);
            prim_to_tri_[o][p] = static_cast<std::uint32_t>(tris_.size());
            tris_.push_back(tri);
            std::array<glm::dvec3, 3>& corner_normals = vertex_normals_.emplace_back();
            for (int k = 0; k < 3; ++k) {
                corner_normals[std::size_t(k)] = with_normals ? glm::dvec3(normals[indices[p][k]]) : glm::dvec3(0.0);
            }
            has_vertex_normals_.push_back(with_normals ? 1 : 0);

            // Bounding sphere around the centroid, padded so rounding in the filter can only
            // let more triangles through.
            const glm::dvec3 c = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
            double r = 0.0;
            for (const glm::dvec3& v : tri.v) r = std::max(r, glm::length(v - c));
            spheres_.push_back({c, r * (1.0 + 1e-9) + 1e-300});
        }
    }

    // Cut-outs: what deciding where a cut-out triangle is there needs, copied.
    if (any_cutout(scene.materials)) {
        materials_ = scene.materials;
        texcoords_.resize(scene.objects.size());
        triangles_.resize(scene.objects.size());
        for (std::size_t o = 0; o < scene.objects.size(); ++o) {
            const Object& object = scene.objects[o];
            object_material_.push_back(object.material);
            if (!materials_.at(object.material).alpha_cutoff) continue;
            texcoords_[o] = object.mesh.texcoords;
            triangles_[o] = object.mesh.triangles;
        }
        if (TextureSet::needed(scene)) textures_ = std::make_shared<const TextureSet>(scene, false);
    }

    // Edge adjacency: sort the 3n edge slots by their endpoint pair (in canonical order), so
    // slots with bitwise-equal endpoints end up next to each other and form a group.
    struct SlotKey {
        PointKey a, b;
        std::uint32_t slot;
    };
    std::vector<SlotKey> keys;
    keys.reserve(tris_.size() * 3);
    slot_flipped_.assign(tris_.size() * 3, 0);
    for (std::uint32_t t = 0; t < tris_.size(); ++t) {
        for (std::uint32_t i = 0; i < 3; ++i) {
            PointKey a = point_key(tris_[t].v[(i + 1) % 3]);
            PointKey b = point_key(tris_[t].v[(i + 2) % 3]);
            if (b < a) {
                std::swap(a, b);
                slot_flipped_[3 * t + i] = 1;
            }
            keys.push_back({a, b, 3 * t + i});
        }
    }
    std::sort(keys.begin(), keys.end(), [](const SlotKey& x, const SlotKey& y) {
        return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.slot < y.slot);
    });
    slot_group_.assign(keys.size(), 0);
    group_slots_.reserve(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) {
        if (k == 0 || keys[k].a != keys[k - 1].a || keys[k].b != keys[k - 1].b) {
            group_first_.push_back(static_cast<std::uint32_t>(group_slots_.size()));
        }
        slot_group_[keys[k].slot] = static_cast<std::uint32_t>(group_first_.size() - 1);
        group_slots_.push_back(keys[k].slot);
    }
    group_first_.push_back(static_cast<std::uint32_t>(group_slots_.size()));
}

std::uint32_t ReferenceTracer::index_of(TriangleRef tri) const {
    if (tri.object < 0 || static_cast<std::size_t>(tri.object) >= prim_to_tri_.size()) return kNoTri;
    const std::vector<std::uint32_t>& prims = prim_to_tri_[static_cast<std::size_t>(tri.object)];
    if (tri.prim < 0 || static_cast<std::size_t>(tri.prim) >= prims.size()) return kNoTri;
    return prims[static_cast<std::size_t>(tri.prim)];
}

glm::dvec3 ReferenceTracer::normal(TriangleRef tri) const {
    const std::uint32_t index = index_of(tri);
    if (index == kNoTri) throw std::invalid_argument("ReferenceTracer::normal: no such triangle");
    return glm::normalize(tris_[index].n);
}

bool ReferenceTracer::vertex_normals(TriangleRef tri, glm::dvec3 out[3]) const {
    const std::uint32_t index = index_of(tri);
    if (index == kNoTri) throw std::invalid_argument("ReferenceTracer::vertex_normals: no such triangle");
    if (!has_vertex_normals_[index]) return false;
    for (int k = 0; k < 3; ++k) out[k] = vertex_normals_[index][std::size_t(k)];
    return true;
}

void ReferenceTracer::vertices(TriangleRef tri, glm::dvec3 out[3]) const {
    const std::uint32_t index = index_of(tri);
    if (index == kNoTri) throw std::invalid_argument("ReferenceTracer::vertices: no such triangle");
    for (int k = 0; k < 3; ++k) out[k] = tris_[index].v[k];
}

double ReferenceTracer::scale_at(const glm::dvec3& origin) const {
    return glm::length(origin - center_) + radius_;
}

// ---- One triangle against one ray ----------------------------------------------------------

bool ReferenceTracer::evaluate(std::uint32_t index, const RayD& ray, double lateral,
                               Candidate& out) const {
    const Tri& tri = tris_[index];
    const glm::dvec3& d = ray.dir;
    const glm::dvec3 a[3] = {tri.v[0] - ray.org, tri.v[1] - ray.org, tri.v[2] - ray.org};

    // E_i = d . ((v_j - o) x edge_i): each term is a product of one long vector (vertex -
    // origin) and one short one (an edge), which double resolves far below any tolerance here.
    const double d_dot_n = glm::dot(d, tri.n);
    out.sigma = d_dot_n > 0.0 ? 1 : (d_dot_n < 0.0 ? -1 : 0);
    const double cos_incidence = std::abs(d_dot_n) / glm::length(tri.n);
    out.tan_incidence = out.sigma == 0 ? std::numeric_limits<double>::infinity()
                                       : std::sqrt(std::max(0.0, 1.0 - cos_incidence * cos_incidence)) /
                                             cos_incidence;
    const double orient = out.sigma < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; ++i) {
        const double e = glm::dot(d, glm::cross(a[(i + 1) % 3], tri.edge[i]));
        const double len = glm::length(glm::cross(tri.edge[i], d));
        // An edge parallel to the ray projects to a point: the triangle is seen edge-on and
        // the distance to that edge's line says nothing, so count the ray as on it.
        out.s[i] = len > 0.0 ? orient * e / len : 0.0;
        if (out.s[i] < -lateral) return false;
    }
    out.tri = index;
    out.inside = out.sigma != 0 && out.s_min() >= 0.0;

    double depth_lo = glm::dot(a[0], d), depth_hi = depth_lo;
    for (int k = 1; k < 3; ++k) {
        depth_lo = std::min(depth_lo, glm::dot(a[k], d));
        depth_hi = std::max(depth_hi, glm::dot(a[k], d));
    }
    if (out.sigma != 0) {
        const double t_plane = glm::dot(tri.n, a[0]) / d_dot_n;
        out.t = out.inside ? t_plane : std::clamp(t_plane, depth_lo, depth_hi);
    } else {
        out.t = 0.5 * (depth_lo + depth_hi);
    }
    return true;
}

// ---- Cut-outs ------------------------------------------------------------------------------
//
// The alpha is read where the ray meets the triangle's plane (exact barycentrics, as a hit's),
// and at the four points `error` away from it along the texture's axes: if any reads the other
// side of the cutoff, a float renderer may see the triangle where this one does not, or the
// other way round.

ReferenceTracer::Cover ReferenceTracer::cover(const Candidate& c, const RayD& ray, double error) const {
    const Tri& tri = tris_[c.tri];
    if (materials_.empty()) return Cover::solid;
    const std::uint32_t index = object_material_[std::size_t(tri.object)];
    const Material& material = materials_[index];
    if (!material.alpha_cutoff) return Cover::solid;
    if (c.sigma == 0) return Cover::open;  // edge-on: no point to read
    const std::vector<glm::vec2>& texcoords = texcoords_[std::size_t(tri.object)];
    const bool mapped = textures_ && textures_->maps(index) && !texcoords.empty();
    if (!mapped) return cut_out(material, material.base_alpha) ? Cover::cut : Cover::solid;
    const glm::dvec3& o = ray.org;
    const glm::dvec3& d = ray.dir;
    const double d_dot_n = glm::dot(d, tri.n);
    const double u = glm::dot(d, glm::cross(tri.v[2] - o, tri.edge[1])) / d_dot_n;
    const double v = glm::dot(d, glm::cross(tri.v[0] - o, tri.edge[2])) / d_dot_n;
    const glm::uvec3& corner = triangles_[std::size_t(tri.object)][std::size_t(tri.prim)];
    const glm::dvec2 st0(texcoords[corner.x]), st1(texcoords[corner.y]), st2(texcoords[corner.z]);
    const glm::dvec2 st = (1.0 - u - v) * st0 + u * st1 + v * st2;
    const glm::dvec2 e1 = st1 - st0, e2 = st2 - st0;
    const double twice_texture = std::abs(e1.x * e2.y - e1.y * e2.x);
    const double twice_world = glm::length(tri.n);
    const double st_error = std::sqrt(twice_texture / twice_world) * error;
    const auto is_cut = [&](glm::dvec2 at) {
        const glm::vec2 point(at);
        return cut_out(material, surface_alpha(material, index, textures_.get(), &point));
    };
    const bool centre = is_cut(st);
    for (const glm::dvec2 offset : {glm::dvec2(st_error, 0.0), glm::dvec2(-st_error, 0.0),
                                    glm::dvec2(0.0, st_error), glm::dvec2(0.0, -st_error)}) {
        if (is_cut(st + offset) != centre) return Cover::open;
    }
    return centre ? Cover::cut : Cover::solid;
}

// ---- Coverage ------------------------------------------------------------------------------
//
// A set of triangles covers a disk around the ray (in the plane perpendicular to it, of radius
// each candidate's `reach` at its depth) when no boundary of their union comes that close. An edge near the ray
// is no boundary if another member shares it (bitwise-equal endpoints, the only case in which a
// watertight float test promises to hit one of the two) and lies on the other side of it as
// seen along the ray (otherwise the edge is a silhouette). Members with an unmatched near edge
// cannot be relied on, so they are removed, which may unmatch others: iterate to a fixed point.

bool ReferenceTracer::covered(const std::vector<Candidate>& set) const {
    std::vector<std::uint8_t> alive(set.size(), 1);
    auto side = [&](const Candidate& c, std::uint32_t slot) {
        return c.sigma * (slot_flipped_[slot] ? -1 : 1);
    };
    bool changed = true;
    while (changed) {
        changed = false;
        for (std::size_t m = 0; m < set.size(); ++m) {
            if (!alive[m]) continue;
            const Candidate& c = set[m];
            bool all_matched = c.sigma != 0;
            for (std::uint32_t i = 0; i < 3 && all_matched; ++i) {
                if (c.s[i] >= c.reach) continue;
                const std::uint32_t slot = 3 * c.tri + i;
                const int own_side = side(c, slot);
                const std::uint32_t g = slot_group_[slot];
                bool matched = false;
                for (std::uint32_t k = group_first_[g]; k < group_first_[g + 1] && !matched; ++k) {
                    const std::uint32_t other_slot = group_slots_[k];
                    const std::uint32_t other_tri = other_slot / 3;
                    if (other_tri == c.tri) continue;
                    for (std::size_t q = 0; q < set.size(); ++q) {
                        if (alive[q] && set[q].tri == other_tri &&
                            own_side * side(set[q], other_slot) < 0) {
                            matched = true;
                            break;
                        }
                    }
                }
                all_matched = matched;
            }
            if (!all_matched) {
                alive[m] = 0;
                changed = true;
            }
        }
    }
    return std::find(alive.begin(), alive.end(), 1) != alive.end();
}

// ---- Closest hit ---------------------------------------------------------------------------

ReferenceHit ReferenceTracer::closest(const bvh::Ray& ray, const Tolerances& tol) const {
    const glm::dvec3 dir(ray.dir);
    const double len = glm::length(dir);
    if (!(len > 0.0) || !std::isfinite(len)) {
        throw std::invalid_argument("ReferenceTracer::closest: zero or non-finite direction");
    }
    RayD unit{glm::dvec3(ray.org), dir / len, double(ray.tmin) * len, double(ray.tmax) * len};
    ReferenceHit hit = closest(unit, tol);
    hit.t /= len;
    return hit;
}

/// Lateral tolerance `base + slope * t` at distance t along a ray; candidates nearer than
/// `origin_zone` (when > 0) make the answer kAny.
struct ReferenceTracer::Reach {
    double base = 0.0;
    double slope = 0.0;
    double origin_zone = 0.0;

    /// Written so that a zero slope gives `base` even at t = +inf.
    double at(double t) const { return slope > 0.0 ? base + slope * std::max(t, 0.0) : base; }
};

ReferenceHit ReferenceTracer::closest(const RayD& ray, const Tolerances& tol) const {
    return closest_within(ray, Reach{tol.edge_rel * scale_at(ray.org), 0.0, 0.0}, kNoTri, tol);
}

ReferenceHit ReferenceTracer::closest_leaving(const RayD& ray, TriangleRef from,
                                              const RayDeviation& deviation,
                                              const Tolerances& tol) const {
    const Reach reach{tol.edge_rel * scale_at(ray.org) + deviation.lateral, deviation.angle,
                      deviation.along};
    return closest_within(ray, reach, index_of(from), tol);
}

ReferenceHit ReferenceTracer::closest_within(const RayD& ray, const Reach& reach,
                                             std::uint32_t excluded, const Tolerances& tol) const {
    const glm::dvec3& o = ray.org;
    const glm::dvec3& d = ray.dir;

    // A ray leaving the excluded triangle's surface cannot reach what lies behind its plane or
    // in it (the float renderer starts beside the surface, on the side it leaves toward).
    bool use_half_space = false;
    glm::dvec3 plane_n(0.0), plane_p(0.0);
    double coplanar = 0.0;
    if (excluded != kNoTri) {
        plane_n = glm::normalize(tris_[excluded].n);
        plane_p = tris_[excluded].v[0];
        const double toward = glm::dot(plane_n, d);
        if (toward != 0.0) {
            use_half_space = true;
            if (toward < 0.0) plane_n = -plane_n;
        }
        coplanar = tol.edge_rel * (scale_at(o) + glm::length(o));
    }

    // Every triangle the ray hits or passes within its reach of, inside the t range widened by
    // the same amount (and by the layer tolerance at the far end).
    std::vector<Candidate> near;
    double open_t = std::numeric_limits<double>::infinity();  // the nearest open cut-out
    const double t_lo = ray.tmin - reach.at(ray.tmin);
    const double t_hi = ray.tmax + tol.layer_rel * ray.tmax + reach.at(ray.tmax);
    for (std::uint32_t k = 0; k < tris_.size(); ++k) {
        if (k == excluded) continue;
        const Sphere& s = spheres_[k];
        const glm::dvec3 w = s.c - o;
        const double tc = glm::dot(w, d);
        if (tc + s.r < t_lo || tc - s.r > t_hi) continue;
        const double lateral = reach.at(tc + s.r);  // the widest over the triangle's depths
        const glm::dvec3 q = w - tc * d;
        const double sphere_reach = s.r + lateral;
        if (glm::dot(q, q) > sphere_reach * sphere_reach) continue;
        if (use_half_space) {
            const Tri& tri = tris_[k];
            double front = -std::numeric_limits<double>::infinity();
            for (const glm::dvec3& v : tri.v) {
                front = std::max(front, glm::dot(plane_n, v - plane_p));
            }
            if (front <= coplanar) continue;
        }
        Candidate c;
        if (!evaluate(k, ray, lateral, c)) continue;
        if (c.t < t_lo || c.t > t_hi) continue;
        c.reach = reach.at(c.t);
        if (c.s_min() < -c.reach) continue;
        // A cut-out's cut part is not there; one that may be either way opens what it covers.
        const Cover there = cover(c, ray, c.reach + tol.barycentric_rel * scale_at(o));
        if (there == Cover::cut) continue;
        if (there == Cover::open) open_t = std::min(open_t, c.t - c.depth_band(tol.layer_rel));
        near.push_back(c);
    }

    // The exact answer: the nearest triangle the double test hits within [tmin, tmax].
    const Candidate* winner = nullptr;
    for (const Candidate& c : near) {
        if (!c.inside || c.t < ray.tmin || c.t > ray.tmax) continue;
        if (!winner || c.t < winner->t || (c.t == winner->t && c.tri < winner->tri)) winner = &c;
    }

    ReferenceHit hit;
    if (!winner) {
        // A miss is determined unless some triangle passes within the tolerance.
        hit.ambiguity = near.empty() ? Ambiguity::kNone : Ambiguity::kAny;
        return hit;
    }
    const Tri& w = tris_[winner->tri];
    hit.t = winner->t;
    hit.object = w.object;
    hit.prim = w.prim;
    const double d_dot_n = glm::dot(d, w.n);
    hit.u = glm::dot(d, glm::cross(w.v[2] - o, w.edge[1])) / d_dot_n;
    hit.v = glm::dot(d, glm::cross(w.v[0] - o, w.edge[2])) / d_dot_n;

    // The layer: every candidate the float tracer might report before or instead of the
    // winner: within depth tolerance of it (each t known only to its depth band: rounding, and
    // the change of t across the lateral tolerance, large at grazing incidence), or a near miss
    // in front of it.
    const double winner_band = winner->depth_band(tol.layer_rel);
    if (open_t <= winner->t + winner_band) {
        // A cut-out in front of the winner, or of its layer, may or may not be there.
        hit.ambiguity = Ambiguity::kAny;
        return hit;
    }
    const double near_margin = reach.at(ray.tmin);
    const double far_margin = std::isinf(ray.tmax) ? 0.0 : reach.at(ray.tmax);
    auto in_origin_zone = [&](const Candidate& c) {
        return reach.origin_zone > 0.0 && c.t < reach.origin_zone;
    };
    auto is_sure = [&](const Candidate& c) {
        return c.sigma != 0 && c.s_min() >= c.reach && c.t >= ray.tmin + near_margin &&
               c.t <= ray.tmax - far_margin && !in_origin_zone(c);
    };
    std::vector<Candidate> layer;
    bool same_surface = true;
    bool any_sure = false;
    bool at_origin = false;
    double spread = 0.0;
    for (const Candidate& c : near) {
        const double band = c.depth_band(tol.layer_rel);
        if (c.t - band > winner->t + winner_band) continue;
        layer.push_back(c);
        same_surface = same_surface && tris_[c.tri].object == w.object &&
                       std::abs(c.t - winner->t) <= band + winner_band;
        any_sure = any_sure || is_sure(c);
        at_origin = at_origin || in_origin_zone(c);
        spread = std::max(spread, std::abs(c.t - winner->t));
    }
    if (layer.size() == 1 && is_sure(*winner)) return hit;  // determined
    if (!same_surface || at_origin) {
        // A float ray starting anywhere within the origin zone may pass before a surface
        // inside it as well as hit it.
        hit.ambiguity = Ambiguity::kAny;
        return hit;
    }
    // One object at practically one depth: which triangle is open, whether it is hit is not,
    // provided something in the layer is certainly hit.
    const bool hit_certain = any_sure || covered(layer);
    hit.ambiguity = hit_certain ? Ambiguity::kPrimitive : Ambiguity::kAny;
    hit.t_spread_rel = winner->t > 0.0 ? spread / winner->t : 0.0;
    return hit;
}

// ---- Occlusion -----------------------------------------------------------------------------

ReferenceOcclusion ReferenceTracer::occluded(const glm::dvec3& from, const glm::dvec3& to,
                                             TriangleRef exclude, const Tolerances& tol,
                                             double origin_error,
                                             std::span<const glm::dvec3> object_transmittance) const {
    const glm::dvec3 segment = to - from;
    const double dist = glm::length(segment);
    if (!(dist > 0.0)) return {};
    const RayD ray{from, segment / dist, 0.0, dist};
    // Shadow origins are computed points: their rounding, and any offset a renderer applies,
    // scale with their coordinates too (plus origin_error for a point a deviating secondary
    // ray found). The renderer's segment and this one end at the same
    // light, so the lateral distance between them shrinks linearly from `origin_shift` at the
    // origin to the float test's own resolution `resolution` at the light.
    const double scale = scale_at(from) + glm::length(from);
    const double origin_shift = tol.shadow_rel * scale + origin_error;
    const double resolution = tol.edge_rel * scale;
    const double t_exact_lo = tol.shadow_tmin_rel * scale;
    const double coplanar = resolution;
    auto reach_at = [&](double t) {
        return std::max(resolution, origin_shift * std::clamp(1.0 - t / dist, 0.0, 1.0));
    };

    // The excluded triangle's plane, oriented toward `to`: only triangles reaching out of the
    // closed half-space behind it can block a segment leaving it toward `to`.
    const std::uint32_t excluded = index_of(exclude);
    bool use_half_space = false;
    glm::dvec3 plane_n(0.0), plane_p(0.0);
    if (excluded != kNoTri) {
        plane_n = glm::normalize(tris_[excluded].n);
        plane_p = tris_[excluded].v[0];
        const double to_side = glm::dot(plane_n, to - plane_p);
        if (to_side != 0.0) {
            use_half_space = true;
            if (to_side < 0.0) plane_n = -plane_n;
        }
    }

    bool exact = false;
    std::size_t near_count = 0;
    std::vector<Candidate> inner;  // near candidates well inside the segment's depth range
    // Transmissive triangles let the segment through, filtered by their transmittance: each
    // one it certainly crosses filters it once; one it may cross or miss makes it ambiguous.
    glm::dvec3 through(1.0);
    bool glass_ambiguous = false;
    std::vector<Candidate> glass_edge;  // glass triangles the segment passes near an edge of
    for (std::uint32_t k = 0; k < tris_.size(); ++k) {
        if (k == excluded) continue;
        const Sphere& s = spheres_[k];
        const glm::dvec3 w = s.c - from;
        const double tc = glm::dot(w, ray.dir);
        if (tc + s.r < -origin_shift || tc - s.r > dist + resolution) continue;
        const glm::dvec3 q = w - tc * ray.dir;
        const double reach = s.r + origin_shift;
        if (glm::dot(q, q) > reach * reach) continue;
        if (use_half_space) {
            const Tri& tri = tris_[k];
            double front = -std::numeric_limits<double>::infinity();
            for (const glm::dvec3& v : tri.v) front = std::max(front, glm::dot(plane_n, v - plane_p));
            if (front <= coplanar) continue;
        }
        Candidate c;
        if (!evaluate(k, ray, origin_shift, c)) continue;
        if (c.t < -origin_shift || c.t > dist + resolution) continue;
        c.reach = reach_at(c.t);
        if (c.s_min() < -c.reach) continue;
        const bool in_depth = c.t >= origin_shift && c.t <= dist - resolution;
        const Cover there = cover(c, ray, c.reach + tol.barycentric_rel * scale);
        if (there == Cover::cut) continue;
        if (there == Cover::open) {
            glass_ambiguous = true;  // an occluder, or a filter, that may not be there
            continue;
        }
        if (!object_transmittance.empty()) {
            const glm::dvec3& kt = object_transmittance[std::size_t(tris_[k].object)];
            if (kt != glm::dvec3(0.0)) {
                if (in_depth && c.sigma != 0 && c.s_min() >= c.reach) {
                    through *= kt;
                } else if (in_depth && c.sigma != 0) {
                    glass_edge.push_back(c);
                } else {
                    glass_ambiguous = true;
                }
                continue;
            }
        }
        if (c.inside && c.t > t_exact_lo && c.t < dist) exact = true;
        if (in_depth && c.sigma != 0 && c.s_min() >= c.reach) return {true, false};  // certain
        if (in_depth) inner.push_back(c);
        ++near_count;
    }
    if (!glass_edge.empty()) {
        // The segment passes near edges of glass triangles. When they are of one object, all
        // face it the same way and certainly cover it together (a shared edge of a glass
        // surface crossed once), a float tracer counts exactly one of them (watertight tests):
        // one crossing. Otherwise (a graze, several crossings) the filter is open.
        const Candidate& first = glass_edge.front();
        const bool one_crossing = std::all_of(glass_edge.begin(), glass_edge.end(), [&](const Candidate& c) {
            return tris_[c.tri].object == tris_[first.tri].object && c.sigma == first.sigma;
        }) && covered(glass_edge);
        if (one_crossing) {
            through *= object_transmittance[std::size_t(tris_[first.tri].object)];
        } else {
            glass_ambiguous = true;
        }
    }
    if (near_count == 0) return {false, glass_ambiguous, through};

    // No single triangle certainly blocks it; a closed patch of shared edges still may.
    if (!inner.empty() && covered(inner)) return {exact, !exact || glass_ambiguous, through};
    return {exact, true, through};
}

}  // namespace dynrt::reference
