// `dynrt info`: a scene's objects, triangles and bounds, its cameras, lights, materials and
// textures (files that are not there marked MISSING), its frame rate and clips.

#include "frame_args.h"

#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/engine/scene_loading.h"

#include <glm/mat3x3.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

namespace dynrt::cli {

namespace {

std::ostream& operator<<(std::ostream& out, const glm::vec3& v) {
    // + 0.0f: a -0 prints as 0.
    return out << "[" << v.x + 0.0f << ", " << v.y + 0.0f << ", " << v.z + 0.0f << "]";
}

/// `radians` in degrees with one decimal.
std::string degrees_text(double radians) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", radians * 180.0 / M_PI);
    return text;
}

/// Cameras with where they are at frame 0 (`posed`'s node matrices) and their field of view.
void print_cameras(const dynrt::Scene& scene, const dynrt::anim::PosedScene& posed) {
    std::cout << "cameras: " << scene.cameras.size() << (scene.cameras.empty() ? "" : " (the first is the scene's)")
              << "\n";
    for (std::size_t i = 0; i < scene.cameras.size(); ++i) {
        const dynrt::SceneCamera& camera = scene.cameras[i];
        const glm::dmat4& world = posed.node_world[camera.node];
        const glm::vec3 eye(world[3]);
        const glm::vec3 forward(-glm::normalize(glm::dvec3(world[2])));
        std::cout << "  " << std::left << std::setw(5) << i << "  " << std::setw(32) << camera.name << std::right
                  << "  at " << eye << " looking " << forward << ", yfov " << degrees_text(camera.yfov_rad)
                  << " deg";
        if (camera.aspect_ratio > 0.0) std::cout << ", aspect " << camera.aspect_ratio;
        std::cout << "\n";
    }
}

/// Lights with where they are at frame 0 (`posed`'s node matrices, for lights on a node).
void print_lights(const dynrt::Scene& scene, const dynrt::anim::PosedScene& posed) {
    std::cout << "lights: " << scene.lights.size()
              << (scene.lights.empty() ? " (the renderer's default light is used)" : "") << "\n";
    using Kind = dynrt::PointLight::Kind;
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
        const dynrt::PointLight& light = scene.lights[i];
        std::cout << "  " << std::left << std::setw(5) << i << "  " << std::setw(32) << light.name << std::right << "  ";
        const glm::dmat4 world = light.node >= 0 ? posed.node_world[std::size_t(light.node)] : glm::dmat4(1.0);
        const glm::vec3 at(world * glm::dvec4(glm::dvec3(light.position), 1.0));
        const glm::vec3 along(glm::normalize(glm::dmat3(world) * glm::dvec3(light.direction)));
        if (light.kind == Kind::directional) {
            std::cout << "directional along " << along;
        } else {
            std::cout << (light.kind == Kind::spot ? "spot at " : "point at ") << at;
            if (light.kind == Kind::spot) {
                std::cout << " along " << along << ", cone " << degrees_text(light.inner_cone) << "-"
                          << degrees_text(light.outer_cone) << " deg";
            }
        }
        std::cout << ", intensity " << light.intensity;
        if (light.color != glm::vec3(1.0f)) std::cout << ", colour " << light.color;
        if (light.inverse_square) std::cout << ", inverse-square falloff";
        if (light.range > 0.0f) std::cout << ", range " << light.range;
        if (light.node >= 0) std::cout << ", on node '" << scene.nodes[std::size_t(light.node)].name << "'";
        std::cout << "\n";
    }
}

void print_materials(const dynrt::Scene& scene) {
    std::cout << "materials: " << scene.materials.size() << " (0 is dynrt's default)\n";
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const dynrt::Material& m = scene.materials[i];
        std::cout << "  " << std::left << std::setw(5) << i << "  " << std::setw(32) << m.name << std::right
                  << "  diffuse " << m.diffuse;
        if (m.diffuse_map) std::cout << " x texture " << m.diffuse_map->texture;
        if (m.traces_secondary()) {
            std::cout << ", reflectance " << m.reflectance << ", transmittance " << m.transmittance << ", ior " << m.ior;
        }
        if (m.emission != glm::vec3(0.0f)) {
            std::cout << ", emission " << m.emission;
            if (m.emission_map) std::cout << " x texture " << m.emission_map->texture;
        }
        if (m.alpha_cutoff) std::cout << ", cut out where alpha " << m.base_alpha << (m.diffuse_map ? " x texture's" : "") << " < " << *m.alpha_cutoff;
        std::cout << "\n";
    }
}

