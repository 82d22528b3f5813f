// glTF loading: small files written by the test itself (good ones for every index type,
// topology, node transform kind and container, bad ones for every error the loader promises to
// name), the bundled default scene, and every glTF under the shared scenes folder.

#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <span>
#include <string>
#include <unistd.h>
#include <vector>

namespace dynrt {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kPoints = 0, kLines = 1, kTriangles = 4, kStrip = 5, kFan = 6;

/// Builds a glTF document and its binary buffer, then writes it as .gltf + .bin or as .glb.
class GltfBuilder {
public:
    GltfBuilder() {
        doc_ = {{"asset", {{"version", "2.0"}}},
                {"scenes", json::array({json{{"nodes", json::array()}}})},
                {"scene", 0},
                {"nodes", json::array()},
                {"meshes", json::array()},
                {"accessors", json::array()},
                {"bufferViews", json::array()}};
    }

    json& doc() { return doc_; }
    std::vector<unsigned char>& bin() { return bin_; }

    int add_view(const void* data, std::size_t bytes, std::size_t stride = 0) {
        while (bin_.size() % 4 != 0) bin_.push_back(0);
        json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
        if (stride != 0) view["byteStride"] = stride;
        const auto* first = static_cast<const unsigned char*>(data);
        bin_.insert(bin_.end(), first, first + bytes);
        return push("bufferViews", view);
    }

    int add_accessor(int view, int component_type, std::size_t count, const std::string& type,
                     std::size_t byte_offset = 0) {
        json accessor = {
            {"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}};
        if (byte_offset != 0) accessor["byteOffset"] = byte_offset;
        return push("accessors", accessor);
    }

    int add_positions(const std::vector<glm::vec3>& points) {
        const int view = add_view(points.data(), points.size() * sizeof(glm::vec3));
        return add_accessor(view, kFloat, points.size(), "VEC3");
    }

    template <class Index>
    int add_indices(const std::vector<Index>& indices, int component_type) {
        const int view = add_view(indices.data(), indices.size() * sizeof(Index));
        return add_accessor(view, component_type, indices.size(), "SCALAR");
    }

    static json primitive(int positions, int indices = -1, int mode = kTriangles, int material = -1) {
        json p = {{"attributes", {{"POSITION", positions}}}, {"mode", mode}};
        if (indices >= 0) p["indices"] = indices;
        if (material >= 0) p["material"] = material;
        return p;
    }

    int add_mesh(const std::string& name, const json& primitives) {
        json mesh = {{"primitives", primitives}};
        if (!name.empty()) mesh["name"] = name;
        return push("meshes", mesh);
    }

    /// Adds a node; a root (listed in scene 0) unless `root` is false.
    int add_node(json node, bool root = true) {
        const int index = push("nodes", node);
        if (root) doc_["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    int add_material(const std::string& name, const glm::vec3& rgb) {
        if (!doc_.contains("materials")) doc_["materials"] = json::array();
        return push(
            "materials",
            {{"name", name}, {"pbrMetallicRoughness", {{"baseColorFactor", {rgb.x, rgb.y, rgb.z, 1.0}}}}});
    }

    /// Writes `path` (.gltf) and, next to it, `<stem>.bin`.
    void write_gltf(const fs::path& path) {
        const std::string bin_name = path.stem().string() + ".bin";
        json d = doc_;
        if (!bin_.empty()) d["buffers"] = json::array({json{{"uri", bin_name}, {"byteLength", bin_.size()}}});
        std::ofstream(path) << d.dump(1);
        std::ofstream(path.parent_path() / bin_name, std::ios::binary)
            .write(reinterpret_cast<const char*>(bin_.data()), static_cast<std::streamsize>(bin_.size()));
    }

    /// The GLB container bytes: header, JSON chunk (space-padded), BIN chunk (zero-padded).
    std::vector<unsigned char> glb_bytes() const {
        std::vector<unsigned char> bin = bin_;
        while (bin.size() % 4 != 0) bin.push_back(0);
        json d = doc_;
        d["buffers"] = json::array({json{{"byteLength", bin_.size()}}});
        std::string text = d.dump();
        while (text.size() % 4 != 0) text.push_back(' ');
        std::vector<unsigned char> out;
        const auto u32 = [&](std::uint32_t v) {
            for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
        };
        u32(0x46546C67);
        u32(2);
        u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
        u32(static_cast<std::uint32_t>(text.size()));
        u32(0x4E4F534A);
        out.insert(out.end(), text.begin(), text.end());
        u32(static_cast<std::uint32_t>(bin.size()));
        u32(0x004E4942);
        out.insert(out.end(), bin.begin(), bin.end());
        return out;
    }

    void write_glb(const fs::path& path) const { write_bytes(path, glb_bytes()); }

    static void write_bytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
        std::ofstream(path, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    }

private:
    int push(const char* array, const json& value) {
        doc_[array].push_back(value);
        return static_cast<int>(doc_[array].size()) - 1;
    }

    json doc_;
    std::vector<unsigned char> bin_;
};

const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

/// A one-node, one-mesh quad ("quad_node/quad_mesh") with the given index component type.
GltfBuilder quad_builder(int index_type = kUnsignedShort) {
    GltfBuilder b;
    const int positions = b.add_positions(kQuad);
    int indices = -1;
    switch (index_type) {
        case kUnsignedByte: indices = b.add_indices(std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3}, index_type); break;
        case kUnsignedShort: indices = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}, index_type); break;
        case kUnsignedInt: indices = b.add_indices(std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}, index_type); break;
    }
    const int mesh = b.add_mesh("quad_mesh", json::array({GltfBuilder::primitive(positions, indices)}));
    b.add_node({{"name", "quad_node"}, {"mesh", mesh}});
    return b;
}

