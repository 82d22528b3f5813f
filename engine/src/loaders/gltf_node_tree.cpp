// glTF 2.0 section 3.5.2 "Transformations": a node's local matrix is its `matrix` or T * R * S,
// and its world matrix is the product of the local matrices from the root down.

#include "gltf_node_tree.h"

#include "gltf_data_error.h"
#include "gltf_names.h"
#include "message_text.h"

#include <cmath>
#include <utility>

namespace dynrt {

namespace {

[[noreturn]] void fail_node(const tinygltf::Model& model, int index, const std::string& what) {
    throw GltfDataError(cat("node '", gltf_node_name(model, index), "': ", what));
}

bool all_finite(const std::vector<double>& values) {
    for (const double v : values) {
        if (!std::isfinite(v)) return false;
    }
    return true;
}

void check_length(const std::vector<double>& values, std::size_t expected, const char* what) {
    if (!values.empty() && values.size() != expected) {
        throw GltfDataError(cat(what, " has ", values.size(), " numbers, not ", expected));
    }
    if (!all_finite(values)) throw GltfDataError(cat(what, " is not finite"));
}

}  // namespace

std::string gltf_node_name(const tinygltf::Model& model, int index) {
    return gltf_element_name(model.nodes, index, "node");
}

glm::dmat4 gltf_local_matrix(const tinygltf::Node& node) { return gltf_scene_node(node).rest_local(); }

Node gltf_scene_node(const tinygltf::Node& node) {
    check_length(node.matrix, 16, "matrix");
    check_length(node.translation, 3, "translation");
    check_length(node.rotation, 4, "rotation");
    check_length(node.scale, 3, "scale");

    Node result;
    if (!node.matrix.empty()) {
        // glTF stores matrices column-major, as glm does.
        glm::dmat4 matrix(1.0);
        for (int column = 0; column < 4; ++column) {
            for (int row = 0; row < 4; ++row) matrix[column][row] = node.matrix[4 * column + row];
        }
        result.matrix = matrix;
        return result;
    }
    if (!node.translation.empty()) {
        result.translation = glm::dvec3(node.translation[0], node.translation[1], node.translation[2]);
    }
    if (!node.rotation.empty()) {
        const glm::dvec4 q(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]);
        const double length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        if (!(length > 0.0)) throw GltfDataError("rotation quaternion has zero length");
        result.rotation = q;  // trs_matrix normalises it
    }
    if (!node.scale.empty()) result.scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
    return result;
}

std::vector<GltfNodeInstance> flatten_node_tree(const tinygltf::Model& model) {
    const int node_count = static_cast<int>(model.nodes.size());
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (static_cast<std::size_t>(scene) >= model.scenes.size()) {
            throw GltfDataError(
                cat("default scene ", scene, " does not exist (", model.scenes.size(), " scenes)"));
        }
        roots = model.scenes[static_cast<std::size_t>(scene)].nodes;
    } else {
        std::vector<bool> is_child(model.nodes.size(), false);
        for (const tinygltf::Node& node : model.nodes) {
            for (const int child : node.children) {
                if (child >= 0 && child < node_count) is_child[static_cast<std::size_t>(child)] = true;
            }
        }
        for (int i = 0; i < node_count; ++i) {
            if (!is_child[static_cast<std::size_t>(i)]) roots.push_back(i);
        }
    }

    std::vector<GltfNodeInstance> instances;
    std::vector<bool> reached(model.nodes.size(), false);
    // Explicit stack of (node, parent instance): deep trees from untrusted files must not
    // overflow the call stack. Pushing in reverse keeps the file's child order.
    std::vector<std::pair<int, int>> pending;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root) pending.emplace_back(*root, -1);
    while (!pending.empty()) {
        const auto [index, parent] = pending.back();
        pending.pop_back();
        if (index < 0 || index >= node_count) {
            std::string owner = "the scene";
            if (parent >= 0) {
                const int parent_node = instances[static_cast<std::size_t>(parent)].node;
                owner = cat("node '", gltf_node_name(model, parent_node), "'");
            }
            throw GltfDataError(
                cat(owner, " refers to node ", index, ", which does not exist (", node_count, " nodes)"));
        }
        if (reached[static_cast<std::size_t>(index)]) {
            fail_node(model, index, "reached twice (the node hierarchy must be a tree without cycles)");
        }
        reached[static_cast<std::size_t>(index)] = true;

        const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(index)];
        GltfNodeInstance instance;
        instance.node = index;
        instance.parent = parent;
        try {
            instance.local = gltf_local_matrix(node);
        } catch (const GltfDataError& e) {
            fail_node(model, index, e.what());
        }
        instance.world =
            parent < 0 ? instance.local : instances[static_cast<std::size_t>(parent)].world * instance.local;
        const int self = static_cast<int>(instances.size());
        instances.push_back(instance);
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
            pending.emplace_back(*child, self);
        }
    }
    return instances;
}

}  // namespace dynrt
