#pragma once
// How a scene file asks to be shown. BART's AFF files carry a viewpoint with an image size
// (`v`), a background colour (`b`) and a frame range (`a`); glTF files carry none of these, so
// for them the command line's defaults apply.

#include <glm/vec3.hpp>

namespace dynrt {

struct SceneSetup {
    /// The image size the file renders at (its `resolution`).
    int width = 0;
    int height = 0;
    /// Frame f is at time f / fps; key times were shifted so that frame 0 is the file's start.
    double fps = 24.0;
    /// The file's sequence is frames 0 to frame_count - 1.
    int frame_count = 1;
    /// Colour of rays that hit nothing, linear RGB.
    glm::vec3 background{0.0f};
};

}  // namespace dynrt
