#pragma once
// Choosing which of a scene's clips play (`--clip`).

#include "dynrt/scene/scene.h"

#include <cstddef>
#include <string_view>

namespace dynrt::anim {

/// The index into scene.clips of the clip named `name_or_index`, else of the clip with that
/// decimal index. Throws std::invalid_argument naming the request and listing the clips.
std::size_t find_clip(const Scene& scene, std::string_view name_or_index);

}  // namespace dynrt::anim
