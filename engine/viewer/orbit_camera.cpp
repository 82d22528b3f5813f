// OrbitCamera (orbit_camera.h).

#include "orbit_camera.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dynrt::viewer {

namespace {

constexpr float kPitchLimitDeg = 89.0f;
const glm::vec3 kWorldUp(0.0f, 1.0f, 0.0f);

}  // namespace

OrbitCamera::OrbitCamera(const Camera& camera) : target_(camera.target), fov_y_deg_(camera.fov_y_deg) {
    const glm::vec3 offset = camera.eye - camera.target;
    distance_ = glm::length(offset);
    if (!(distance_ > 0.0f) || !std::isfinite(distance_)) {
        throw std::invalid_argument("viewer camera: the eye must not be at the target");
    }
    first_distance_ = distance_;
    const glm::vec3 d = offset / distance_;
    pitch_deg_ = std::clamp(glm::degrees(std::asin(std::clamp(d.y, -1.0f, 1.0f))), -kPitchLimitDeg, kPitchLimitDeg);
    yaw_deg_ = glm::degrees(std::atan2(d.x, d.z));
}

void OrbitCamera::orbit(float yaw_deg, float pitch_deg) {
    yaw_deg_ = std::remainder(yaw_deg_ + yaw_deg, 360.0f);
    pitch_deg_ = std::clamp(pitch_deg_ + pitch_deg, -kPitchLimitDeg, kPitchLimitDeg);
}

void OrbitCamera::pan(float right, float up) {
    const Camera c = camera();
    const glm::vec3 forward = glm::normalize(c.target - c.eye);
    const glm::vec3 r = glm::normalize(glm::cross(forward, kWorldUp));
    const glm::vec3 u = glm::cross(r, forward);
    target_ += distance_ * (right * r + up * u);
}

void OrbitCamera::zoom(float factor) {
    if (!(factor > 0.0f) || !std::isfinite(factor)) return;
    distance_ = std::max(distance_ / factor, 1e-3f * first_distance_);
}

void OrbitCamera::fly(float forward, float right, float up) {
    const Camera c = camera();
    const glm::vec3 f = glm::normalize(c.target - c.eye);
    const glm::vec3 r = glm::normalize(glm::cross(f, kWorldUp));
    target_ += distance_ * (forward * f + right * r + up * kWorldUp);
}

Camera OrbitCamera::camera() const {
    const float yaw = glm::radians(yaw_deg_), pitch = glm::radians(pitch_deg_);
    const glm::vec3 d(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    Camera c;
    c.target = target_;
    c.eye = target_ + distance_ * d;
    c.up = kWorldUp;
    c.fov_y_deg = fov_y_deg_;
    return c;
}

std::string OrbitCamera::camera_text() const { return viewer::camera_text(camera()); }

std::string camera_text(const Camera& camera) {
    std::ostringstream out;
    out << std::setprecision(std::numeric_limits<float>::max_digits10);
    const auto vec = [&](const char* name, const glm::vec3& v) { out << name << '=' << v.x << ',' << v.y << ',' << v.z; };
    vec("eye", camera.eye);
    out << ',';
    vec("target", camera.target);
    out << ',';
    vec("up", camera.up);
    out << ",fov=" << camera.fov_y_deg;
    return out.str();
}

}  // namespace dynrt::viewer
