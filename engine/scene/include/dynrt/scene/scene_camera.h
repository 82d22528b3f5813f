#pragma once
// A perspective camera hung on a node (glTF 2.0 section 3.10): it sits at the node's origin,
// looks down the node's -Z axis with +Y up, and follows the node when it is animated.

#include <cstdint>
#include <string>

namespace dynrt {

struct SceneCamera {
    /// For messages: the camera's glTF name, else its node's name.
    std::string name;
    /// Index into Scene::nodes.
    std::uint32_t node = 0;
    /// Vertical field of view in radians, in (0, pi).
    double yfov_rad = 0.0;
    /// Width over height when the file gives one, else 0 (use the image's).
    double aspect_ratio = 0.0;
};

}  // namespace dynrt
