#include "dynrt/anim/clip_selection.h"

#include <charconv>
#include <stdexcept>
#include <string>

namespace dynrt::anim {

std::size_t find_clip(const Scene& scene, std::string_view name_or_index) {
    for (std::size_t i = 0; i < scene.clips.size(); ++i) {
        if (scene.clips[i].name == name_or_index) return i;
    }
    std::size_t index = 0;
    const char* end = name_or_index.data() + name_or_index.size();
    const auto [last, ec] = std::from_chars(name_or_index.data(), end, index);
    if (ec == std::errc() && last == end && index < scene.clips.size()) return index;

    std::string what = "clip '" + std::string(name_or_index) + "': ";
    if (scene.clips.empty()) throw std::invalid_argument(what + scene.source + " has no animation clips");
    what += "no clip of that name or index in " + scene.source + " (clips:";
    for (std::size_t i = 0; i < scene.clips.size(); ++i) {
        what += (i == 0 ? " " : ", ") + std::to_string(i) + " '" + scene.clips[i].name + "'";
    }
    throw std::invalid_argument(what + ")");
}

}  // namespace dynrt::anim