class GltfLoaderTest : public ::testing::Test {
protected:
    void SetUp() override {
        static int counter = 0;
        dir_ = fs::temp_directory_path() /
               ("dynrt_gltf_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    fs::path path(const std::string& name) const { return dir_ / name; }

    Scene write_and_load(GltfBuilder& b, const std::string& name = "scene.gltf") {
        b.write_gltf(path(name));
        return load_gltf(path(name));
    }

    /// Expects load_gltf(file) to throw a SceneError naming the file and containing each fragment.
    void expect_error(const fs::path& file, const std::vector<std::string>& fragments) {
        try {
            load_gltf(file);
            ADD_FAILURE() << "no error for " << file;
        } catch (const SceneError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
            for (const std::string& fragment : fragments) {
                EXPECT_NE(what.find(fragment), std::string::npos) << "'" << fragment << "' not in: " << what;
            }
        }
    }

    void expect_error(GltfBuilder& b, const std::vector<std::string>& fragments) {
        b.write_gltf(path("bad.gltf"));
        expect_error(path("bad.gltf"), fragments);
    }

    fs::path dir_;
};

// ---- Good files ------------------------------------------------------------------------------

TEST_F(GltfLoaderTest, IndexedTrianglesWithEveryIndexType) {
    for (const int type : {kUnsignedByte, kUnsignedShort, kUnsignedInt}) {
        SCOPED_TRACE(type);
        GltfBuilder b = quad_builder(type);
        const Scene scene = write_and_load(b);
        ASSERT_EQ(scene.objects.size(), 1u);
        const Object& o = scene.objects[0];
        EXPECT_EQ(o.name, "quad_node/quad_mesh");
        EXPECT_EQ(o.mesh.positions, kQuad);
        ASSERT_EQ(o.mesh.triangles.size(), 2u);
        EXPECT_EQ(o.mesh.triangles[0], glm::uvec3(0, 1, 2));
        EXPECT_EQ(o.mesh.triangles[1], glm::uvec3(0, 2, 3));
        EXPECT_EQ(o.transform, glm::mat4(1.0f));
        EXPECT_EQ(o.material, 0u);
        ASSERT_EQ(scene.materials.size(), 1u);
        EXPECT_EQ(scene.materials[0].diffuse, glm::vec3(0.8f));
        EXPECT_EQ(scene.source, path("scene.gltf").string());
    }
}

TEST_F(GltfLoaderTest, NonIndexedTriangles) {
    GltfBuilder b;
    const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {2, 1, 0}});
    b.add_node({{"name", "n"}, {"mesh", b.add_mesh("m", json::array({GltfBuilder::primitive(positions)}))}});
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {3, 4, 5}}));
}

TEST_F(GltfLoaderTest, StripsAlternateWindingAndFansPivotOnTheFirstVertex) {
    GltfBuilder b;
    const int positions = b.add_positions({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}});
    const int indices = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 3, 4}, kUnsignedShort);
    const int strip = b.add_mesh("strip", json::array({GltfBuilder::primitive(positions, indices, kStrip)}));
    const int fan = b.add_mesh("fan", json::array({GltfBuilder::primitive(positions, indices, kFan)}));
    const int plain_strip =
        b.add_mesh("plain_strip", json::array({GltfBuilder::primitive(positions, -1, kStrip)}));
    b.add_node({{"name", "s"}, {"mesh", strip}});
    b.add_node({{"name", "f"}, {"mesh", fan}});
    b.add_node({{"name", "p"}, {"mesh", plain_strip}});
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 3u);
    // glTF 2.0 3.7.2.1: strip p_i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}); fan p_i = (v_{i+1}, v_{i+2}, v_0).
    const std::vector<glm::uvec3> expected_strip = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}};
    EXPECT_EQ(scene.objects[0].mesh.triangles, expected_strip);
    EXPECT_EQ(scene.objects[1].mesh.triangles, (std::vector<glm::uvec3>{{1, 2, 0}, {2, 3, 0}, {3, 4, 0}}));
    EXPECT_EQ(scene.objects[2].mesh.triangles, expected_strip);
    // Consistent winding: every strip triangle of this zig-zag faces the same way.
    for (const glm::uvec3& t : scene.objects[0].mesh.triangles) {
        const glm::vec3 a = scene.objects[0].mesh.positions[t.x], b2 = scene.objects[0].mesh.positions[t.y],
                        c = scene.objects[0].mesh.positions[t.z];
        EXPECT_LT((b2.x - a.x) * (c.y - a.y) - (b2.y - a.y) * (c.x - a.x), 0.0f);
    }
}

TEST_F(GltfLoaderTest, NodeHierarchyWithMatrixAndTrs) {
    GltfBuilder b;
    const int mesh = b.add_mesh(
        "tri", json::array({GltfBuilder::primitive(b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}));
    // Parent: matrix = translate(1,2,3) * scale(2), column-major.
    const double half_sqrt2 = std::sqrt(0.5);
    const int child = b.add_node({{"name", "child"},
                                  {"mesh", mesh},
                                  {"translation", {0.0, 1.0, 0.0}},
                                  {"rotation", {0.0, 0.0, half_sqrt2, half_sqrt2}},
                                  {"scale", {1.0, 1.0, 3.0}}},
                                 false);
    const int grandchild =
        b.add_node({{"name", "grandchild"}, {"mesh", mesh}, {"translation", {5.0, 0.0, 0.0}}}, false);
    b.doc()["nodes"][child]["children"] = json::array({grandchild});
    b.add_node({{"name", "parent"},
                {"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1}},
                {"children", json::array({child})}});
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 2u);
    EXPECT_EQ(scene.objects[0].name, "child/tri");
    EXPECT_EQ(scene.objects[1].name, "grandchild/tri");

    const glm::mat4 parent = glm::scale(glm::translate(glm::mat4(1.0f), {1, 2, 3}), glm::vec3(2.0f));
    const glm::mat4 child_local = glm::scale(
        glm::rotate(glm::translate(glm::mat4(1.0f), {0, 1, 0}), glm::radians(90.0f), glm::vec3(0, 0, 1)),
        {1, 1, 3});
    const glm::mat4 expected_child = parent * child_local;
    const glm::mat4 expected_grandchild = expected_child * glm::translate(glm::mat4(1.0f), {5, 0, 0});
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            EXPECT_NEAR(scene.objects[0].transform[c][r], expected_child[c][r], 1e-5f) << c << "," << r;
            EXPECT_NEAR(scene.objects[1].transform[c][r], expected_grandchild[c][r], 1e-5f) << c << "," << r;
        }
    }
    // Positions stay in mesh space.
    EXPECT_EQ(scene.objects[1].mesh.positions[1], glm::vec3(1, 0, 0));
}

