#include "dynrt/anim/clip_selection.h"

#include <charconv>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

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

std::vector<std::size_t> default_clips(const Scene& scene) {
    std::vector<std::size_t> all;
    std::set<std::pair<std::uint32_t, int>> driven;  // (node, property) of the clips so far
    for (std::size_t c = 0; c < scene.clips.size(); ++c) {
        std::set<std::pair<std::uint32_t, int>> mine;
        for (const AnimationChannel& channel : scene.clips[c].channels) {
            mine.emplace(channel.node, static_cast<int>(channel.property));
        }
        for (const auto& key : mine) {
            if (driven.count(key) != 0) return {0};
        }
        driven.insert(mine.begin(), mine.end());
        all.push_back(c);
    }
    return all;
}

}  // namespace dynrt::anim
