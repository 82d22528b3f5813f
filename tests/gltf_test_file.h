#pragma once
// Small glTF files written by the tests themselves: a JSON document whose accessors each get
// their own bufferView in one buffer, written as a .gltf with the buffer embedded as a base64
// data URI under testing::TempDir(). Used by the animation, skinning and morph tests.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace dynrt::test {

constexpr int kGltfByte = 5120, kGltfUnsignedByte = 5121, kGltfShort = 5122, kGltfUnsignedShort = 5123,
              kGltfUnsignedInt = 5125, kGltfFloat = 5126;

class GltfTestFile {
public:
    GltfTestFile() {
        doc_ = {{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", nlohmann::json::array({nlohmann::json{{"nodes", nlohmann::json::array()}}})},
                {"nodes", nlohmann::json::array()},
                {"meshes", nlohmann::json::array()},
                {"accessors", nlohmann::json::array()},
                {"bufferViews", nlohmann::json::array()}};
    }

    nlohmann::json& doc() { return doc_; }

    /// An accessor over `values` (each `Component` stored as `component_type`), of glTF type
    /// `type` ("SCALAR", "VEC3", "MAT4", ...), in a bufferView of its own.
    template <class Component>
    int add_accessor(const std::vector<Component>& values, const std::string& type, int component_type,
                     bool normalized = false) {
        while (bin_.size() % 4 != 0) bin_.push_back(0);
        const std::size_t bytes = values.size() * sizeof(Component);
        const int view = push("bufferViews", {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}});
        const auto* first = reinterpret_cast<const unsigned char*>(values.data());
        bin_.insert(bin_.end(), first, first + bytes);
        nlohmann::json accessor = {{"bufferView", view},
                                   {"componentType", component_type},
                                   {"count", values.size() / components(type)},
                                   {"type", type}};
        if (normalized) accessor["normalized"] = true;
        return push("accessors", accessor);
    }

    /// A FLOAT accessor.
    int add_floats(const std::vector<float>& values, const std::string& type) {
        return add_accessor(values, type, kGltfFloat);
    }

    /// A mesh with one triangle-list primitive over `positions` (FLOAT VEC3, 3 per vertex),
    /// non-indexed; `attributes` adds more (e.g. JOINTS_0), `targets` morph targets.
    int add_mesh(const std::vector<float>& positions, nlohmann::json attributes = nlohmann::json::object(),
                 nlohmann::json targets = nullptr, const std::string& name = "mesh") {
        attributes["POSITION"] = add_floats(positions, "VEC3");
        nlohmann::json primitive = {{"attributes", attributes}, {"mode", 4}};
        if (!targets.is_null()) primitive["targets"] = targets;
        return push("meshes", {{"name", name}, {"primitives", nlohmann::json::array({primitive})}});
    }

    /// A node; listed as a root of scene 0 unless `root` is false.
    int add_node(const nlohmann::json& node, bool root = true) {
        const int index = push("nodes", node);
        if (root) doc_["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    /// Makes `child` a child of `parent`.
    void add_child(int parent, int child) { doc_["nodes"][parent]["children"].push_back(child); }

    /// An animation with one sampler per channel: channels are {node, path, times, values,
    /// interpolation}.
    struct Channel {
        int node;
        std::string path;
        std::vector<float> times;
        std::vector<float> values;
        std::string interpolation = "LINEAR";
    };
    int add_animation(const std::string& name, const std::vector<Channel>& channels) {
        nlohmann::json animation = {{"samplers", nlohmann::json::array()}, {"channels", nlohmann::json::array()}};
        if (!name.empty()) animation["name"] = name;
        for (const Channel& c : channels) {
            const std::string type = c.path == "rotation" ? "VEC4" : c.path == "weights" ? "SCALAR" : "VEC3";
            const int input = add_floats(c.times, "SCALAR");
            const int output = add_floats(c.values, type);
            const int sampler = static_cast<int>(animation["samplers"].size());
            animation["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", c.interpolation}});
            animation["channels"].push_back({{"sampler", sampler}, {"target", {{"node", c.node}, {"path", c.path}}}});
        }
        return push("animations", animation);
    }

    /// Writes `<TempDir>/dynrt_<pid>_<name>` and returns its path.
    std::filesystem::path write(const std::string& name) const {
        nlohmann::json d = doc_;
        d["buffers"] = nlohmann::json::array(
            {{{"byteLength", bin_.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin_)}}});
        const std::filesystem::path path =
            std::filesystem::path(::testing::TempDir()) / ("dynrt_" + std::to_string(::getpid()) + "_" + name);
        std::ofstream(path) << d.dump(1);
        return path;
    }

    /// Standard base64 with padding (for data: URIs).
    static std::string base64(const std::vector<unsigned char>& bytes) {
        static const char* const alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        std::string out;
        for (std::size_t i = 0; i < bytes.size(); i += 3) {
            const std::uint32_t b0 = bytes[i], b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0,
                                b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
            const std::uint32_t triple = b0 << 16 | b1 << 8 | b2;
            out += alphabet[triple >> 18 & 63];
            out += alphabet[triple >> 12 & 63];
            out += i + 1 < bytes.size() ? alphabet[triple >> 6 & 63] : '=';
            out += i + 2 < bytes.size() ? alphabet[triple & 63] : '=';
        }
        return out;
    }

private:
    static std::size_t components(const std::string& type) {
        if (type == "SCALAR") return 1;
        if (type == "VEC2") return 2;
        if (type == "VEC3") return 3;
        if (type == "VEC4") return 4;
        return 16;
    }

    int push(const char* array, const nlohmann::json& value) {
        if (!doc_.contains(array)) doc_[array] = nlohmann::json::array();
        doc_[array].push_back(value);
        return static_cast<int>(doc_[array].size()) - 1;
    }

    nlohmann::json doc_;
    std::vector<unsigned char> bin_;
};

}  // namespace dynrt::test
