#include "rendering/level_of_detail.h"

#include "update/held_bytes.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace dynrt {

namespace {

/// At least the largest factor by which `transform` stretches any length (its largest singular
/// value), and exactly that for glTF's translate-rotate-scale matrices: the square root of the
/// largest row sum of |M^T M|, whose rows are the columns' dot products (any induced norm of a
/// matrix bounds its largest eigenvalue; for orthogonal columns M^T M is diagonal).
double largest_stretch(const glm::dmat4& transform) {
    const glm::dmat3 m(transform);
    double largest = 0.0;
    for (int i = 0; i < 3; ++i) {
        double row = 0.0;
        for (int j = 0; j < 3; ++j) row += std::abs(glm::dot(m[i], m[j]));
        largest = std::max(largest, row);
    }
    return std::sqrt(largest);
}

}  // namespace

const LevelOfDetail::MeshLevels* LevelOfDetail::levels_of(const Mesh& mesh) {
    const glm::uvec3* key = mesh.triangles.data();
    if (!key) return nullptr;
    auto found = meshes_.find(key);
    if (found == meshes_.end()) {
        auto made = std::make_unique<MeshLevels>();
        made->levels = simplified_levels(mesh);
        if (!made->levels.empty()) {
            glm::vec3 lo(mesh.positions[0]), hi(mesh.positions[0]);
            for (const glm::vec3& p : mesh.positions) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            made->centre = 0.5f * (lo + hi);
            made->radius = 0.5f * glm::length(hi - lo);
        }
        found = meshes_.emplace(key, std::move(made)).first;
    }
    return found->second->levels.empty() ? nullptr : found->second.get();
}

const Scene& LevelOfDetail::choose(const Scene& scene, std::span<ObjectState> states, const Camera* camera,
                                   int height, float max_pixels, std::vector<std::size_t>& changed) {
    changed.clear();
    if (source_ != &scene || scene_.objects.size() != scene.objects.size()) {
        reset();
        scene_ = scene;
        // Only the poser reads the animation, from the scene itself: the copy lets it go.
        scene_.nodes = {};
        scene_.skins = {};
        scene_.clips = {};
        source_ = &scene;
        chosen_.assign(scene.objects.size(), 0);
    }
    // A world length L at distance d covers L / (d * pixel_angle) pixels, the pixel's angle
    // being the field of view's height over the image's.
    const double pixel_angle =
        2.0 * std::tan(0.5 * double(camera ? camera->fov_y_deg : 0.0f) * 3.14159265358979323846 / 180.0) /
        double(std::max(height, 1));
    for (std::size_t i = 0; i < scene.objects.size() && i < states.size(); ++i) {
        const Object& object = scene.objects[i];
        ObjectState& state = states[i];
        const bool fixed_shape = (state.motion_class == anim::MotionClass::static_ ||
                                  state.motion_class == anim::MotionClass::rigid) &&
                                 !object.skin && !object.morph;
        const MeshLevels* mesh = fixed_shape ? levels_of(object.mesh) : nullptr;
        std::size_t level = 0;
        if (mesh) {
            state.motion_class = anim::MotionClass::rigid;
            level = chosen_[i];
            if (camera) {
                const glm::dvec3 centre = glm::dvec3(state.transform * glm::dvec4(glm::dvec3(mesh->centre), 1.0));
                const double stretch = largest_stretch(state.transform);
                const double distance =
                    glm::length(centre - glm::dvec3(camera->eye)) - stretch * double(mesh->radius);
                level = 0;
                // Inside the bounding sphere (or on it) the mesh itself is traced.
                if (distance > 0.0 && pixel_angle > 0.0) {
                    const double pixels_per_unit = stretch / (distance * pixel_angle);
                    for (std::size_t k = mesh->levels.size(); k > 0; --k) {
                        if (double(mesh->levels[k - 1].error) * pixels_per_unit <= double(max_pixels)) {
                            level = k;
                            break;
                        }
                    }
                }
            }
        }
        if (level == chosen_[i]) continue;
        chosen_[i] = level;
        scene_.objects[i].mesh.triangles = level == 0 ? object.mesh.triangles : mesh->levels[level - 1].triangles;
        changed.push_back(i);
    }
    return scene_;
}

void LevelOfDetail::reset() {
    source_ = nullptr;
    scene_ = Scene{};
    meshes_.clear();
    chosen_.clear();
}

std::size_t LevelOfDetail::memory_bytes() const {
    std::size_t bytes = held_bytes(chosen_);
    for (const auto& [key, mesh] : meshes_) {
        for (const SimplifiedLevel& level : mesh->levels) bytes += level.triangles.size() * sizeof(glm::uvec3);
    }
    return bytes;
}

}  // namespace dynrt
