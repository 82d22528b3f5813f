#pragma once
// Motions the user adds to any scene (`--anim MOTION[:OBJECT]`), evaluated by dynrt::anim from
// the object's pose at each frame. The exact definitions are in dynrt/anim/procedural_motion.h.

#include <cstdint>

namespace dynrt {

enum class MotionKind : std::uint8_t {
    rigid,    ///< rotation about the vertical axis through the object's frame-0 box centre
    wave,     ///< vertical sine displacement travelling along x
    explode,  ///< triangles fly apart along their frame-0 normals
};

/// One motion on one object. Several may name the same object; they apply in Scene order.
struct ProceduralMotion {
    MotionKind kind = MotionKind::rigid;
    /// Index into Scene::objects.
    std::uint32_t object = 0;
};

}  // namespace dynrt
