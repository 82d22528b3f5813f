#include "rendering/simplified_levels.h"

#include <meshoptimizer.h>

#include <cstdint>
#include <limits>

namespace dynrt {

std::vector<SimplifiedLevel> simplified_levels(const Mesh& mesh) {
    std::vector<SimplifiedLevel> levels;
    const std::size_t triangles = mesh.triangles.size();
    const std::size_t vertices = mesh.positions.size();
    // A soup (three vertices of its own per triangle) has no edge to collapse.
    if (triangles < kSimplifiedTrianglesMin || vertices >= 3 * triangles) return levels;
    const float* positions = &mesh.positions[0].x;
    const std::vector<unsigned int> indices(&mesh.triangles[0].x, &mesh.triangles[0].x + 3 * triangles);
    // The simplifier's errors are relative to the mesh's extent; this makes them object-space.
    const float scale = meshopt_simplifyScale(positions, vertices, sizeof(glm::vec3));
    std::vector<unsigned int> source = indices;
    std::vector<unsigned int> simplified(indices.size());
    constexpr std::size_t kLevelTrianglesMin = 32;
    while (source.size() / 3 >= 4 * kLevelTrianglesMin) {
        const std::size_t target = source.size() / 4 / 3 * 3;
        float error = 0.0f;
        // Each level simplifies the one before (cheaper than from the mesh each time); its error
        // is then at most the sum of the steps', which is what is kept (conservative).
        const std::size_t count = meshopt_simplify(simplified.data(), source.data(), source.size(), positions,
                                                   vertices, sizeof(glm::vec3), target,
                                                   std::numeric_limits<float>::max(), 0, &error);
        if (count == 0 || 3 * count > 2 * source.size()) break;  // not a third smaller
        std::vector<glm::uvec3> level(count / 3);
        for (std::size_t t = 0; t < level.size(); ++t) {
            level[t] = glm::uvec3(simplified[3 * t], simplified[3 * t + 1], simplified[3 * t + 2]);
        }
        const float before = levels.empty() ? 0.0f : levels.back().error;
        levels.push_back(SimplifiedLevel{SharedArray<glm::uvec3>(std::move(level)), before + error * scale});
        source.assign(simplified.begin(), simplified.begin() + std::ptrdiff_t(count));
    }
    return levels;
}

}  // namespace dynrt
