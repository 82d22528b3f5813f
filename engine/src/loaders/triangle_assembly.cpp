#include "triangle_assembly.h"

namespace dynrt {

std::vector<glm::uvec3> assemble_triangles(TriangleTopology topology,
                                           std::span<const std::uint32_t> indices) {
    std::vector<glm::uvec3> triangles;
    const std::size_t n = indices.size();
    switch (topology) {
        case TriangleTopology::list:
            triangles.reserve(n / 3);
            for (std::size_t i = 0; i + 2 < n; i += 3) {
                triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
            }
            break;
        case TriangleTopology::strip:
            if (n < 3) break;
            triangles.reserve(n - 2);
            for (std::size_t i = 0; i + 2 < n; ++i) {
                const std::size_t odd = i % 2;
                triangles.emplace_back(indices[i], indices[i + 1 + odd], indices[i + 2 - odd]);
            }
            break;
        case TriangleTopology::fan:
            if (n < 3) break;
            triangles.reserve(n - 2);
            for (std::size_t i = 0; i + 2 < n; ++i) {
                triangles.emplace_back(indices[i + 1], indices[i + 2], indices[0]);
            }
            break;
    }
    return triangles;
}

}  // namespace dynrt
