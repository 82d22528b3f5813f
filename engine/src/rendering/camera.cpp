#include "dynrt/engine/camera.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt {

Framing framing_of(const bvh::Aabb& scene_bounds) {
    glm::vec3 c = scene_bounds.center();
    float r = 0.5f * glm::length(scene_bounds.extent());
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) c = glm::vec3(0.0f);
    if (!std::isfinite(r) || !(r > 0.0f)) r = 1.0f;
    return Framing{c, r};
}

Camera default_camera(const bvh::Aabb& scene_bounds) {
    const auto [c, r] = framing_of(scene_bounds);
    Camera camera;
    camera.target = c;
    camera.eye = c + 2.5f * r * glm::normalize(glm::vec3(0.6f, 0.5f, 1.0f));
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.fov_y_deg = 45.0f;
    return camera;
}

namespace {

float parse_float(std::string_view text, std::string_view spec) {
    float value = 0.0f;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
        throw std::invalid_argument("camera '" + std::string(spec) + "': '" + std::string(text) +
                                    "' is not a finite number");
    }
    return value;
}

}  // namespace

Camera parse_camera(std::string_view spec, const Camera& base) {
    // Split at commas; a key=value token starts a new key, plain tokens continue its vector.
    std::vector<std::string_view> tokens;
    for (std::size_t start = 0; start <= spec.size();) {
        const std::size_t comma = std::min(spec.find(',', start), spec.size());
        tokens.push_back(spec.substr(start, comma - start));
        start = comma + 1;
    }
    Camera camera = base;
    for (std::size_t i = 0; i < tokens.size();) {
        const std::size_t eq = tokens[i].find('=');
        if (eq == std::string_view::npos) {
            throw std::invalid_argument("camera '" + std::string(spec) + "': expected key=value at '" +
                                        std::string(tokens[i]) + "' (keys: eye, target, up, fov)");
        }
        const std::string_view key = tokens[i].substr(0, eq);
        const std::string_view first = tokens[i].substr(eq + 1);
        if (key == "fov") {
            camera.fov_y_deg = parse_float(first, spec);
            if (!(camera.fov_y_deg > 0.0f && camera.fov_y_deg < 180.0f)) {
                throw std::invalid_argument("camera '" + std::string(spec) +
                                            "': fov must be in (0, 180) degrees");
            }
            i += 1;
            continue;
        }
        glm::vec3* target = key == "eye" ? &camera.eye
                          : key == "target" ? &camera.target
                          : key == "up" ? &camera.up : nullptr;
        if (!target) {
            throw std::invalid_argument("camera '" + std::string(spec) + "': unknown key '" +
                                        std::string(key) + "' (keys: eye, target, up, fov)");
        }
        if (i + 2 >= tokens.size()) {
            throw std::invalid_argument("camera '" + std::string(spec) + "': '" + std::string(key) +
                                        "' needs three numbers x,y,z");
        }
        *target = glm::vec3(parse_float(first, spec), parse_float(tokens[i + 1], spec),
                            parse_float(tokens[i + 2], spec));
        i += 3;
    }
    return camera;
}

Camera camera_from_scene(const anim::PosedCamera& posed) {
    Camera camera;
    camera.eye = glm::vec3(posed.eye);
    camera.target = glm::vec3(posed.eye + posed.forward);
    camera.up = glm::vec3(posed.up);
    camera.fov_y_deg = float(posed.yfov_rad * (180.0 / 3.14159265358979323846));
    return camera;
}

}  // namespace dynrt
