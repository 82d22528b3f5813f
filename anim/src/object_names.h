#pragma once
// Finding objects by the names users type in `--anim` and `--treat` specs.

#include "dynrt/scene/scene.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dynrt::anim {

/// Indices of the objects whose name equals `pattern` or starts with `pattern` + "/" (every
/// primitive of a node) or `pattern` + "#" (every primitive of a mesh), in scene order.
std::vector<std::uint32_t> match_objects(const Scene& scene, std::string_view pattern);

/// "no object named 'x' in <source> (objects: 'a', 'b', ... and N more)", for messages.
std::string no_such_object(const Scene& scene, std::string_view pattern);

}  // namespace dynrt::anim