TEST_F(GltfLoaderTest, UnnamedNodesMultiPrimitiveMeshesAndMaterials) {
    GltfBuilder b;
    const int positions = b.add_positions(kQuad);
    const int indices = b.add_indices(std::vector<std::uint8_t>{0, 1, 2}, kUnsignedByte);
    const int red = b.add_material("red", {1.0f, 0.0f, 0.0f});
    const int blue = b.add_material("", {0.0f, 0.25f, 1.0f});
    const int mesh =
        b.add_mesh("", json::array({GltfBuilder::primitive(positions, indices, kTriangles, blue),
                                    GltfBuilder::primitive(positions, indices),
                                    GltfBuilder::primitive(positions, indices, kTriangles, red)}));
    b.add_node({{"mesh", mesh}});
    // A material with a texture whose image file is missing: no error (the renderer warns
    // when it cannot read the file, and uses the colour alone).
    b.doc()["images"] = json::array({json{{"uri", "missing_texture.png"}}});
    b.doc()["textures"] = json::array({json{{"source", 0}}});
    b.doc()["materials"][red]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    // The blue one glows through the same texture (emissiveTexture); an emissiveTexture
    // without an emissive factor adds nothing, so it is not mapped.
    b.doc()["materials"][blue]["emissiveTexture"] = {{"index", 0}};
    b.doc()["materials"][blue]["emissiveFactor"] = {1.0, 1.0, 0.5};
    b.doc()["materials"][red]["emissiveTexture"] = {{"index", 0}};

    const Scene scene = write_and_load(b);
    ASSERT_TRUE(scene.materials[2].emission_map.has_value());
    EXPECT_EQ(scene.materials[2].emission_map->texture, scene.materials[1].diffuse_map->texture);
    EXPECT_FALSE(scene.materials[2].diffuse_map.has_value());
    EXPECT_FALSE(scene.materials[1].emission_map.has_value());
    ASSERT_EQ(scene.objects.size(), 3u);
    EXPECT_EQ(scene.objects[0].name, "node0/mesh0#0");
    EXPECT_EQ(scene.objects[1].name, "node0/mesh0#1");
    EXPECT_EQ(scene.objects[2].name, "node0/mesh0#2");
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[0].diffuse, glm::vec3(0.8f));
    EXPECT_EQ(scene.materials[1].name, "red");
    EXPECT_EQ(scene.materials[1].diffuse, glm::vec3(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(scene.materials[2].name, "material1");
    EXPECT_EQ(scene.materials[2].diffuse, glm::vec3(0.0f, 0.25f, 1.0f));
    EXPECT_EQ(scene.objects[0].material, 2u);
    EXPECT_EQ(scene.objects[1].material, 0u);
    EXPECT_EQ(scene.objects[2].material, 1u);
}

// The material mapping (gltf_loader.cpp, docs/scene-input.md "Materials"): base = baseColorFactor,
//   reflectance = metallic * base * (1 - roughness)^2, transmittance = transmission *
//   (1 - metallic) * base, diffuse = base * (1 - transmission), ior from KHR_materials_ior
//   (1.5 when the material has either extension, 1 otherwise).
TEST_F(GltfLoaderTest, MaterialsMapMetalnessTransmissionAndIor) {
    GltfBuilder b = quad_builder();
    const auto pbr = [](const glm::vec3& base, double metallic, double roughness) {
        return json{{"baseColorFactor", {base.x, base.y, base.z, 1.0}},
                    {"metallicFactor", metallic},
                    {"roughnessFactor", roughness}};
    };
    const glm::vec3 gold(0.9f, 0.6f, 0.3f), tint(0.8f, 0.9f, 1.0f), amber(1.0f, 0.5f, 0.25f);
    b.doc()["materials"] = json::array({
        json{{"name", "mirror"}, {"pbrMetallicRoughness", pbr(gold, 1.0, 0.0)}},
        json{{"name", "brushed"}, {"pbrMetallicRoughness", pbr(gold, 1.0, 0.5)}},
        json{{"name", "plastic"}, {"pbrMetallicRoughness", pbr(gold, 0.0, 0.0)}},
        json{{"name", "glass"},
             {"pbrMetallicRoughness", pbr(tint, 0.0, 0.0)},
             {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}},
        json{{"name", "half"},
             {"pbrMetallicRoughness", pbr(amber, 0.5, 0.0)},
             {"extensions",
              {{"KHR_materials_transmission", {{"transmissionFactor", 0.5}}}, {"KHR_materials_ior", {{"ior", 1.33}}}}}},
        json{{"name", "water"}, {"extensions", {{"KHR_materials_ior", {{"ior", 1.33}}}}}},
        json{{"name", "glTF defaults"}},
        json{{"name", "over"},
             {"pbrMetallicRoughness", pbr(tint, 0.0, 0.0)},
             {"extensions",
              {{"KHR_materials_transmission", {{"transmissionFactor", 3.0}, {"transmissionTexture", {{"index", 0}}}}},
               {"KHR_materials_ior", json::object()}}}},
    });
    b.doc()["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"};
    b.doc()["extensionsRequired"] = {"KHR_materials_transmission"};
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.materials.size(), 9u);
    const auto material = [&](const std::string& name) -> const Material& {
        for (const Material& m : scene.materials) {
            if (m.name == name) return m;
        }
        ADD_FAILURE() << "no material " << name;
        return scene.materials.front();
    };
    const glm::vec3 zero(0.0f);

    // A smooth metal is a mirror of its base colour; rougher, less of one.
    EXPECT_EQ(material("mirror").reflectance, gold);
    EXPECT_EQ(material("mirror").diffuse, gold);
    EXPECT_EQ(material("mirror").transmittance, zero);
    EXPECT_EQ(material("mirror").ior, 1.0f);
    EXPECT_EQ(material("brushed").reflectance, gold * 0.25f);
    // A dielectric reflects no ray (its highlight stays Phong's).
    EXPECT_EQ(material("plastic").reflectance, zero);
    EXPECT_EQ(material("plastic").transmittance, zero);
    EXPECT_FALSE(material("plastic").traces_secondary());

    // Full transmission: no diffuse, the base colour tints what goes through, glTF's ior 1.5.
    EXPECT_EQ(material("glass").transmittance, tint);
    EXPECT_EQ(material("glass").diffuse, zero);
    EXPECT_EQ(material("glass").reflectance, zero);
    EXPECT_EQ(material("glass").ior, 1.5f);
    // Half metal, half transmissive, its own ior.
    EXPECT_EQ(material("half").diffuse, amber * 0.5f);
    EXPECT_EQ(material("half").transmittance, amber * 0.25f);
    EXPECT_EQ(material("half").reflectance, amber * 0.5f);
    EXPECT_FLOAT_EQ(material("half").ior, 1.33f);
    // KHR_materials_ior alone gives the ior of an opaque material.
    EXPECT_FLOAT_EQ(material("water").ior, 1.33f);
    EXPECT_EQ(material("water").transmittance, zero);
    // glTF's defaults (white, metallic 1, roughness 1): fully rough, so no mirror.
    EXPECT_EQ(material("glTF defaults").diffuse, glm::vec3(1.0f));
    EXPECT_EQ(material("glTF defaults").reflectance, zero);
    EXPECT_EQ(material("glTF defaults").ior, 1.0f);
    // transmissionFactor is clamped to [0, 1]; an empty KHR_materials_ior is its default.
    EXPECT_EQ(material("over").transmittance, tint);
    EXPECT_EQ(material("over").ior, 1.5f);

    // The two material extensions are implemented; another one and the transmission texture
    // are reported.
    const std::vector<std::string> ignored = {
        "textures other than base colour and emission of 1 material(s) (metal, roughness and transmission from their factors)",
        "extension KHR_materials_volume (not implemented)"};
    EXPECT_EQ(scene.ignored, ignored);
}

