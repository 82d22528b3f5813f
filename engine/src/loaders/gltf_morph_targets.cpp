// glTF 2.0 section 3.7.2.2 "Morph Targets": every primitive of a mesh has the same number of
// targets; the default weights are the node's, else the mesh's, else zero.

#include "gltf_morph_targets.h"

#include "gltf_accessors.h"
#include "gltf_data_error.h"
#include "message_text.h"

#include <cmath>

namespace dynrt {

std::size_t gltf_morph_target_count(const tinygltf::Mesh& mesh) {
    const std::size_t count = mesh.primitives.empty() ? 0 : mesh.primitives.front().targets.size();
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
        if (mesh.primitives[k].targets.size() != count) {
            throw GltfDataError(cat("primitive ", k, " has ", mesh.primitives[k].targets.size(),
                                    " morph targets, primitive 0 has ", count, " (they must match)"));
        }
    }
    return count;
}

std::vector<glm::vec3> read_vec3_attribute(const tinygltf::Model& model, int accessor, std::size_t vertex_count,
                                           const std::string& what) {
    std::vector<double> numbers;
    try {
        numbers = read_numbers(model, accessor, TINYGLTF_TYPE_VEC3, NormalizedIntegers::any);
    } catch (const GltfDataError& e) {
        throw GltfDataError(cat(what, ": ", e.what()));
    }
    if (numbers.size() != 3 * vertex_count) {
        throw GltfDataError(cat(what, " has ", numbers.size() / 3, " elements for ", vertex_count, " positions"));
    }
    std::vector<glm::vec3> values(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        values[v] = glm::vec3(float(numbers[3 * v]), float(numbers[3 * v + 1]), float(numbers[3 * v + 2]));
    }
    return values;
}

std::optional<MorphTargets> read_morph_targets(const tinygltf::Model& model, const tinygltf::Node& node,
                                               const tinygltf::Mesh& mesh, const tinygltf::Primitive& primitive,
                                               const std::vector<glm::vec3>& base,
                                               const std::vector<glm::vec3>& base_normals) {
    const std::size_t count = gltf_morph_target_count(mesh);
    MorphTargets morph;
    bool moves_positions = false;
    for (std::size_t i = 0; i < count; ++i) {
        const auto position = primitive.targets[i].find("POSITION");
        if (position == primitive.targets[i].end()) {
            morph.position_deltas.emplace_back(base.size(), glm::vec3(0.0f));
            continue;
        }
        try {
            morph.position_deltas.push_back(read_positions(model, position->second));
        } catch (const GltfDataError& e) {
            throw GltfDataError(cat("morph target ", i, " POSITION: ", e.what()));
        }
        if (morph.position_deltas.back().size() != base.size()) {
            throw GltfDataError(cat("morph target ", i, " POSITION has ", morph.position_deltas.back().size(),
                                    " elements for ", base.size(), " positions"));
        }
        moves_positions = true;
    }
    const auto check_weights = [&](const std::vector<double>& weights, const char* owner) {
        if (weights.empty()) return;
        if (weights.size() != count) {
            throw GltfDataError(cat(owner, " weights has ", weights.size(), " numbers for ", count, " morph targets"));
        }
        for (const double w : weights) {
            if (!std::isfinite(w)) throw GltfDataError(cat(owner, " weights are not finite"));
        }
    };
    check_weights(mesh.weights, "mesh");
    check_weights(node.weights, "node");
    if (!moves_positions) return std::nullopt;
    morph.base_positions = base;
    // Normal displacements, when the mesh has normals and some target moves them.
    bool moves_normals = false;
    for (std::size_t i = 0; i < count && !base_normals.empty(); ++i) {
        moves_normals = moves_normals || primitive.targets[i].count("NORMAL") != 0;
    }
    if (moves_normals) {
        morph.base_normals = base_normals;
        for (std::size_t i = 0; i < count; ++i) {
            const auto normal = primitive.targets[i].find("NORMAL");
            if (normal == primitive.targets[i].end()) {
                morph.normal_deltas.emplace_back(base.size(), glm::vec3(0.0f));
                continue;
            }
            morph.normal_deltas.push_back(
                read_vec3_attribute(model, normal->second, base.size(), cat("morph target ", i, " NORMAL")));
        }
    }
    morph.default_weights = !node.weights.empty() ? node.weights
                            : !mesh.weights.empty() ? mesh.weights
                                                    : std::vector<double>(count, 0.0);
    return morph;
}

}  // namespace dynrt
