#pragma once
// Choosing which of a scene's clips play (`--clip`).

#include "dynrt/scene/scene.h"

#include <cstddef>
#include <string_view>
#include <vector>

namespace dynrt::anim {

/// The index into scene.clips of the clip named `name_or_index`, else of the clip with that
/// decimal index. Throws std::invalid_argument naming the request and listing the clips.
std::size_t find_clip(const Scene& scene, std::string_view name_or_index);

/// The clips that play when the user names none: all of them, together, when no two animate
/// the same property of the same node (the file then means them as parts of one animation,
/// e.g. one clip per object); else only the first, since clips that drive the same nodes are
/// alternatives (a character's Survey, Walk and Run) and played together the first listed
/// would silently mask the others. Empty for a scene without clips.
std::vector<std::size_t> default_clips(const Scene& scene);

}  // namespace dynrt::anim
