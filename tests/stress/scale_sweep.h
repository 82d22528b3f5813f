#pragma once
// The scales and places the surface-offset stress tests (shadow rays, secondary rays) sweep:
// scenes 1e-6 ... 1e6 across, each at the origin and 1000 times its size away, and the large
// ones 1e6 away, along one fixed oblique direction.

#include <glm/vec3.hpp>

#include <vector>

namespace dynrt::stress {

struct Sweep {
    double scale;
    double offset;  ///< along (0.6, -0.48, 0.64)
};

inline std::vector<Sweep> scale_sweep() {
    std::vector<Sweep> out;
    for (const double s : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
        out.push_back({s, 0.0});
        out.push_back({s, 1000.0 * s});
        if (s >= 1e3) out.push_back({s, 1e6});
    }
    return out;
}

/// Where the sweep's scene is centred.
inline glm::dvec3 offset_of(const Sweep& sweep) { return sweep.offset * glm::dvec3(0.6, -0.48, 0.64); }

}  // namespace dynrt::stress
