#pragma once
// Choosing which of a scene's clips play (`--clip`).

#include "dynrt/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace dynrt::anim {

/// The index into scene.clips of the clip named `name_or_index`, else of the clip with that
/// decimal index. Throws std::invalid_argument naming the request and listing the clips.
std::size_t find_clip(const Scene& scene, std::string_view name_or_index);

/// Two clips that animate the same property of the same node: played together, the first
/// would silently mask the other there.
struct ClipOverlap {
    std::size_t first = 0;   ///< index into scene.clips
    std::size_t second = 0;  ///< index into scene.clips, listed after `first` in `clips`
    std::uint32_t node = 0;  ///< index into scene.nodes
    AnimatedProperty property = AnimatedProperty::translation;
};

/// The first two of `clips` (indices into scene.clips, in the order given) that animate the
/// same property of the same node, or nothing when no two do. A clip listed twice overlaps
/// itself (when it animates anything).
std::optional<ClipOverlap> find_clip_overlap(const Scene& scene, std::span<const std::size_t> clips);

/// "translation", "rotation", "scale" or "weights", as glTF names the property.
const char* animated_property_name(AnimatedProperty property);

/// The clips that play when the user names none: all of them, together, when no two animate
/// the same property of the same node (the file then means them as parts of one animation,
/// e.g. one clip per object); else only the first, since clips that drive the same nodes are
/// alternatives (a character's Survey, Walk and Run) and played together the first listed
/// would silently mask the others. Empty for a scene without clips.
std::vector<std::size_t> default_clips(const Scene& scene);

}  // namespace dynrt::anim
