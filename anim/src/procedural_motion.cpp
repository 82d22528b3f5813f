// The procedural motions' exact definitions are in procedural_motion.h; this file follows them
// term by term, in double, in the order the formulas are written.

#include "dynrt/anim/procedural_motion.h"

#include "object_names.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string_view>

namespace dynrt::anim {

namespace {

std::optional<MotionKind> parse_kind(std::string_view name) {
    if (name == "rigid") return MotionKind::rigid;
    if (name == "wave") return MotionKind::wave;
    if (name == "explode") return MotionKind::explode;
    return std::nullopt;
}

/// 2f degrees in radians.
double rigid_angle(int frame) { return 2.0 * static_cast<double>(frame) * (std::numbers::pi / 180.0); }

/// The per-vertex arrays of `object` indexed by corner: out[3i + k] = in[triangle i corner k].
template <class T>
std::vector<T> by_corner(const std::vector<T>& per_vertex, const std::vector<glm::uvec3>& triangles,
                         std::size_t stride = 1) {
    std::vector<T> out;
    out.reserve(triangles.size() * 3 * stride);
    for (const glm::uvec3& t : triangles) {
        for (int corner = 0; corner < 3; ++corner) {
            const auto first = per_vertex.begin() + static_cast<std::ptrdiff_t>(t[corner] * stride);
            out.insert(out.end(), first, first + static_cast<std::ptrdiff_t>(stride));
        }
    }
    return out;
}

}  // namespace

MotionReference motion_reference(std::span<const glm::vec3> world_positions) {
    glm::dvec3 lo(world_positions.front()), hi(world_positions.front());
    for (const glm::vec3& p : world_positions) {
        lo = glm::min(lo, glm::dvec3(p));
        hi = glm::max(hi, glm::dvec3(p));
    }
    return MotionReference{(lo + hi) * 0.5, 0.5 * glm::length(hi - lo)};
}

glm::dmat4 rigid_motion_matrix(const MotionReference& reference, int frame) {
    const double a = rigid_angle(frame);
    const double c = std::cos(a), s = std::sin(a);
    glm::dmat4 m(1.0);  // m[column][row]
    m[0] = glm::dvec4(c, 0.0, -s, 0.0);
    m[2] = glm::dvec4(s, 0.0, c, 0.0);
    const glm::dvec3& k = reference.centre;
    m[3] = glm::dvec4(k.x - (c * k.x + s * k.z), 0.0, k.z - (-s * k.x + c * k.z), 1.0);
    return m;
}

glm::dvec3 rigid_motion(const glm::dvec3& p, const MotionReference& reference, int frame) {
    const double a = rigid_angle(frame);
    const glm::dvec3 d = p - reference.centre;
    return reference.centre + glm::dvec3(d.x * std::cos(a) + d.z * std::sin(a), d.y,
                                         -d.x * std::sin(a) + d.z * std::cos(a));
}

glm::dvec3 wave_motion(const glm::dvec3& p, const MotionReference& reference, int frame) {
    const double r = reference.radius;
    if (!(r > 0.0)) return p;
    return glm::dvec3(p.x, p.y + 0.05 * r * std::sin(6.0 * p.x / r + 0.5 * static_cast<double>(frame)), p.z);
}

glm::dvec3 explode_offset(const glm::dvec3& unit_normal, std::uint32_t triangle, const MotionReference& reference,
                          int frame) {
    return static_cast<double>(frame) * 0.02 * reference.radius * (0.5 + explode_hash(triangle)) * unit_normal;
}

glm::dvec3 face_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length)) return glm::dvec3(0.0);
    return n / length;
}

bool has_unshared_triangles(const Object& object) {
    const std::vector<glm::uvec3>& triangles = object.mesh.triangles;
    if (object.mesh.positions.size() != 3 * triangles.size()) return false;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const auto first = static_cast<std::uint32_t>(3 * i);
        if (triangles[i] != glm::uvec3(first, first + 1, first + 2)) return false;
    }
    return true;
}

void unshare_triangles(Object& object) {
    if (has_unshared_triangles(object)) return;
    const std::vector<glm::uvec3>& triangles = object.mesh.triangles;
    std::vector<glm::vec3> positions = by_corner(object.mesh.positions.vector(), triangles);
    // Normals go with their corners, so the pieces keep the smooth shading of the whole.
    if (!object.mesh.normals.empty()) object.mesh.normals = by_corner(object.mesh.normals.vector(), triangles);
    if (!object.mesh.texcoords.empty()) object.mesh.texcoords = by_corner(object.mesh.texcoords.vector(), triangles);
    if (object.skin) {
        object.skin->joints = by_corner(object.skin->joints, triangles, object.skin->influences);
        object.skin->weights = by_corner(object.skin->weights, triangles, object.skin->influences);
    }
    if (object.morph) {
        object.morph->base_positions = by_corner(object.morph->base_positions, triangles);
        for (std::vector<glm::vec3>& deltas : object.morph->position_deltas) deltas = by_corner(deltas, triangles);
        if (!object.morph->base_normals.empty()) {
            object.morph->base_normals = by_corner(object.morph->base_normals, triangles);
        }
        for (std::vector<glm::vec3>& deltas : object.morph->normal_deltas) deltas = by_corner(deltas, triangles);
    }
    object.mesh.positions = std::move(positions);
    std::vector<glm::uvec3>& corners = object.mesh.triangles.edit();
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const auto first = static_cast<std::uint32_t>(3 * i);
        corners[i] = glm::uvec3(first, first + 1, first + 2);
    }
}

void add_procedural_motions(Scene& scene, std::span<const std::string> specs) {
    std::vector<ProceduralMotion> added;
    for (const std::string& spec : specs) {
        const auto fail = [&](const std::string& what) {
            throw std::invalid_argument("motion spec '" + spec + "': " + what);
        };
        const std::size_t colon = spec.find(':');
        const std::string_view kind_name = std::string_view(spec).substr(0, colon);
        const std::optional<MotionKind> kind = parse_kind(kind_name);
        if (!kind) fail("unknown motion '" + std::string(kind_name) + "' (expected rigid, wave or explode)");
        std::vector<std::uint32_t> objects;
        if (colon == std::string::npos) {
            for (std::size_t i = 0; i < scene.objects.size(); ++i) objects.push_back(static_cast<std::uint32_t>(i));
        } else {
            const std::string_view name = std::string_view(spec).substr(colon + 1);
            if (name.empty()) fail("expected MOTION:OBJECT with an object name after ':'");
            objects = match_objects(scene, name);
            if (objects.empty()) fail(no_such_object(scene, name));
        }
        for (const std::uint32_t object : objects) added.push_back(ProceduralMotion{*kind, object});
    }
    for (const ProceduralMotion& motion : added) {
        if (motion.kind == MotionKind::explode) unshare_triangles(scene.objects[motion.object]);
        scene.motions.push_back(motion);
    }
}

}  // namespace dynrt::anim
