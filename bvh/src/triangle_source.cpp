#include "dynrt/bvh/triangle_source.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_reduce.h>

namespace dynrt::bvh {

bool TriangleSource::is_soup(std::span<const glm::uvec3> triangles) {
    // A mesh with shared vertices fails at its first triangles; a soup is read once, in order.
    constexpr std::size_t kGrain = 64 * 1024;
    const auto in_order = [&](std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t) {
            const std::size_t v = 3 * t;
            if (triangles[t].x != v || triangles[t].y != v + 1 || triangles[t].z != v + 2) return false;
        }
        return true;
    };
    if (!in_order(0, std::min(triangles.size(), kGrain))) return false;
    if (triangles.size() <= kGrain) return true;
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(kGrain, triangles.size(), kGrain), true,
        [&](const tbb::blocked_range<std::size_t>& r, bool soup) { return soup && in_order(r.begin(), r.end()); },
        [](bool a, bool b) { return a && b; });
}

}  // namespace dynrt::bvh