TEST_F(GltfLoaderTest, EmissionAndAlphaAreMapped) {
    // emissiveFactor (clamped to [0, 1]) times KHR_materials_emissive_strength; MASK is a
    // cut-out at its alphaCutoff (default 1/2), BLEND covers its base alpha of what is behind
    // (convert_alpha), OPAQUE ignores alpha.
    GltfBuilder b = quad_builder();
    const int glowing = b.add_material("glowing", {1.0f, 1.0f, 1.0f});
    const int strong = b.add_material("strong", {1.0f, 1.0f, 1.0f});
    const int cut = b.add_material("cut", {1.0f, 1.0f, 1.0f});
    const int see_through = b.add_material("see-through", {1.0f, 1.0f, 1.0f});
    const int opaque = b.add_material("opaque", {1.0f, 1.0f, 1.0f});
    b.doc()["materials"][glowing]["emissiveFactor"] = {1.0, 0.5, 2.0};
    b.doc()["materials"][strong]["emissiveFactor"] = {0.5, 0.25, 0.0};
    b.doc()["materials"][strong]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 4.0;
    b.doc()["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    b.doc()["materials"][cut]["alphaMode"] = "MASK";
    b.doc()["materials"][see_through]["alphaMode"] = "BLEND";
    b.doc()["materials"][opaque]["alphaMode"] = "OPAQUE";
    b.doc()["materials"][see_through]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 0.5, 1.0, 0.25};
    b.doc()["materials"][opaque]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 0.25};
    const Scene scene = write_and_load(b);
    const auto material = [&](const std::string& name) {
        for (const Material& m : scene.materials) {
            if (m.name == name) return m;
        }
        ADD_FAILURE() << "no material " << name;
        return Material{};
    };
    EXPECT_EQ(material("glowing").emission, glm::vec3(1.0f, 0.5f, 1.0f));
    EXPECT_FALSE(material("glowing").emission_map.has_value());
    EXPECT_EQ(material("strong").emission, glm::vec3(2.0f, 1.0f, 0.0f));
    EXPECT_EQ(material("opaque").emission, glm::vec3(0.0f));
    EXPECT_EQ(material("cut").alpha_cutoff, 0.5f);
    EXPECT_EQ(material("cut").base_alpha, 1.0f);
    EXPECT_EQ(material("cut").transmittance, glm::vec3(0.0f));
    const Material blend = material("see-through");
    EXPECT_FALSE(blend.alpha_cutoff.has_value());  // no texture: its cover is the factor's
    const Material plain = material("opaque");
    EXPECT_FALSE(plain.alpha_cutoff.has_value());
    EXPECT_EQ(plain.transmittance, glm::vec3(0.0f));
    EXPECT_EQ(blend.diffuse, 0.25f * plain.diffuse * glm::vec3(1.0f, 0.5f, 1.0f));
    EXPECT_EQ(blend.specular, 0.25f * plain.specular);
    EXPECT_EQ(blend.transmittance, glm::vec3(0.75f));
    EXPECT_EQ(blend.ior, 1.0f);
    EXPECT_TRUE(scene.ignored.empty()) << scene.ignored.front();

    // A BLEND material's texture alpha is cut at 1/2, and said so.
    b.doc()["images"] = json::array({json{{"uri", "missing_texture.png"}}});
    b.doc()["textures"] = json::array({json{{"source", 0}}});
    b.doc()["materials"][see_through]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    const Scene textured = write_and_load(b);
    EXPECT_EQ(textured.materials[std::size_t(see_through) + 1].alpha_cutoff, 0.5f);
    const std::vector<std::string> ignored = {
        "partial cover from the base colour texture's alpha of 1 BLEND material(s) (cut out where below 1/2)"};
    EXPECT_EQ(textured.ignored, ignored);
    b.doc()["materials"][see_through]["pbrMetallicRoughness"].erase("baseColorTexture");

    // A negative strength is refused, naming the material.
    b.doc()["materials"][strong]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = -1.0;
    b.write_gltf(path("negative.gltf"));
    expect_error(path("negative.gltf"), {"material 'strong'", "emission", "must be finite and >= 0"});
    b.doc()["materials"][strong]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 1.0;

    // Alpha the specification does not allow is refused, naming the material.
    b.doc()["materials"][cut]["alphaCutoff"] = 1.5;
    expect_error(b, {"material 'cut'", "alphaCutoff 1.5 must be in [0, 1]"});
    b.doc()["materials"][cut]["alphaCutoff"] = -0.1;
    expect_error(b, {"material 'cut'", "alphaCutoff -0.1 must be in [0, 1]"});
    b.doc()["materials"][cut]["alphaCutoff"] = 0.3;
    b.doc()["materials"][opaque]["alphaMode"] = "TRANSLUCENT";
    expect_error(b, {"material 'opaque'", "alphaMode 'TRANSLUCENT' is not OPAQUE, MASK or BLEND"});
}

