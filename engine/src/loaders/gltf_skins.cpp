// glTF 2.0 section 3.7.3 "Skins": joints, inverse bind matrices and the JOINTS_n/WEIGHTS_n
// vertex attributes, each validated before the scene model holds it.

#include "gltf_skins.h"

#include "gltf_accessors.h"
#include "gltf_data_error.h"
#include "gltf_names.h"
#include "gltf_node_tree.h"
#include "message_text.h"

namespace dynrt {

namespace {

constexpr std::size_t kInfluencesPerSet = 4;

}  // namespace

GltfSkins::GltfSkins(const tinygltf::Model& model, std::span<const int> scene_node_of)
    : model_(model), scene_node_of_(scene_node_of), converted_(model.skins.size(), -1) {}

std::uint32_t GltfSkins::use(int index, std::vector<Skin>& skins) {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.skins.size()) {
        throw GltfDataError(cat("skin ", index, " does not exist (", model_.skins.size(), " skins)"));
    }
    int& converted = converted_[static_cast<std::size_t>(index)];
    if (converted >= 0) return static_cast<std::uint32_t>(converted);

    const tinygltf::Skin& source = model_.skins[static_cast<std::size_t>(index)];
    Skin skin;
    skin.name = gltf_element_name(model_.skins, index, "skin");
    const auto fail = [&](const std::string& what) { throw GltfDataError(cat("skin '", skin.name, "': ", what)); };
    if (source.joints.empty()) fail("has no joints");
    std::vector<bool> listed(scene_node_of_.size(), false);
    for (std::size_t j = 0; j < source.joints.size(); ++j) {
        const int node = source.joints[j];
        if (node < 0 || static_cast<std::size_t>(node) >= scene_node_of_.size()) {
            fail(cat("joint ", j, " is node ", node, ", which does not exist (", scene_node_of_.size(), " nodes)"));
        }
        if (listed[static_cast<std::size_t>(node)]) {
            fail(cat("joint ", j, " (node '", gltf_node_name(model_, node), "') is listed twice"));
        }
        listed[static_cast<std::size_t>(node)] = true;
        const int scene_node = scene_node_of_[static_cast<std::size_t>(node)];
        if (scene_node < 0) {
            fail(cat("joint ", j, " is node '", gltf_node_name(model_, node), "', which is not in the default scene"));
        }
        skin.joints.push_back(static_cast<std::uint32_t>(scene_node));
    }
    skin.inverse_bind_matrices.assign(skin.joints.size(), glm::dmat4(1.0));
    if (source.inverseBindMatrices >= 0) {
        std::vector<double> numbers;
        try {
            numbers = read_numbers(model_, source.inverseBindMatrices, TINYGLTF_TYPE_MAT4, NormalizedIntegers::none);
        } catch (const GltfDataError& e) {
            fail(cat("inverseBindMatrices: ", e.what()));
        }
        if (numbers.size() < 16 * skin.joints.size()) {
            fail(cat("inverseBindMatrices has ", numbers.size() / 16, " matrices for ", skin.joints.size(), " joints"));
        }
        for (std::size_t j = 0; j < skin.joints.size(); ++j) {
            for (int column = 0; column < 4; ++column) {
                for (int row = 0; row < 4; ++row) {
                    skin.inverse_bind_matrices[j][column][row] = numbers[16 * j + 4 * column + row];
                }
            }
        }
    }
    converted = static_cast<int>(skins.size());
    skins.push_back(std::move(skin));
    return static_cast<std::uint32_t>(converted);
}

SkinWeights GltfSkins::read_weights(const tinygltf::Primitive& primitive, std::uint32_t scene_skin,
                                    const std::vector<Skin>& skins, std::size_t vertex_count) const {
    const std::size_t joint_count = skins[scene_skin].joints.size();
    const auto attribute = [&](const std::string& name) {
        const auto found = primitive.attributes.find(name);
        return found == primitive.attributes.end() ? -1 : found->second;
    };
    const std::size_t sets = attribute("JOINTS_1") >= 0 || attribute("WEIGHTS_1") >= 0 ? 2 : 1;
    SkinWeights weights;
    weights.skin = scene_skin;
    weights.influences = static_cast<std::uint32_t>(sets * kInfluencesPerSet);
    weights.joints.resize(vertex_count * weights.influences);
    weights.weights.resize(vertex_count * weights.influences);
    for (std::size_t set = 0; set < sets; ++set) {
        const std::string joints_name = cat("JOINTS_", set), weights_name = cat("WEIGHTS_", set);
        const int joints_accessor = attribute(joints_name), weights_accessor = attribute(weights_name);
        if (joints_accessor < 0 || weights_accessor < 0) {
            throw GltfDataError(cat("skinned primitive needs both ", joints_name, " and ", weights_name));
        }
        std::vector<std::uint16_t> joints;
        std::vector<double> values;
        try {
            joints = read_joint_indices(model_, joints_accessor);
        } catch (const GltfDataError& e) {
            throw GltfDataError(cat(joints_name, ": ", e.what()));
        }
        try {
            values = read_numbers(model_, weights_accessor, TINYGLTF_TYPE_VEC4, NormalizedIntegers::unsigned_only);
        } catch (const GltfDataError& e) {
            throw GltfDataError(cat(weights_name, ": ", e.what()));
        }
        if (joints.size() != 4 * vertex_count || values.size() != 4 * vertex_count) {
            throw GltfDataError(cat(joints_name, " has ", joints.size() / 4, " and ", weights_name, " ",
                                    values.size() / 4, " elements for ", vertex_count, " positions"));
        }
        for (std::size_t v = 0; v < vertex_count; ++v) {
            for (std::size_t c = 0; c < kInfluencesPerSet; ++c) {
                const std::uint16_t joint = joints[4 * v + c];
                const double weight = values[4 * v + c];
                if (joint >= joint_count) {
                    throw GltfDataError(cat(joints_name, " vertex ", v, ": joint ", joint, " out of range of the skin's ",
                                            joint_count, " joints"));
                }
                if (weight < 0.0) throw GltfDataError(cat(weights_name, " vertex ", v, ": negative weight"));
                const std::size_t slot = v * weights.influences + set * kInfluencesPerSet + c;
                weights.joints[slot] = joint;
                weights.weights[slot] = static_cast<float>(weight);
            }
        }
    }
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const auto first = weights.weights.begin() + static_cast<std::ptrdiff_t>(v * weights.influences);
        double sum = 0.0;
        for (auto w = first; w != first + weights.influences; ++w) sum += *w;
        if (!(sum > 0.0)) throw GltfDataError(cat("skin weights of vertex ", v, " are all zero"));
    }
    return weights;
}

}  // namespace dynrt
