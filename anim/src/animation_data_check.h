#pragma once
// The invariants ScenePoser relies on, checked once so evaluation never reads out of range even
// for hand-built scenes. The glTF loader establishes all of them with better messages.

#include "dynrt/scene/scene.h"

namespace dynrt::anim {

/// Throws SceneError naming the source and the element when node, skin, morph, clip, camera or
/// motion data is inconsistent: an index out of range, a parent after its child, arrays of
/// mismatched sizes, key times not strictly increasing, squad interpolation on anything but a
/// rotation, an animated node with a matrix, an exploding object that is not unshared.
void check_animation_data(const Scene& scene);

}  // namespace dynrt::anim