TEST_F(GltfLoaderTest, PunctualLightsAreReadOnTheirNodes) {
    // KHR_lights_punctual: each kind in the spec's units (candela, lux) divided by pi for
    // dynrt's Phong (gltf_lights.h), on its node, pointing down the node's -Z.
    GltfBuilder b = quad_builder();
    b.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"name", "bulb"}, {"type", "point"}, {"intensity", 100.0}, {"color", {1.0, 0.5, 0.25}}, {"range", 10.0}},
        {{"type", "spot"}, {"intensity", 50.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
        {{"name", "sun"}, {"type", "directional"}, {"intensity", 3.0}}};
    for (int light = 0; light < 3; ++light) {
        b.add_node({{"name", "holder " + std::to_string(light)},
                    {"translation", {1.0 * light, 2.0, 0.0}},
                    {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
    }
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.lights.size(), 3u);
    const PointLight& bulb = scene.lights[0];
    EXPECT_EQ(bulb.name, "bulb");
    EXPECT_EQ(bulb.kind, PointLight::Kind::point);
    EXPECT_FLOAT_EQ(bulb.intensity, float(100.0 / M_PI));
    EXPECT_EQ(bulb.color, glm::vec3(1.0f, 0.5f, 0.25f));
    EXPECT_TRUE(bulb.inverse_square);
    EXPECT_EQ(bulb.range, 10.0f);
    EXPECT_EQ(scene.nodes.at(std::size_t(bulb.node)).name, "holder 0");
    const PointLight& spot = scene.lights[1];
    EXPECT_EQ(spot.name, "holder 1");  // unnamed: the node's name
    EXPECT_EQ(spot.kind, PointLight::Kind::spot);
    EXPECT_FLOAT_EQ(spot.inner_cone, 0.2f);
    EXPECT_FLOAT_EQ(spot.outer_cone, 0.5f);
    EXPECT_EQ(spot.direction, glm::vec3(0.0f, 0.0f, -1.0f));
    const PointLight& sun = scene.lights[2];
    EXPECT_EQ(sun.kind, PointLight::Kind::directional);
    EXPECT_FALSE(sun.inverse_square);
    EXPECT_FLOAT_EQ(sun.intensity, float(3.0 / M_PI));
    EXPECT_TRUE(scene.ignored.empty()) << scene.ignored.front();

    // Bad lights are refused, naming the light.
    json& lights = b.doc()["extensions"]["KHR_lights_punctual"]["lights"];
    lights[1]["spot"]["innerConeAngle"] = 0.6;
    expect_error(b, {"light 'holder 1'", "innerConeAngle < outerConeAngle"});
    lights[1]["spot"]["innerConeAngle"] = 0.2;
    lights[1]["spot"]["outerConeAngle"] = 2.0;
    expect_error(b, {"light 'holder 1'", "<= pi/2"});
    lights[1]["spot"]["outerConeAngle"] = 0.5;
    lights[0]["intensity"] = -1.0;
    expect_error(b, {"light 'bulb'", "intensity must be finite and >= 0"});
    lights[0]["intensity"] = 1.0;
    lights[0]["color"] = {1.0, -1.0, 0.0};
    expect_error(b, {"light 'bulb'", "color"});
    lights[0]["color"] = {1.0, 1.0, 1.0};
    lights[0]["range"] = -3.0;
    expect_error(b, {"light 'bulb'", "range must be finite and > 0"});
    lights[0]["range"] = 10.0;
    lights[2]["type"] = "area";
    expect_error(b, {"light 'sun'", "type 'area'"});
    lights[2]["type"] = "directional";
    b.doc()["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"] = 7;
    expect_error(b, {"node 'holder 0'", "light 7 does not exist"});
}

TEST_F(GltfLoaderTest, BadIorIsAnErrorNamingObjectAndMaterial) {
    for (const double ior : {0.0, -1.5}) {
        GltfBuilder b = quad_builder();
        b.doc()["materials"] = json::array(
            {json{{"name", "ice"}, {"extensions", {{"KHR_materials_ior", {{"ior", ior}}}}}}});
        b.doc()["meshes"][0]["primitives"][0]["material"] = 0;
        expect_error(b, {"object 'quad_node/quad_mesh': material 'ice' (index 1): ior " +
                             std::string(ior == 0.0 ? "0" : "-1.5") + " must be finite and > 0"});
    }
    // A material no primitive uses is refused all the same, named alone.
    GltfBuilder unused = quad_builder();
    unused.doc()["materials"] = json::array(
        {json{{"name", "spare"}, {"extensions", {{"KHR_materials_ior", {{"ior", 0.0}}}}}}});
    expect_error(unused, {"material 'spare' (index 1): ior 0 must be finite and > 0"});
}

TEST_F(GltfLoaderTest, ByteStrideAndOffsetsAreRespected) {
    GltfBuilder b;
    // Interleaved: 4 bytes of padding, then x y z, then 8 more bytes: a 24-byte stride.
    std::vector<float> interleaved;
    for (const glm::vec3& p : kQuad) {
        interleaved.insert(interleaved.end(), {-7.0f, p.x, p.y, p.z, -8.0f, -9.0f});
    }
    const int view = b.add_view(interleaved.data(), interleaved.size() * sizeof(float), 24);
    const int positions = b.add_accessor(view, kFloat, 4, "VEC3", 4);
    // Indices start 2 bytes into their view.
    const std::vector<std::uint16_t> raw = {999, 0, 2, 3};
    const int index_view = b.add_view(raw.data(), raw.size() * 2);
    const int indices = b.add_accessor(index_view, kUnsignedShort, 3, "SCALAR", 2);
    b.add_node({{"name", "n"},
                {"mesh", b.add_mesh("m", json::array({GltfBuilder::primitive(positions, indices)}))}});
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].mesh.positions, kQuad);
    EXPECT_EQ(scene.objects[0].mesh.triangles, (std::vector<glm::uvec3>{{0, 2, 3}}));
}

TEST_F(GltfLoaderTest, GlbLoadsLikeGltfWhateverTheExtensionCase) {
    GltfBuilder b = quad_builder(kUnsignedInt);
    b.write_glb(path("QUAD.GLB"));
    const Scene scene = load_scene(path("QUAD.GLB").string());
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].name, "quad_node/quad_mesh");
    EXPECT_EQ(scene.objects[0].mesh.positions, kQuad);
    EXPECT_EQ(scene.objects[0].mesh.triangles.size(), 2u);

    b.write_gltf(path("Quad.GlTf"));
    EXPECT_EQ(load_scene(path("Quad.GlTf").string()).triangle_count(), 2u);
}

TEST_F(GltfLoaderTest, SceneSelection) {
    GltfBuilder b;
    const int mesh = b.add_mesh(
        "m", json::array({GltfBuilder::primitive(b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}))}));
    const int a = b.add_node({{"name", "a"}, {"mesh", mesh}});
    const int c = b.add_node({{"name", "c"}, {"mesh", mesh}}, false);
    const int p = b.add_node({{"name", "p"}, {"mesh", mesh}, {"children", json::array({c})}}, false);
    b.doc()["scenes"].push_back({{"nodes", json::array({p})}});

    b.doc()["scene"] = 1;
    Scene scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 2u);
    EXPECT_EQ(scene.objects[0].name, "p/m");
    EXPECT_EQ(scene.objects[1].name, "c/m");

    b.doc().erase("scene");  // no default: scene 0
    scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].name, "a/m");

    b.doc().erase("scenes");  // no scenes: every root node, in node order
    scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 3u);
    EXPECT_EQ(scene.objects[0].name, "a/m");
    EXPECT_EQ(scene.objects[1].name, "p/m");
    EXPECT_EQ(scene.objects[2].name, "c/m");
    (void)a;
}

