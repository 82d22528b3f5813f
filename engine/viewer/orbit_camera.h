#pragma once
// The viewer's camera (`dynrt view`): a target, a distance and two angles, moved by the mouse
// and keys as interactive viewers move theirs (orbit with the left button, pan with the right
// or middle, zoom with the wheel, fly with W A S D Q E). It makes the pinhole Camera every
// frame is traced with, and writes it as `--camera` text that `dynrt render` reads back to the
// same floats, so a still view can be rendered again bit for bit.

#include "dynrt/engine/camera.h"

#include <glm/vec3.hpp>

#include <string>

namespace dynrt::viewer {

class OrbitCamera {
public:
    /// Framing `camera` (its eye, target and field of view; its up is taken to be world up,
    /// +Y, unless it is close to the view direction). Throws std::invalid_argument for a
    /// camera whose eye is its target.
    explicit OrbitCamera(const Camera& camera);

    /// Turns the eye around the target: `yaw` degrees about world up, `pitch` degrees up or
    /// down (held within 89 degrees of the horizon).
    void orbit(float yaw_deg, float pitch_deg);
    /// Moves eye and target together across the view: `right` and `up` in units of the
    /// distance to the target.
    void pan(float right, float up);
    /// Divides the distance to the target by `factor` (> 1 closer), at most down to a
    /// thousandth of the first distance.
    void zoom(float factor);
    /// Moves eye and target together along the view (`forward`), across it (`right`) and
    /// along world up (`up`), in units of the distance to the target.
    void fly(float forward, float right, float up);

    /// The camera as it is now.
    Camera camera() const;
    /// The camera as `--camera` text, every float written so that it reads back exactly.
    std::string camera_text() const;

private:
    glm::vec3 target_;
    float distance_, first_distance_;
    float yaw_deg_, pitch_deg_;
    float fov_y_deg_;
};

/// `camera` as `--camera` text (eye=...,target=...,up=...,fov=...), each float with as many
/// digits as reading it back exactly needs.
std::string camera_text(const Camera& camera);

}  // namespace dynrt::viewer
