#include "object_names.h"

namespace dynrt::anim {

namespace {

constexpr std::size_t kNamesListed = 8;

}  // namespace

std::vector<std::uint32_t> match_objects(const Scene& scene, std::string_view pattern) {
    std::vector<std::uint32_t> matches;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const std::string_view name = scene.objects[i].name;
        const bool prefix = name.size() > pattern.size() && name.substr(0, pattern.size()) == pattern &&
                            (name[pattern.size()] == '/' || name[pattern.size()] == '#');
        if (name == pattern || prefix) matches.push_back(static_cast<std::uint32_t>(i));
    }
    return matches;
}

std::string no_such_object(const Scene& scene, std::string_view pattern) {
    std::string text = "no object named '" + std::string(pattern) + "' in " + scene.source + " (objects: ";
    for (std::size_t i = 0; i < scene.objects.size() && i < kNamesListed; ++i) {
        if (i > 0) text += ", ";
        text += "'" + scene.objects[i].name + "'";
    }
    if (scene.objects.size() > kNamesListed) {
        text += " and " + std::to_string(scene.objects.size() - kNamesListed) + " more";
    }
    return text + ")";
}

}  // namespace dynrt::anim