TEST_F(GltfLoaderTest, PointsAndLinesAreSkipped) {
    GltfBuilder b;
    const int positions = b.add_positions(kQuad);
    const int mesh = b.add_mesh("mixed", json::array({GltfBuilder::primitive(positions, -1, kPoints),
                                                      GltfBuilder::primitive(positions, -1, kLines),
                                                      GltfBuilder::primitive(positions, -1, kFan)}));
    b.add_node({{"name", "n"}, {"mesh", mesh}});
    const Scene scene = write_and_load(b);
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].name, "n/mixed#2");
    EXPECT_EQ(scene.objects[0].mesh.triangles.size(), 2u);
}

// ---- Bad files -------------------------------------------------------------------------------

TEST_F(GltfLoaderTest, MissingFile) { expect_error(path("nope.gltf"), {"no such file"}); }

TEST_F(GltfLoaderTest, MalformedJson) {
    std::ofstream(path("broken.gltf")) << "{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ ";
    expect_error(path("broken.gltf"), {"invalid glTF"});
    std::ofstream(path("empty.gltf")) << "";
    expect_error(path("empty.gltf"), {"invalid glTF"});
}

TEST_F(GltfLoaderTest, TruncatedAndCorruptGlb) {
    const std::vector<unsigned char> good = quad_builder().glb_bytes();
    for (const std::size_t size : {std::size_t{0}, std::size_t{5}, std::size_t{12}, std::size_t{30},
                                   good.size() / 2, good.size() - 4}) {
        SCOPED_TRACE(size);
        GltfBuilder::write_bytes(path("cut.glb"), std::vector<unsigned char>(
                                                      good.begin(), good.begin() + static_cast<long>(size)));
        expect_error(path("cut.glb"), {"truncated GLB"});
    }
    std::vector<unsigned char> bad_magic = good;
    bad_magic[0] = 'x';
    GltfBuilder::write_bytes(path("magic.glb"), bad_magic);
    expect_error(path("magic.glb"), {"not a GLB"});

    // A BIN chunk whose length overruns the file by less than its own 8-byte header: the case
    // tinygltf 2.7 itself would read past the end for.
    std::vector<unsigned char> overrun = good;
    const std::size_t json_length = overrun[12] | overrun[13] << 8 | overrun[14] << 16 | overrun[15] << 24;
    const std::size_t bin_header = 20 + json_length;
    overrun[bin_header] = static_cast<unsigned char>(overrun[bin_header] + 4);
    GltfBuilder::write_bytes(path("overrun.glb"), overrun);
    expect_error(path("overrun.glb"), {"truncated GLB"});

    // A header that claims fewer bytes than itself (the fuzzer's find: no chunk to read at all).
    std::vector<unsigned char> short_length = good;
    short_length[8] = short_length[9] = short_length[10] = short_length[11] = 0;
    GltfBuilder::write_bytes(path("short.glb"), short_length);
    expect_error(path("short.glb"), {"corrupt GLB", "shorter than the header"});

    // Text where a GLB should be.
    std::ofstream(path("text.glb")) << "{ \"asset\": { \"version\": \"2.0\" } }";
    expect_error(path("text.glb"), {"not a GLB"});
}

/// A GLB of `text` (space-padded) and, when `bin_type` is not 0, a chunk of `bin` of that type.
std::vector<unsigned char> glb_of(std::string text, std::vector<unsigned char> bin, std::uint32_t bin_type) {
    while (text.size() % 4 != 0) text.push_back(' ');
    while (bin.size() % 4 != 0) bin.push_back(0);
    std::vector<unsigned char> out;
    const auto u32 = [&](std::size_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    u32(0x46546C67);
    u32(2);
    u32(12 + 8 + text.size() + (bin_type != 0 ? 8 + bin.size() : 0));
    u32(text.size());
    u32(0x4E4F534A);
    out.insert(out.end(), text.begin(), text.end());
    if (bin_type != 0) {
        u32(bin.size());
        u32(bin_type);
        out.insert(out.end(), bin.begin(), bin.end());
    }
    return out;
}

// A .glb file is read without a second copy of its BIN chunk (gltf_file.cpp): buffer 0 is read
// from the file straight into the model. Its mesh, the files it lists and tinygltf's refusals of
// a bad BIN chunk stay what they were.
TEST_F(GltfLoaderTest, GlbFilesReadTheirBinChunkOnce) {
    GltfBuilder b = quad_builder(kUnsignedInt);
    b.write_glb(path("quad.glb"));
    const Scene scene = load_gltf(path("quad.glb"));
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(std::vector<glm::vec3>(scene.objects[0].mesh.positions.begin(), scene.objects[0].mesh.positions.end()),
              kQuad);
    EXPECT_EQ(scene.objects[0].mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));
    EXPECT_EQ(scene.files, std::vector<std::string>{path("quad.glb").string()});

    json doc = b.doc();
    const std::vector<unsigned char>& bin = b.bin();
    // Buffer 0 claims more bytes than the BIN chunk holds.
    doc["buffers"] = json::array({json{{"byteLength", bin.size() + 64}}});
    GltfBuilder::write_bytes(path("long.glb"), glb_of(doc.dump(), bin, 0x004E4942));
    expect_error(path("long.glb"), {"invalid glTF", "byteLength"});
    // No BIN chunk for a buffer without a URI.
    doc["buffers"] = json::array({json{{"byteLength", bin.size()}}});
    GltfBuilder::write_bytes(path("nobin.glb"), glb_of(doc.dump(), {}, 0));
    expect_error(path("nobin.glb"), {"invalid glTF", "empty BIN chunk"});
    // A second chunk that is not BIN.
    GltfBuilder::write_bytes(path("notbin.glb"), glb_of(doc.dump(), bin, 0x12345678));
    expect_error(path("notbin.glb"), {"invalid glTF", "chunk1"});
    // A BIN chunk too short to hold anything.
    GltfBuilder::write_bytes(path("tiny.glb"), glb_of(doc.dump(), {}, 0x004E4942));
    expect_error(path("tiny.glb"), {"invalid glTF", "Chunk1(BIN)"});
}

// ---- Documents in memory ---------------------------------------------------------------------

