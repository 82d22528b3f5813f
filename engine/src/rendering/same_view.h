#pragma once
// Whether two traces saw the scene the same way: the comparisons every pixel reuse mode makes
// between the last trace and this one (exact_reuse.h, approximate_reuse.h, FramePipeline).
// Exact comparisons of the values: any change, however small, counts.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"

#include <algorithm>
#include <span>

namespace dynrt::detail {

inline bool same_camera(const Camera& a, const Camera& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fov_y_deg == b.fov_y_deg;
}

inline bool same_lights(std::span<const PointLight> a, std::span<const PointLight> b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) {
        return x == y;
    });
}

}  // namespace dynrt::detail
