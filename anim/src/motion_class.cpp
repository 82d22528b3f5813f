#include "dynrt/anim/motion_class.h"

#include "object_names.h"

#include <array>
#include <stdexcept>

namespace dynrt::anim {

namespace {

constexpr std::array<MotionClass, 4> kClasses = {MotionClass::static_, MotionClass::rigid,
                                                  MotionClass::deformable, MotionClass::exploding};

}  // namespace

const char* motion_class_name(MotionClass motion_class) {
    switch (motion_class) {
        case MotionClass::static_:
            return "static";
        case MotionClass::rigid:
            return "rigid";
        case MotionClass::deformable:
            return "deformable";
        case MotionClass::exploding:
            return "exploding";
    }
    return "unknown";
}

std::optional<MotionClass> parse_motion_class(std::string_view name) {
    for (const MotionClass motion_class : kClasses) {
        if (name == motion_class_name(motion_class)) return motion_class;
    }
    return std::nullopt;
}

std::vector<ClassOverride> parse_class_overrides(const Scene& scene, std::span<const std::string> specs) {
    std::vector<ClassOverride> overrides;
    for (const std::string& spec : specs) {
        const auto fail = [&](const std::string& what) {
            throw std::invalid_argument("class override '" + spec + "': " + what);
        };
        const std::size_t equals = spec.rfind('=');
        if (equals == std::string::npos || equals == 0) fail("expected NAME=CLASS");
        const std::string_view name = std::string_view(spec).substr(0, equals);
        const std::string_view class_name = std::string_view(spec).substr(equals + 1);
        const std::optional<MotionClass> motion_class = parse_motion_class(class_name);
        if (!motion_class) {
            fail("unknown class '" + std::string(class_name) + "' (expected static, rigid, deformable or exploding)");
        }
        const std::vector<std::uint32_t> objects = match_objects(scene, name);
        if (objects.empty()) fail(no_such_object(scene, name));
        for (const std::uint32_t object : objects) overrides.push_back(ClassOverride{object, *motion_class, spec});
    }
    return overrides;
}

}  // namespace dynrt::anim
