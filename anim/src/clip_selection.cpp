#include "dynrt/anim/clip_selection.h"

#include <charconv>
#include <cstdint>
#include <map>
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

std::optional<ClipOverlap> find_clip_overlap(const Scene& scene, std::span<const std::size_t> clips) {
    std::map<std::pair<std::uint32_t, int>, std::size_t> driven;  // (node, property) -> clip
    for (const std::size_t c : clips) {
        std::set<std::pair<std::uint32_t, int>> mine;
        for (const AnimationChannel& channel : scene.clips[c].channels) {
            mine.emplace(channel.node, static_cast<int>(channel.property));
        }
        for (const auto& key : mine) {
            if (const auto it = driven.find(key); it != driven.end()) {
                return ClipOverlap{it->second, c, key.first, AnimatedProperty(key.second)};
            }
        }
        for (const auto& key : mine) driven.emplace(key, c);
    }
    return std::nullopt;
}

const char* animated_property_name(AnimatedProperty property) {
    switch (property) {
    case AnimatedProperty::translation: return "translation";
    case AnimatedProperty::rotation: return "rotation";
    case AnimatedProperty::scale: return "scale";
    case AnimatedProperty::weights: return "weights";
    }
    return "?";
}

std::vector<std::size_t> default_clips(const Scene& scene) {
    std::vector<std::size_t> all(scene.clips.size());
    for (std::size_t c = 0; c < all.size(); ++c) all[c] = c;
    if (find_clip_overlap(scene, all)) return {0};
    return all;
}

}  // namespace dynrt::anim
