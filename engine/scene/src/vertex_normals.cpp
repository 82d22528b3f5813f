#include "dynrt/scene/vertex_normals.h"

#include <cstdint>
#include <map>
#include <utility>

namespace dynrt {

namespace {

/// Whether two corners (of one triangle or of two) are the same vertex. Stops at the first
/// such corner, at once for a mesh of shared vertices.
bool shares_a_vertex(std::size_t vertex_count, std::span<const glm::uvec3> triangles) {
    std::vector<std::uint8_t> used(vertex_count, 0);
    for (const glm::uvec3& t : triangles) {
        for (const std::uint32_t v : {t.x, t.y, t.z}) {
            if (used[v] != 0) return true;
            used[v] = 1;
        }
    }
    return false;
}

}  // namespace

std::vector<glm::vec3> area_weighted_normals(std::span<const glm::vec3> positions,
                                             std::span<const glm::uvec3> triangles) {
    // The cross product's length is twice the triangle's area: summing it unnormalised is the
    // area weighting.
    if (!shares_a_vertex(positions.size(), triangles)) {
        // A soup: each vertex's sum is its one triangle's, so the sums (24 bytes a vertex, a
        // 20M-triangle soup's loading peak) are not held. The same arithmetic, 0 + n included.
        std::vector<glm::vec3> normals(positions.size(), glm::vec3(0.0f));
        for (const glm::uvec3& t : triangles) {
            const glm::dvec3 a(positions[t.x]), b(positions[t.y]), c(positions[t.z]);
            const glm::vec3 unit(normalize_or_zero(glm::dvec3(0.0) + glm::cross(b - a, c - a)));
            normals[t.x] = normals[t.y] = normals[t.z] = unit;
        }
        return normals;
    }
    std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
    for (const glm::uvec3& t : triangles) {
        const glm::dvec3 a(positions[t.x]), b(positions[t.y]), c(positions[t.z]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        sum[t.x] += n;
        sum[t.y] += n;
        sum[t.z] += n;
    }
    std::vector<glm::vec3> normals(positions.size());
    for (std::size_t v = 0; v < sum.size(); ++v) normals[v] = glm::vec3(normalize_or_zero(sum[v]));
    return normals;
}

std::vector<glm::vec3> missing_normals(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles) {
    // A soup's area-weighted normals are its faces' own: it is shaded flat, from the posed
    // triangles' geometric normals, without 36 bytes a triangle in the scene and again in every
    // pose of a moving one.
    if (!shares_a_vertex(positions.size(), triangles)) return {};
    return area_weighted_normals(positions, triangles);
}

void add_missing_normals(Scene& scene) {
    // Copies of one mesh (shared arrays) share the normals made for the first of them.
    std::map<std::pair<const glm::vec3*, const glm::uvec3*>, const Mesh*> made;
    for (Object& object : scene.objects) {
        Mesh& mesh = object.mesh;
        if (!mesh.normals.empty() || mesh.positions.empty()) continue;
        const auto [first, fresh] = made.try_emplace({mesh.positions.data(), mesh.triangles.data()}, &mesh);
        if (fresh) {
            mesh.normals = missing_normals(mesh.positions, mesh.triangles);
        } else {
            mesh.normals = first->second->normals;
        }
    }
}

}  // namespace dynrt
