#include "gltf_cameras.h"

#include "gltf_data_error.h"
#include "message_text.h"

#include <cmath>
#include <numbers>

namespace dynrt {

std::vector<SceneCamera> read_cameras(const tinygltf::Model& model, std::span<const GltfNodeInstance> instances,
                                      std::vector<Warning>& warnings) {
    std::vector<SceneCamera> cameras;
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const int node = instances[i].node;
        const int index = model.nodes[static_cast<std::size_t>(node)].camera;
        if (index < 0) continue;
        const std::string node_name = gltf_node_name(model, node);
        if (static_cast<std::size_t>(index) >= model.cameras.size()) {
            throw GltfDataError(
                cat("node '", node_name, "': camera ", index, " does not exist (", model.cameras.size(), " cameras)"));
        }
        const tinygltf::Camera& source = model.cameras[static_cast<std::size_t>(index)];
        SceneCamera camera;
        camera.name = source.name.empty() ? node_name : source.name;
        camera.node = static_cast<std::uint32_t>(i);
        if (source.type != "perspective") {
            warnings.push_back({.kind = cat(source.type.empty() ? "untyped" : source.type, " camera skipped"),
                                .kinds = cat(source.type.empty() ? "untyped" : source.type, " cameras skipped"),
                                .item = cat("camera '", camera.name, "'"),
                                .effect = "only perspective cameras are used"});
            continue;
        }
        const double yfov = source.perspective.yfov, aspect = source.perspective.aspectRatio;
        if (!(std::isfinite(yfov) && yfov > 0.0 && yfov < std::numbers::pi)) {
            throw GltfDataError(cat("camera '", camera.name, "': yfov must be in (0, pi) radians"));
        }
        if (!(std::isfinite(aspect) && aspect >= 0.0)) {
            throw GltfDataError(cat("camera '", camera.name, "': aspectRatio must be finite and positive"));
        }
        camera.yfov_rad = yfov;
        camera.aspect_ratio = aspect;
        cameras.push_back(camera);
    }
    return cameras;
}

}  // namespace dynrt
