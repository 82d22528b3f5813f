// The invariants every later stage may rely on without checking again: triangles exist, indices
// are in range, positions, normals and texture coordinates (none, or one per vertex) and
// transforms are finite, material indices and their texture indices are valid, and every
// material's Whitted terms are usable (reflectance and transmittance finite and >= 0, ior finite
// and > 0: the refraction maths divides by it), and so is its emission (finite and >= 0), and
// its alpha (cutoff and base alpha in [0, 1]).

#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include "message_text.h"

#include <array>
#include <cmath>
#include <set>
#include <sstream>

namespace dynrt {

namespace {

[[noreturn]] void fail(const Scene& scene, const Object* object, const std::string& what) {
    if (object == nullptr) throw SceneError(cat(scene.source, ": ", what));
    throw SceneError(cat(scene.source, ": object '", object->name, "': ", what));
}

bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string to_text(const glm::vec3& v) {
    std::ostringstream out;
    out << '(' << v.x << ", " << v.y << ", " << v.z << ')';
    return out.str();
}

bool is_finite_non_negative(const glm::vec3& v) {
    return is_finite(v) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f;
}

/// What is wrong with material `index`'s secondary-ray terms, or "" when nothing is.
std::string material_problem(const Material& material, std::size_t index) {
    const std::string which = cat("material '", material.name, "' (index ", index, "): ");
    if (!is_finite_non_negative(material.reflectance)) {
        return cat(which, "reflectance ", to_text(material.reflectance), " must be finite and >= 0");
    }
    if (!is_finite_non_negative(material.transmittance)) {
        return cat(which, "transmittance ", to_text(material.transmittance), " must be finite and >= 0");
    }
    if (!std::isfinite(material.ior) || !(material.ior > 0.0f)) {
        return cat(which, "ior ", material.ior, " must be finite and > 0");
    }
    if (!is_finite_non_negative(material.emission)) {
        return cat(which, "emission ", to_text(material.emission), " must be finite and >= 0");
    }
    if (material.ambient && !is_finite_non_negative(*material.ambient)) {
        return cat(which, "ambient ", to_text(*material.ambient), " must be finite and >= 0");
    }
    if (material.alpha_cutoff && !(*material.alpha_cutoff >= 0.0f && *material.alpha_cutoff <= 1.0f)) {
        return cat(which, "alpha cutoff ", *material.alpha_cutoff, " must be in [0, 1]");
    }
    if (!(material.base_alpha >= 0.0f && material.base_alpha <= 1.0f)) {
        return cat(which, "base alpha ", material.base_alpha, " must be in [0, 1]");
    }
    return {};
}

/// What is wrong with material `index`'s texture map in `scene`, or "" when nothing is.
std::string texture_problem(const Scene& scene, const Material& material, std::size_t index) {
    for (const std::optional<TextureMap>& map : {material.diffuse_map, material.emission_map}) {
        if (!map || map->texture < scene.textures.size()) continue;
        return cat("material '", material.name, "' (index ", index, "): texture ", map->texture, " out of range (",
                   scene.textures.size(), " textures)");
    }
    return {};
}

void check_object(const Scene& scene, const Object& object) {
    if (object.material >= scene.materials.size()) {
        fail(scene, &object,
             cat("material index ", object.material, " out of range (", scene.materials.size(),
                 " materials)"));
    }
    if (const std::string problem = material_problem(scene.materials[object.material], object.material);
        !problem.empty()) {
        fail(scene, &object, problem);
    }
    for (int column = 0; column < 4; ++column) {
        const glm::vec4& c = object.transform[column];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) {
            fail(scene, &object, "transform is not finite");
        }
    }
}

/// The object's mesh: finite vertices, normals and texture coordinates, one per vertex, and
/// corners that index them.
void check_mesh(const Scene& scene, const Object& object) {
    const std::vector<glm::vec3>& positions = object.mesh.positions;
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (!is_finite(positions[v])) {
            fail(scene, &object, cat("vertex ", v, " position ", to_text(positions[v]), " is not finite"));
        }
    }
    const std::vector<glm::vec3>& normals = object.mesh.normals;
    if (!normals.empty() && normals.size() != positions.size()) {
        fail(scene, &object, cat(normals.size(), " normals for ", positions.size(), " vertices"));
    }
    for (std::size_t v = 0; v < normals.size(); ++v) {
        if (!is_finite(normals[v])) {
            fail(scene, &object, cat("vertex ", v, " normal ", to_text(normals[v]), " is not finite"));
        }
    }
    const std::vector<glm::vec2>& texcoords = object.mesh.texcoords;
    if (!texcoords.empty() && texcoords.size() != positions.size()) {
        fail(scene, &object, cat(texcoords.size(), " texture coordinates for ", positions.size(), " vertices"));
    }
    for (std::size_t v = 0; v < texcoords.size(); ++v) {
        if (!std::isfinite(texcoords[v].x) || !std::isfinite(texcoords[v].y)) {
            fail(scene, &object, cat("vertex ", v, " texture coordinates are not finite"));
        }
    }
    const std::vector<glm::uvec3>& triangles = object.mesh.triangles;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        for (int corner = 0; corner < 3; ++corner) {
            if (triangles[t][corner] >= positions.size()) {
                fail(scene, &object,
                     cat("triangle ", t, " index ", triangles[t][corner], " out of range (", positions.size(),
                         " vertices)"));
            }
        }
    }
}

}  // namespace

void check_scene(const Scene& scene) {
    if (scene.materials.empty()) fail(scene, nullptr, "scene has no materials");
    // Copies of one mesh (shared arrays) are checked once: the first copy names the problem.
    std::set<std::array<const void*, 4>> meshes_checked;
    for (const Object& object : scene.objects) {
        check_object(scene, object);
        const Mesh& m = object.mesh;
        const std::array<const void*, 4> arrays{m.positions.data(), m.normals.data(), m.texcoords.data(),
                                                m.triangles.data()};
        if (m.positions.holders() > 1 && !meshes_checked.insert(arrays).second) continue;
        check_mesh(scene, object);
    }
    // Materials no object uses yet (a caller may assign them later): named without an object.
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        if (const std::string problem = material_problem(scene.materials[m], m); !problem.empty()) {
            fail(scene, nullptr, problem);
        }
        if (const std::string problem = texture_problem(scene, scene.materials[m], m); !problem.empty()) {
            fail(scene, nullptr, problem);
        }
    }
    if (scene.triangle_count() == 0) fail(scene, nullptr, "scene has no triangles");
}

}  // namespace dynrt
