#pragma once
// How each object moves over a sequence, so the engine can pick the cheapest correct update:
// keep its tree (static), move an instance (rigid), refit (deformable) or rebuild (exploding).
// The class comes from the animation data (ScenePoser derives it); the user may raise it.

#include "dynrt/scene/scene.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dynrt::anim {

/// Ordered from cheapest to most general: each class may be treated as any later one.
enum class MotionClass : std::uint8_t {
    /// Nothing animates it (`static_`: `static` is a keyword).
    static_,
    /// Only its world transform changes: animated translation/rotation/scale on its node or an
    /// ancestor, or the procedural `rigid` motion. Its object-space vertices never change.
    rigid,
    /// Same topology, vertices move: skinning with animated joints, animated morph weights or
    /// the procedural `wave` motion.
    deformable,
    /// The procedural `explode` motion: triangles fly apart, so a refitted tree degrades.
    exploding,
};

/// "static", "rigid", "deformable" or "exploding".
const char* motion_class_name(MotionClass motion_class);

/// The class named `name` (the names above), or nullopt.
std::optional<MotionClass> parse_motion_class(std::string_view name);

/// The user's request to treat one object as a class (`--treat NAME=CLASS`).
struct ClassOverride {
    /// Index into Scene::objects.
    std::uint32_t object = 0;
    MotionClass motion_class = MotionClass::static_;
    /// The spec it came from, for messages.
    std::string spec;
};

/// Parses "NAME=CLASS" specs (split at the last '='). NAME selects objects as in
/// add_procedural_motions: an object's full name, or the part before its '/' (every primitive
/// of that node) or before its '#' (every primitive of that mesh); one override per matching
/// object. Throws std::invalid_argument naming the spec: missing '=', unknown class, no such
/// object. Whether a class may be given to an object is checked by ScenePoser: a class can only
/// be raised, never lowered below the derived one.
std::vector<ClassOverride> parse_class_overrides(const Scene& scene, std::span<const std::string> specs);

}  // namespace dynrt::anim