TEST_F(GltfLoaderTest, FromMemoryLoadsLikeTheFile) {
    GltfBuilder b = quad_builder(kUnsignedByte);
    const std::vector<unsigned char> glb = b.glb_bytes();
    b.write_glb(path("quad.glb"));
    const Scene from_file = load_gltf(path("quad.glb"));
    const Scene from_memory = load_gltf_from_memory(glb, GltfFormat::binary, "in memory");
    EXPECT_EQ(from_memory.source, "in memory");
    ASSERT_EQ(from_memory.objects.size(), from_file.objects.size());
    EXPECT_EQ(from_memory.objects[0].name, from_file.objects[0].name);
    EXPECT_EQ(from_memory.objects[0].mesh.positions, from_file.objects[0].mesh.positions);
    EXPECT_EQ(from_memory.objects[0].mesh.triangles, from_file.objects[0].mesh.triangles);

    // The same document as JSON, its buffer embedded as a data: URI.
    json doc = b.doc();
    const std::vector<unsigned char>& bin = b.bin();
    static const char* const alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string base64;
    for (std::size_t i = 0; i < bin.size(); i += 3) {
        const std::size_t n = std::min<std::size_t>(3, bin.size() - i);
        std::uint32_t triple = 0;
        for (std::size_t k = 0; k < 3; ++k) triple = triple << 8 | (k < n ? bin[i + k] : 0u);
        for (std::size_t k = 0; k < 4; ++k) base64 += k <= n ? alphabet[triple >> (18 - 6 * k) & 63] : '=';
    }
    doc["buffers"] = json::array(
        {json{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64}}});
    const std::string text = doc.dump();
    const Scene from_json = load_gltf_from_memory(std::span(reinterpret_cast<const unsigned char*>(text.data()),
                                                            text.size()),
                                                  GltfFormat::json, "in memory");
    EXPECT_EQ(from_json.objects[0].mesh.triangles, from_file.objects[0].mesh.triangles);
}

TEST_F(GltfLoaderTest, FromMemoryNeverReadsFiles) {
    // scene.bin exists next to the working directory's idea of the document, but a document in
    // memory has no directory: only data: URIs are read.
    GltfBuilder b = quad_builder();
    b.write_gltf(path("scene.gltf"));
    std::ifstream in(path("scene.gltf"), std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const fs::path previous = fs::current_path();
    fs::current_path(dir_);
    try {
        load_gltf_from_memory(bytes, GltfFormat::json, "doc.gltf");
        ADD_FAILURE() << "an external buffer was read";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("doc.gltf: invalid glTF: ", 0), 0u) << what;
        EXPECT_NE(what.find("only data: URIs"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    fs::current_path(previous);

    try {
        load_gltf_from_memory(std::span(bytes.data(), 10), GltfFormat::binary, "doc.glb");
        ADD_FAILURE() << "no error for a truncated GLB";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("doc.glb: truncated GLB", 0), 0u) << e.what();
    }
}

TEST_F(GltfLoaderTest, MissingBinFile) {
    GltfBuilder b = quad_builder();
    b.write_gltf(path("scene.gltf"));
    fs::remove(path("scene.bin"));
    expect_error(path("scene.gltf"), {"invalid glTF", "scene.bin"});
}

TEST_F(GltfLoaderTest, AccessorOutOfBufferViewRange) {
    GltfBuilder b = quad_builder();
    b.doc()["accessors"][0]["count"] = 5;  // 5 positions in a 4-position view
    expect_error(b, {"object 'quad_node/quad_mesh'", "accessor 0", "exceed bufferView 0"});

    b = quad_builder();
    b.doc()["accessors"][1]["byteOffset"] = 2;  // 6 indices shifted past the view's end
    expect_error(b, {"object 'quad_node/quad_mesh'", "accessor 1"});
}

TEST_F(GltfLoaderTest, BufferViewOutOfBufferRange) {
    GltfBuilder b = quad_builder();
    b.doc()["bufferViews"][0]["byteOffset"] = 1000;
    expect_error(b, {"object 'quad_node/quad_mesh'", "exceeds buffer 0"});

    b = quad_builder();
    b.doc()["bufferViews"][1]["byteLength"] = 1u << 20;
    expect_error(b, {"object 'quad_node/quad_mesh'", "exceeds buffer 0"});

    b = quad_builder();
    b.doc()["accessors"][0]["bufferView"] = 7;
    expect_error(b, {"object 'quad_node/quad_mesh'"});
}

TEST_F(GltfLoaderTest, IndexOutOfRange) {
    GltfBuilder b;
    const int positions = b.add_positions(kQuad);
    const int indices = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 7}, kUnsignedShort);
    b.add_node({{"name", "n"},
                {"mesh", b.add_mesh("m", json::array({GltfBuilder::primitive(positions, indices)}))}});
    expect_error(b, {"object 'n/m'", "index 5 (value 7) out of range of 4 positions"});
}