/// Textures, a file that does not exist marked MISSING (the renderer then uses the diffuse
/// colour alone).
void print_textures(const dynrt::Scene& scene) {
    std::cout << "textures: " << scene.textures.size() << "\n";
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const dynrt::Texture& texture = scene.textures[i];
        std::cout << "  " << std::left << std::setw(5) << i << std::right << "  " << texture.name;
        if (texture.path.empty()) {
            std::cout << " (embedded, " << texture.encoded.size() << " bytes)";
        } else {
            std::error_code ec;
            if (!std::filesystem::is_regular_file(texture.path, ec)) std::cout << "  MISSING";
        }
        std::cout << "\n";
    }
}

}  // namespace

int run_info(const std::string& source) {
    const dynrt::Scene scene = load_scene_with_progress(source);
    dynrt::anim::PosedScene posed;
    dynrt::anim::pose_scene(scene, 0, posed);
    std::cout << source << "\n";
    std::cout << std::left << std::setw(40) << "object" << std::right << std::setw(12)
              << "triangles" << std::setw(12) << "degenerate" << "  bounds (frame 0)\n";
    dynrt::bvh::Aabb all;
    std::size_t degenerate_total = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const dynrt::Object& object = scene.objects[i];
        const std::vector<glm::vec3>& p = posed.objects[i].positions;
        dynrt::bvh::Aabb bounds;
        std::size_t degenerate = 0;
        for (const glm::uvec3& t : object.mesh.triangles) {
            const dynrt::bvh::Triangle tri{p[t.x], p[t.y], p[t.z]};
            degenerate += dynrt::bvh::is_degenerate(tri);
            bounds.extend(tri.bounds());
        }
        all.extend(bounds);
        degenerate_total += degenerate;
        std::cout << std::left << std::setw(40) << object.name << std::right << std::setw(12)
                  << object.mesh.triangles.size() << std::setw(12) << degenerate << "  ["
                  << bounds.lo.x << ", " << bounds.lo.y << ", " << bounds.lo.z << "] - ["
                  << bounds.hi.x << ", " << bounds.hi.y << ", " << bounds.hi.z << "]\n";
    }
    std::cout << std::left << std::setw(40) << "total" << std::right << std::setw(12)
              << scene.triangle_count() << std::setw(12) << degenerate_total << "  ["
              << all.lo.x << ", " << all.lo.y << ", " << all.lo.z << "] - [" << all.hi.x << ", "
              << all.hi.y << ", " << all.hi.z << "]\n"
              << scene.objects.size() << " objects, " << scene.materials.size()
              << " materials, " << scene.lights.size() << " lights\n";
    print_cameras(scene, posed);
    print_lights(scene, posed);
    print_materials(scene);
    print_textures(scene);
    // The timeline: frame rate and clips, as render and bench would play them.
    const double fps = scene.setup ? scene.setup->fps : dynrt::anim::kDefaultFps;
    std::cout << "frame rate: " << fps << " fps ("
              << (scene.setup ? "the file's" : "dynrt's default; the file gives none")
              << "; --fps changes it)\n";
    if (scene.setup) {
        std::cout << "sequence: frames 0-" << scene.setup->frame_count - 1 << " (the file's)\n";
    }
    if (scene.clips.empty()) {
        std::cout << "clips: none\n";
        return 0;
    }
    const std::vector<std::size_t> plays = dynrt::anim::default_clips(scene);
    std::cout << "clips: " << scene.clips.size();
    if (scene.clips.size() > 1) {
        std::cout << (plays.size() == 1 ? " (by default only the first plays: they animate the same nodes"
                                        : " (by default all play together: they animate different nodes")
                  << "; --clip NAME or index picks)";
    }
    std::cout << "\n" << std::left << std::setw(7) << "  index" << "  " << std::setw(32) << "name"
              << std::right << std::setw(10) << "start s" << std::setw(10) << "end s"
              << std::setw(12) << "duration s" << "  frames at " << fps << " fps\n";
    for (std::size_t i = 0; i < scene.clips.size(); ++i) {
        const dynrt::AnimationClip& clip = scene.clips[i];
        std::cout << "  " << std::left << std::setw(5) << i << "  " << std::setw(32) << clip.name
                  << std::right << std::fixed << std::setprecision(3) << std::setw(10)
                  << clip.start_time() << std::setw(10) << clip.end_time() << std::setw(12)
                  << clip.end_time() - clip.start_time() << "  "
                  << int(std::floor(clip.start_time() * fps)) << "-"
                  << int(std::ceil(clip.end_time() * fps)) << "\n"
                  << std::defaultfloat;
    }
    return 0;
}

}  // namespace dynrt::cli
