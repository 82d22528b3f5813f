#include "gltf_lights.h"

#include "gltf_data_error.h"
#include "message_text.h"

#include <cmath>
#include <numbers>

namespace dynrt {

namespace {

constexpr const char* kLightsPunctual = "KHR_lights_punctual";

}  // namespace

int node_light(const tinygltf::Node& node) {
    const auto found = node.extensions.find(kLightsPunctual);
    if (found == node.extensions.end() || !found->second.IsObject() || !found->second.Has("light")) return -1;
    const tinygltf::Value& index = found->second.Get("light");
    return index.IsInt() ? index.GetNumberAsInt() : -2;  // -2: present but not an index
}

std::vector<PointLight> read_lights(const tinygltf::Model& model, std::span<const GltfNodeInstance> instances) {
    std::vector<PointLight> lights;
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const int node = instances[i].node;
        const int index = node_light(model.nodes[static_cast<std::size_t>(node)]);
        if (index == -1) continue;
        const std::string node_name = gltf_node_name(model, node);
        if (index < 0 || static_cast<std::size_t>(index) >= model.lights.size()) {
            throw GltfDataError(cat("node '", node_name, "': light ", index, " does not exist (", model.lights.size(),
                                    " lights)"));
        }
        const tinygltf::Light& source = model.lights[static_cast<std::size_t>(index)];
        PointLight light;
        light.name = source.name.empty() ? node_name : source.name;
        light.node = static_cast<std::int32_t>(i);
        const auto bad = [&](const std::string& why) { throw GltfDataError(cat("light '", light.name, "': ", why)); };
        if (source.type == "point") {
            light.kind = PointLight::Kind::point;
        } else if (source.type == "spot") {
            light.kind = PointLight::Kind::spot;
        } else if (source.type == "directional") {
            light.kind = PointLight::Kind::directional;
        } else {
            bad(cat("type '", source.type, "' is not point, spot or directional"));
        }
        if (!(std::isfinite(source.intensity) && source.intensity >= 0.0)) bad("intensity must be finite and >= 0");
        light.intensity = static_cast<float>(source.intensity / std::numbers::pi);
        if (!source.color.empty()) {
            if (source.color.size() != 3) bad("color must have 3 components");
            for (int c = 0; c < 3; ++c) {
                const double value = source.color[std::size_t(c)];
                if (!(std::isfinite(value) && value >= 0.0)) bad("color components must be finite and >= 0");
                light.color[c] = static_cast<float>(value);
            }
        }
        if (light.kind != PointLight::Kind::directional) {
            light.inverse_square = true;
            if (source.range != 0.0) {
                if (!(std::isfinite(source.range) && source.range > 0.0)) bad("range must be finite and > 0");
                light.range = static_cast<float>(source.range);
            }
        }
        if (light.kind == PointLight::Kind::spot) {
            const double inner = source.spot.innerConeAngle, outer = source.spot.outerConeAngle;
            if (!(inner >= 0.0 && inner < outer && outer <= std::numbers::pi / 2.0)) {
                bad(cat("spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2 (inner ", inner,
                        ", outer ", outer, ")"));
            }
            light.inner_cone = static_cast<float>(inner);
            light.outer_cone = static_cast<float>(outer);
        }
        light.position = glm::vec3(0.0f);
        light.direction = glm::vec3(0.0f, 0.0f, -1.0f);
        lights.push_back(light);
    }
    return lights;
}

}  // namespace dynrt