TEST_F(GltfLoaderTest, NonFinitePositions) {
    for (const float bad :
         {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        GltfBuilder b;
        const int positions = b.add_positions({{0, 0, 0}, {1, bad, 0}, {0, 1, 0}});
        b.add_node(
            {{"name", "n"}, {"mesh", b.add_mesh("m", json::array({GltfBuilder::primitive(positions)}))}});
        expect_error(b, {"object 'n/m'", "position 1 is not finite"});
    }
}

TEST_F(GltfLoaderTest, NoTriangles) {
    GltfBuilder b;
    b.add_node({{"name", "empty"}});
    expect_error(b, {"no triangles"});

    GltfBuilder lines;
    const int positions = lines.add_positions(kQuad);
    lines.add_node(
        {{"name", "n"},
         {"mesh", lines.add_mesh("m", json::array({GltfBuilder::primitive(positions, -1, kLines),
                                                   GltfBuilder::primitive(positions, -1, kPoints)}))}});
    expect_error(lines, {"no triangles"});
}

TEST_F(GltfLoaderTest, UnsupportedAccessors) {
    GltfBuilder b = quad_builder();
    b.doc()["accessors"][0]["sparse"] = {{"count", 1},
                                         {"indices", {{"bufferView", 1}, {"componentType", kUnsignedShort}}},
                                         {"values", {{"bufferView", 0}}}};
    expect_error(b, {"object 'quad_node/quad_mesh'", "sparse"});

    b = quad_builder();
    b.doc()["accessors"][0]["componentType"] = kUnsignedShort;  // quantized positions
    expect_error(b, {"object 'quad_node/quad_mesh'", "POSITION must be FLOAT VEC3"});

    b = quad_builder();
    b.doc()["accessors"][1]["componentType"] = kFloat;
    expect_error(b, {"object 'quad_node/quad_mesh'", "indices must be"});
}

TEST_F(GltfLoaderTest, BrokenNodeGraph) {
    GltfBuilder cycle = quad_builder();
    cycle.add_node({{"name", "other"}, {"children", json::array({0})}}, false);
    cycle.doc()["nodes"][0]["children"] = json::array({1});
    expect_error(cycle, {"node 'quad_node'", "reached twice"});

    GltfBuilder missing_child = quad_builder();
    missing_child.doc()["nodes"][0]["children"] = json::array({42});
    expect_error(missing_child, {"node 'quad_node' refers to node 42"});

    GltfBuilder missing_mesh = quad_builder();
    missing_mesh.doc()["nodes"][0]["mesh"] = 3;
    expect_error(missing_mesh, {"node 'quad_node': mesh 3 does not exist"});

    GltfBuilder bad_scene = quad_builder();
    bad_scene.doc()["scene"] = 4;
    expect_error(bad_scene, {"default scene 4"});

    GltfBuilder bad_matrix = quad_builder();
    bad_matrix.doc()["nodes"][0]["matrix"] = {1, 0, 0};
    expect_error(bad_matrix, {"node 'quad_node'", "matrix"});

    GltfBuilder bad_material = quad_builder();
    bad_material.doc()["meshes"][0]["primitives"][0]["material"] = 2;
    expect_error(bad_material, {"object 'quad_node/quad_mesh'", "material 2"});
}

// ---- Bundled and shared scenes ---------------------------------------------------------------

TEST(DefaultScene, LoadsWithSeveralObjectsAndAHierarchy) {
    const fs::path path = default_scene_path();
    ASSERT_TRUE(fs::exists(path)) << path;
    const Scene scene = load_gltf(path);
    EXPECT_GE(scene.objects.size(), 10u);
    EXPECT_GE(scene.materials.size(), 6u);
    EXPECT_GE(scene.triangle_count(), 30000u);
    EXPECT_LE(scene.triangle_count(), 80000u);

    // box_top sits under box_stack: world = stack TRS * top TRS.
    const auto find = [&](const std::string& name) -> const Object& {
        for (const Object& o : scene.objects) {
            if (o.name == name) return o;
        }
        ADD_FAILURE() << "no object " << name;
        return scene.objects.front();
    };
    const glm::mat4 stack = glm::rotate(glm::translate(glm::mat4(1.0f), {-2.7f, 0.0f, -2.4f}),
                                        glm::radians(25.0f), glm::vec3(0, 1, 0));
    const glm::vec4 expected = stack * glm::vec4(0.1f, 1.55f, 0.05f, 1.0f);
    const Object& top = find("box_top/box");
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(top.transform[3][r], expected[r], 1e-5f);
    EXPECT_EQ(find("pedestal/pedestal#1").name, "pedestal/pedestal#1");
    EXPECT_NE(find("pedestal/pedestal#0").material, find("pedestal/pedestal#1").material);
}

// Khronos' TransmissionTest: glTF materials 1-8 are transmissive dielectrics (glass), 9-12 the
// same with metallicFactor absent, so 1: smooth mirrors that let nothing through; 0 (the
// backdrop) and 13 (the label) are opaque. dynrt's material i + 1 is glTF's i.
TEST(SharedScenes, TransmissionTestHasGlassAndMirrors) {
    const fs::path file = fs::path(DYNRT_SHARED_SCENES_DIR) / "transmissiontest" / "TransmissionTest.glb";
    if (!fs::exists(file)) GTEST_SKIP() << file << " not found";
    const Scene scene = load_gltf(file);
    ASSERT_EQ(scene.materials.size(), 15u);
    EXPECT_EQ(scene.materials[2].name, "RedTransTexture");
    EXPECT_EQ(scene.materials[11].name, "YellowTransMetal");
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        SCOPED_TRACE(std::to_string(i) + " " + m.name);
        if (i >= 2 && i <= 9) {
            EXPECT_GT(m.transmittance.x + m.transmittance.y + m.transmittance.z, 0.5f);
            EXPECT_GE(std::min({m.transmittance.x, m.transmittance.y, m.transmittance.z}), 0.0f);
            EXPECT_EQ(m.diffuse, glm::vec3(0.0f));  // transmissionFactor 1
            EXPECT_EQ(m.reflectance, glm::vec3(0.0f));
            EXPECT_EQ(m.ior, 1.5f);
        } else if (i >= 10 && i <= 13) {
            EXPECT_EQ(m.transmittance, glm::vec3(0.0f));
            EXPECT_GT(m.reflectance.x + m.reflectance.y + m.reflectance.z, 0.5f);
        } else {
            EXPECT_FALSE(m.traces_secondary());
        }
    }
    // Objects are made of glass.
    EXPECT_TRUE(std::any_of(scene.objects.begin(), scene.objects.end(), [&](const Object& o) {
        const glm::vec3& t = scene.materials[o.material].transmittance;
        return t.x > 0.0f && t.y > 0.0f && t.z > 0.0f;
    }));
    // KHR_materials_transmission is implemented, its textures (and KHR_xmp) are not.
    EXPECT_NE(std::find(scene.ignored.begin(), scene.ignored.end(), "extension KHR_xmp (not implemented)"),
              scene.ignored.end());
    for (const std::string& line : scene.ignored) {
        EXPECT_EQ(line.find("KHR_materials_transmission"), std::string::npos) << line;
    }
}

TEST(SharedScenes, EveryGltfLoadsOrThrowsSceneError) {
    const fs::path root = DYNRT_SHARED_SCENES_DIR;
    if (!fs::is_directory(root)) GTEST_SKIP() << root << " does not exist";
    int loaded = 0, rejected = 0;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root)) {
        std::string ext = entry.path().extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (!entry.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
        try {
            const Scene scene = load_gltf(entry.path());
            EXPECT_GT(scene.triangle_count(), 0u) << entry.path();
            ++loaded;
        } catch (const SceneError& e) {
            ++rejected;
            std::cout << "[ rejected ] " << e.what() << '\n';
        } catch (const std::exception& e) {
            ADD_FAILURE() << entry.path() << ": not a SceneError: " << e.what();
        }
    }
    std::cout << "[ shared   ] " << loaded << " loaded, " << rejected << " rejected\n";
    EXPECT_GT(loaded, 0);
}

}  // namespace
}  // namespace dynrt
