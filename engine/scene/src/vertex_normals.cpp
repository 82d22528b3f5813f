#include "dynrt/scene/vertex_normals.h"

#include <map>
#include <utility>

namespace dynrt {

std::vector<glm::vec3> area_weighted_normals(std::span<const glm::vec3> positions,
                                             std::span<const glm::uvec3> triangles) {
    // The cross product's length is twice the triangle's area: summing it unnormalised is the
    // area weighting.
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

void add_missing_normals(Scene& scene) {
    // Copies of one mesh (shared arrays) share the normals made for the first of them.
    std::map<std::pair<const glm::vec3*, const glm::uvec3*>, const Mesh*> made;
    for (Object& object : scene.objects) {
        Mesh& mesh = object.mesh;
        if (!mesh.normals.empty() || mesh.positions.empty()) continue;
        const auto [first, fresh] = made.try_emplace({mesh.positions.data(), mesh.triangles.data()}, &mesh);
        if (fresh) {
            mesh.normals = area_weighted_normals(mesh.positions, mesh.triangles);
        } else {
            mesh.normals = first->second->normals;
        }
    }
}

}  // namespace dynrt
