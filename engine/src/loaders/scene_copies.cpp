// Copies on a grid (scene_copies.h).

#include "scene_copies.h"

#include "dynrt/scene/scene_error.h"
#include "message_text.h"

#include <glm/common.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace dynrt {

glm::mat4 copy_matrix(std::uint64_t k, std::uint64_t copies, glm::vec3 lo, glm::vec3 hi) {
    const auto side = std::uint64_t(std::ceil(std::sqrt(double(copies))));
    const float spacing = 1.5f * std::max({hi.x - lo.x, hi.z - lo.z, 1e-3f});
    const float centre = 0.5f * float(side - 1);
    const glm::vec3 c = 0.5f * (lo + hi);
    const float angle = float(double(k) * 2.399963229728653);
    const float cos_a = std::cos(angle), sin_a = std::sin(angle);
    // rotate_y(angle) * translate(-c), then moved to the grid point.
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(cos_a, 0.0f, -sin_a, 0.0f);
    m[2] = glm::vec4(sin_a, 0.0f, cos_a, 0.0f);
    const glm::vec3 turned_c(cos_a * c.x + sin_a * c.z, c.y, -sin_a * c.x + cos_a * c.z);
    const glm::vec3 grid((float(k % side) - centre) * spacing, c.y, (float(k / side) - centre) * spacing);
    m[3] = glm::vec4(grid - turned_c, 1.0f);
    return m;
}

std::optional<CopiesSpec> parse_copies_spec(const std::string& source) {
    const std::size_t star = source.rfind('*');
    if (star == std::string::npos || star == 0 || star + 1 == source.size()) return std::nullopt;
    const std::string digits = source.substr(star + 1);
    if (digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    CopiesSpec spec{source.substr(0, star), 0};
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), spec.copies);
    if (ec != std::errc() || end != digits.data() + digits.size()) spec.copies = kMaxCopies + 1;  // too large
    return spec;
}

void make_copies(Scene& scene, std::uint64_t copies, const std::string& source) {
    if (copies == 0 || copies > kMaxCopies) {
        throw SceneError(cat(source, ": copies '*", copies > kMaxCopies ? "(too many)" : "0",
                             "' must be an integer from 1 to ", kMaxCopies));
    }
    const bool morphed = std::any_of(scene.objects.begin(), scene.objects.end(),
                                     [](const Object& o) { return o.morph.has_value(); });
    if (!scene.clips.empty() || !scene.skins.empty() || morphed) {
        throw SceneError(cat(source, ": copies of a scene with clips, skins or morph targets are not supported "
                                     "(its copies would move as one); add motions to the copies with --anim"));
    }
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const Object& object : scene.objects) {
        for (const glm::vec3& p : object.mesh.positions) {
            const glm::vec3 world(object.transform * glm::vec4(p, 1.0f));
            lo = glm::min(lo, world);
            hi = glm::max(hi, world);
        }
    }
    if (!(lo.x <= hi.x)) lo = hi = glm::vec3(0.0f);
    std::vector<Object> originals = std::move(scene.objects);
    scene.objects.clear();
    scene.objects.reserve(originals.size() * copies);
    for (std::uint64_t k = 0; k < copies; ++k) {
        const glm::mat4 place = copy_matrix(k, copies, lo, hi);
        for (const Object& object : originals) {
            Object copy = object;
            copy.name = cat(object.name, "[", k, "]");
            copy.transform = place * object.transform;
            copy.node = -1;
            scene.objects.push_back(std::move(copy));
        }
    }
    scene.source = source;
}

}  // namespace dynrt
