// glTF 2.0 -> scene model. Reading the file (gltf_file), walking the node tree
// (gltf_node_tree), reading accessors (gltf_accessors), assembling strips and fans
// (triangle_assembly), skins (gltf_skins), morph targets (gltf_morph_targets), cameras
// (gltf_cameras) and animations (gltf_animations) live in their own files; this one maps glTF
// nodes, primitives and materials onto Nodes, Objects and Materials and names every problem by
// file and object.

#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"
#include "dynrt/scene/warnings.h"

#include "dynrt/anim/morphing.h"

#include "gltf_accessors.h"
#include "gltf_animations.h"
#include "gltf_cameras.h"
#include "gltf_lights.h"
#include "gltf_data_error.h"
#include "gltf_file.h"
#include "gltf_morph_targets.h"
#include "gltf_node_tree.h"
#include "gltf_skins.h"
#include "message_text.h"
#include "read_files.h"
#include "triangle_assembly.h"

#include <algorithm>
#include <functional>
#include <filesystem>
#include <map>
#include <cmath>
#include <numeric>
#include <optional>
#include <unordered_map>

namespace dynrt {

namespace {

constexpr float kDefaultGrey = 0.8f;
constexpr const char* kTransmission = "KHR_materials_transmission";
constexpr const char* kIor = "KHR_materials_ior";
constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";
/// glTF's index of refraction where KHR_materials_ior does not give one.
constexpr double kGltfDefaultIor = 1.5;

/// A number of a material extension (`extension.key`), or `fallback` when the extension, the key
/// or a finite number is missing.
double extension_number(const tinygltf::Material& source, const char* extension, const char* key,
                        double fallback) {
    const auto found = source.extensions.find(extension);
    if (found == source.extensions.end() || !found->second.IsObject() || !found->second.Has(key)) return fallback;
    const tinygltf::Value& value = found->second.Get(key);
    if (!value.IsNumber()) return fallback;
    const double number = value.GetNumberAsDouble();
    return std::isfinite(number) ? number : fallback;
}

bool has_extension(const tinygltf::Material& source, const char* extension) {
    return source.extensions.find(extension) != source.extensions.end();
}

/// Whether KHR_materials_transmission gives a transmissionTexture (which dynrt ignores).
bool has_transmission_texture(const tinygltf::Material& source) {
    const auto found = source.extensions.find(kTransmission);
    return found != source.extensions.end() && found->second.IsObject() &&
           found->second.Has("transmissionTexture");
}

/// glTF's alpha (alphaMode, alphaCutoff, baseColorFactor's alpha a, the base colour
/// texture's alpha) on `material`, already converted from `source` as if opaque:
///   OPAQUE  alpha is ignored, as the specification says;
///   MASK    a cut-out (Material::alpha_cutoff, dynrt/engine/alpha_mask.h): where a times
///           the texture's alpha is below alphaCutoff the surface is not there;
///   BLEND   the surface covers a of what is behind it: every term it shades with (diffuse,
///           specular, reflection, emission) times a, and the rest, 1 - a, let through
///           unrefracted (transmittance + 1 - a, ior 1 when the material had none), so that
///           a pixel shows a times the surface plus 1 - a times what is behind it, and a
///           shadow through it keeps 1 - a of the light (Whitted's transmission with a
///           straight ray: it needs secondary rays, --depth >= 1). A base colour texture's
///           alpha, which would vary that cover across the surface, is applied as a cut-out
///           at 1/2 instead (note_ignored says so).
void convert_alpha(const tinygltf::Material& source, Material& material) {
    const std::vector<double>& factor = source.pbrMetallicRoughness.baseColorFactor;
    const double a = factor.size() >= 4 && std::isfinite(factor[3]) ? std::clamp(factor[3], 0.0, 1.0) : 1.0;
    if (source.alphaMode == "MASK") {
        material.base_alpha = static_cast<float>(a);
        material.alpha_cutoff = static_cast<float>(source.alphaCutoff);
    } else if (source.alphaMode == "BLEND") {
        const auto cover = static_cast<float>(a);
        material.diffuse *= cover;
        material.specular *= cover;
        material.reflectance *= cover;
        material.emission *= cover;
        if (material.transmittance == glm::vec3(0.0f)) material.ior = 1.0f;
        material.transmittance = cover * material.transmittance + glm::vec3(1.0f - cover);
        if (source.pbrMetallicRoughness.baseColorTexture.index >= 0) material.alpha_cutoff = 0.5f;
    }
}

/// Phong and Whitted parameters from glTF metallic-roughness, a deliberately simple mapping
/// (dynrt shades with Phong plus mirror and refraction rays; of the textures it reads only
/// baseColorTexture, mapped by GltfSceneBuilder::map_base_color). With
/// base = baseColorFactor.rgb (linear, clamped to [0, 1]; default 1), metallic and roughness
/// their factors (clamped to [0, 1]; default 1 both) and transmission
/// KHR_materials_transmission's transmissionFactor (clamped to [0, 1]; 0 without it):
///   diffuse       = base * (1 - transmission): light goes through, not scattered;
///   specular      = grey 0.2 * (1 - roughness / 2): 0.2 for a mirror-smooth surface, 0.1 for
///                   a fully rough one (glTF's default roughness is 1);
///   shininess     = 2 / alpha^2 - 2 with alpha = roughness^2, the Blinn-Phong exponent
///                   matching a Beckmann lobe (Walter et al. 2007, "Microfacet Models for
///                   Refraction through Rough Surfaces"), clamped to [8, 128] so rough surfaces
///                   keep a broad highlight;
///   reflectance   = metallic * base * (1 - roughness)^2: a smooth metal is a mirror, rough or
///                   dielectric surfaces reflect no ray;
///   transmittance = transmission * (1 - metallic) * base: a metal lets nothing through;
///   ior           = KHR_materials_ior's ior (default 1.5) when the material has either
///                   extension, else 1 (an opaque material never refracts). A value <= 0 is
///                   passed on for check_scene to refuse, naming the material;
///   emission      = emissiveFactor (each channel clamped to [0, 1]) times
///                   KHR_materials_emissive_strength's emissiveStrength (default 1), times
///                   emissiveTexture's colour where it gives one (map_base_color).
/// The other textures, transmissionTexture included, are ignored (listed in Scene::ignored).
/// Alpha: convert_alpha.
Material convert_material(const tinygltf::Material& source, std::size_t index) {
    Material material;
    material.name = source.name.empty() ? cat("material", index) : source.name;
    const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    glm::vec3 base(1.0f);
    if (pbr.baseColorFactor.size() >= 3) {
        for (int c = 0; c < 3; ++c) {
            const double value = pbr.baseColorFactor[static_cast<std::size_t>(c)];
            base[c] = std::isfinite(value) ? static_cast<float>(std::clamp(value, 0.0, 1.0)) : 1.0f;
        }
    }
    const double roughness =
        std::isfinite(pbr.roughnessFactor) ? std::clamp(pbr.roughnessFactor, 0.0, 1.0) : 1.0;
    const double metallic = std::isfinite(pbr.metallicFactor) ? std::clamp(pbr.metallicFactor, 0.0, 1.0) : 1.0;
    const double transmission =
        std::clamp(extension_number(source, kTransmission, "transmissionFactor", 0.0), 0.0, 1.0);
    material.diffuse = base * static_cast<float>(1.0 - transmission);
    material.specular = glm::vec3(static_cast<float>(0.2 * (1.0 - 0.5 * roughness)));
    const double alpha_squared = std::pow(roughness, 4.0);
    const double shininess = alpha_squared > 0.0 ? 2.0 / alpha_squared - 2.0 : 128.0;
    material.shininess = static_cast<float>(std::clamp(shininess, 8.0, 128.0));
    material.reflectance = base * static_cast<float>(metallic * (1.0 - roughness) * (1.0 - roughness));
    material.transmittance = base * static_cast<float>(transmission * (1.0 - metallic));
    if (has_extension(source, kTransmission) || has_extension(source, kIor)) {
        material.ior = static_cast<float>(extension_number(source, kIor, "ior", kGltfDefaultIor));
    }
    // Emission: the factor (each channel clamped to [0, 1], as the spec bounds it) times the
    // strength (a strength that is negative or not finite is refused by check_scene, naming
    // the material).
    const double strength = extension_number(source, kEmissiveStrength, "emissiveStrength", 1.0);
    for (int c = 0; c < 3 && c < int(source.emissiveFactor.size()); ++c) {
        const double factor = source.emissiveFactor[std::size_t(c)];
        material.emission[c] = static_cast<float>((std::isfinite(factor) ? std::clamp(factor, 0.0, 1.0) : 0.0) * strength);
    }
    convert_alpha(source, material);
    return material;
}

const char* mode_name(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS:
            return "POINTS";
        case TINYGLTF_MODE_LINE:
            return "LINES";
        case TINYGLTF_MODE_LINE_LOOP:
            return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP:
            return "LINE_STRIP";
        case TINYGLTF_MODE_TRIANGLES:
            return "TRIANGLES";
        case TINYGLTF_MODE_TRIANGLE_STRIP:
            return "TRIANGLE_STRIP";
        case TINYGLTF_MODE_TRIANGLE_FAN:
            return "TRIANGLE_FAN";
        default:
            return "unknown";
    }
}

std::optional<TriangleTopology> topology_of(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_TRIANGLES:
            return TriangleTopology::list;
        case TINYGLTF_MODE_TRIANGLE_STRIP:
            return TriangleTopology::strip;
        case TINYGLTF_MODE_TRIANGLE_FAN:
            return TriangleTopology::fan;
        default:
            return std::nullopt;
    }
}

/// Turns the primitives of one glTF file into Objects, naming problems by file and object.
class GltfSceneBuilder {
public:
    /// `name` is the file's path, or the name of a document loaded from memory.
    GltfSceneBuilder(const std::string& name, const tinygltf::Model& model) : name_(name), model_(model) {}

    /// The scene. `done_reading`, when given, is called once the document's bytes are no longer
    /// read (before the missing normals are made), so that the caller may free its buffers.
    Scene build(const std::function<void()>& done_reading = {}) {
        Scene scene;
        scene.source = name_;
        scene.materials.push_back(Material{.name = "default", .diffuse = glm::vec3(kDefaultGrey)});
        for (std::size_t i = 0; i < model_.materials.size(); ++i) {
            scene.materials.push_back(convert_material(model_.materials[i], i));
            check_alpha(model_.materials[i], scene.materials.back().name);
            map_base_color(model_.materials[i], scene.materials.back(), scene);
        }
        note_ignored(scene);

        std::vector<GltfNodeInstance> instances;
        try {
            instances = flatten_node_tree(model_);
        } catch (const GltfDataError& e) {
            fail(e.what());
        }
        std::vector<int> scene_node_of(model_.nodes.size(), -1);
        for (std::size_t i = 0; i < instances.size(); ++i) {
            scene_node_of[static_cast<std::size_t>(instances[i].node)] = static_cast<int>(i);
            // flatten_node_tree has already read (and checked) every one of these nodes.
            Node node = gltf_scene_node(model_.nodes[static_cast<std::size_t>(instances[i].node)]);
            node.name = gltf_node_name(model_, instances[i].node);
            node.parent = instances[i].parent;
            scene.nodes.push_back(std::move(node));
        }
        GltfSkins skins(model_, scene_node_of);
        for (std::size_t i = 0; i < instances.size(); ++i) add_node(i, instances[i], skins, scene);

        std::vector<Warning> warnings;
        try {
            scene.cameras = read_cameras(model_, instances, warnings);
            scene.lights = read_lights(model_, instances);
            scene.clips = read_animations(model_, scene_node_of, warnings);
        } catch (const GltfDataError& e) {
            fail(e.what());
        }
        for (Warning& warning : warnings) warn(std::move(warning));

        if (scene.objects.empty()) {
            fail(cat("no triangles: the default scene has no triangle primitive (", skipped_,
                     " other primitives skipped)"));
        }
        // Primitives without NORMAL get area-weighted ones. glTF 2.0 section 3.7.2.1 asks for
        // flat normals there; dynrt smooths shared vertices instead (docs/rendering.md "Shading normals"),
        // and `--normals flat` gives the specification's flat shading.
        if (done_reading) done_reading();
        add_missing_normals(scene);
        check_scene(scene);
        return scene;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw SceneError(cat(name_, ": ", what));
    }

    [[noreturn]] void fail_object(const std::string& object, const std::string& what) const {
        fail(cat("object '", object, "': ", what));
    }

    /// Refuses alpha the specification does not allow, naming the material: an alphaMode other
    /// than OPAQUE, MASK and BLEND, or a MASK's alphaCutoff outside [0, 1].
    void check_alpha(const tinygltf::Material& source, const std::string& name) const {
        const std::string& mode = source.alphaMode;
        if (mode != "OPAQUE" && mode != "MASK" && mode != "BLEND") {
            fail(cat("material '", name, "': alphaMode '", mode, "' is not OPAQUE, MASK or BLEND"));
        }
        const double cutoff = source.alphaCutoff;
        if (mode == "MASK" && !(cutoff >= 0.0 && cutoff <= 1.0)) {
            fail(cat("material '", name, "': alphaCutoff ", cutoff, " must be in [0, 1]"));
        }
    }

    /// Reports a problem the loader works around (dynrt/scene/warnings.h), naming this file.
    void warn(Warning warning) const {
        warning.source = name_;
        dynrt::warn(std::move(warning));
    }

    /// A primitive left out: `kind` says why, in the same words for every such primitive.
    void skip_primitive(const std::string& object, const std::string& kind, const std::string& kinds,
                        const std::string& detail = {}) {
        ++skipped_;
        warn({.kind = kind, .kinds = kinds, .item = cat("object '", object, "'"), .detail = detail});
    }

    /// Adds the primitives of scene node `scene_node`, the instance `instance`.
    void add_node(std::size_t scene_node, const GltfNodeInstance& instance, GltfSkins& skins, Scene& scene) {
        const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(instance.node)];
        const std::string node_name = gltf_node_name(model_, instance.node);
        if (node.skin >= 0 && node.mesh < 0) fail(cat("node '", node_name, "': has a skin but no mesh"));
        if (node.mesh < 0) return;
        if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size()) {
            fail(cat("node '", node_name, "': mesh ", node.mesh, " does not exist (", model_.meshes.size(),
                     " meshes)"));
        }
        const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(node.mesh)];
        const std::string mesh_name = mesh.name.empty() ? cat("mesh", node.mesh) : mesh.name;
        std::optional<std::uint32_t> skin;
        if (node.skin >= 0) {
            try {
                skin = skins.use(node.skin, scene.skins);
            } catch (const GltfDataError& e) {
                fail(cat("node '", node_name, "': ", e.what()));
            }
        }
        const PrimitiveOwner owner{node, mesh, static_cast<std::int32_t>(scene_node), glm::mat4(instance.world), skin};
        for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
            std::string name = cat(node_name, "/", mesh_name);
            if (mesh.primitives.size() > 1) name += cat("#", k);
            add_primitive(mesh.primitives[k], name, owner, skins, scene);
        }
    }

    /// What a primitive takes from the node and mesh it belongs to.
    struct PrimitiveOwner {
        const tinygltf::Node& node;
        const tinygltf::Mesh& mesh;
        std::int32_t scene_node;
        glm::mat4 transform;
        /// Scene::skins index when the node is skinned.
        std::optional<std::uint32_t> skin;
    };

    void add_primitive(const tinygltf::Primitive& primitive, const std::string& name, const PrimitiveOwner& owner,
                       const GltfSkins& skins, Scene& scene) {
        const glm::mat4& transform = owner.transform;
        const std::optional<TriangleTopology> topology = topology_of(primitive.mode);
        if (!topology) {
            skip_primitive(name, cat(mode_name(primitive.mode), " primitive skipped (mode ", primitive.mode,
                                     "): only triangles are traced"),
                           cat(mode_name(primitive.mode), " primitives skipped (mode ", primitive.mode,
                               "): only triangles are traced"));
            return;
        }
        const auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) {
            skip_primitive(name, "primitive without POSITION skipped", "primitives without POSITION skipped");
            return;
        }

        Object object;
        object.name = name;
        object.transform = transform;
        object.node = owner.scene_node;
        try {
            // A primitive that another node's instance read already: its arrays are shared
            // (Mesh, SharedArray), so a mesh many nodes reference is held once. Morph targets
            // shape a mesh by its node's weights, so morphed primitives are read per node.
            const bool morphed = !primitive.targets.empty();
            if (const auto read = meshes_read_.find(&primitive); !morphed && read != meshes_read_.end()) {
                object.mesh = read->second;
            } else {
                read_mesh(primitive, position->second, *topology, name, owner, object);
                if (!morphed) meshes_read_.emplace(&primitive, object.mesh);
            }
            if (owner.skin) {
                object.skin = skins.read_weights(primitive, *owner.skin, scene.skins, object.mesh.positions.size());
                if (primitive.attributes.count("JOINTS_2") != 0) {
                    warn({.kind = "skin with more than 8 influences per vertex",
                          .kinds = "skins with more than 8 influences per vertex",
                          .item = cat("object '", name, "'"),
                          .effect = "only JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1 are used"});
                }
            }
        } catch (const GltfDataError& e) {
            fail_object(name, e.what());
        }
        if (object.mesh.triangles.empty()) {
            skip_primitive(name, "primitive with no triangles skipped", "primitives with no triangles skipped");
            return;
        }

        if (primitive.material >= 0) {
            if (static_cast<std::size_t>(primitive.material) >= model_.materials.size()) {
                fail_object(name, cat("material ", primitive.material, " does not exist (",
                                      model_.materials.size(), " materials)"));
            }
            // dynrt material 0 is the default; glTF material i is dynrt material i + 1.
            object.material = static_cast<std::uint32_t>(primitive.material) + 1;
        }
        for (int column = 0; column < 4; ++column) {
            const glm::vec4& c = transform[column];
            if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) {
                fail_object(name, "node world transform is not finite in single precision");
            }
        }
        scene.objects.push_back(std::move(object));
    }

    /// Reads the primitive's morph targets into `object`, with mesh.positions (and normals)
    /// morphed by the default weights (in double, rounded once) so unanimated code sees the
    /// morphed shape.
    void add_morph_targets(const tinygltf::Primitive& primitive, const PrimitiveOwner& owner, Object& object) const {
        object.morph = read_morph_targets(model_, owner.node, owner.mesh, primitive, object.mesh.positions,
                                          object.mesh.normals);
        if (!object.morph) return;
        std::vector<glm::vec3>& positions = object.mesh.positions.edit();
        for (std::size_t v = 0; v < positions.size(); ++v) {
            positions[v] = glm::vec3(anim::morphed_position(*object.morph, object.morph->default_weights, v));
        }
        if (object.morph->normal_deltas.empty()) return;
        std::vector<glm::vec3>& normals = object.mesh.normals.edit();
        for (std::size_t v = 0; v < normals.size(); ++v) {
            normals[v] = glm::vec3(anim::morphed_normal(*object.morph, object.morph->default_weights, v));
        }
    }

    /// The primitive's vertices, corners, normals, morph targets and texture coordinates, into
    /// `object`'s mesh.
    void read_mesh(const tinygltf::Primitive& primitive, int position_accessor, TriangleTopology topology,
                   const std::string& name, const PrimitiveOwner& owner, Object& object) {
        object.mesh.positions = read_shared(positions_read_, {position_accessor, 0},
                                            [&] { return read_positions(model_, position_accessor); });
        const std::size_t vertices = object.mesh.positions.size();
        if (primitive.indices >= 0 && topology == TriangleTopology::list) {
            // The common case read straight into triangles: a big mesh's indices held once.
            object.mesh.triangles = read_shared(triples_read_, {primitive.indices, vertices}, [&] {
                return read_index_triples(model_, primitive.indices, vertices);
            });
        } else {
            std::vector<std::uint32_t> indices;
            if (primitive.indices >= 0) {
                indices = read_indices(model_, primitive.indices, object.mesh.positions.size());
            } else {
                indices.resize(object.mesh.positions.size());
                std::iota(indices.begin(), indices.end(), 0u);
            }
            object.mesh.triangles = assemble_triangles(topology, indices);
        }
        // NORMAL (glTF 2.0 section 3.7.2.1): unit vectors, renormalised as read (quantised
        // ones are not exactly unit). Without it add_missing_normals computes them below.
        if (const auto normal = primitive.attributes.find("NORMAL"); normal != primitive.attributes.end()) {
            object.mesh.normals = read_shared(normals_read_, {normal->second, vertices}, [&] {
                std::vector<glm::vec3> normals = read_vec3_attribute(model_, normal->second, vertices, "NORMAL");
                for (glm::vec3& n : normals) n = normalize_or_zero(n);
                return normals;
            });
        }
        add_morph_targets(primitive, owner, object);
        read_texcoords(primitive, name, object);
    }

    /// TEXCOORD_0 (glTF 2.0 section 3.7.2.1: FLOAT, or normalised UNSIGNED_BYTE or
    /// UNSIGNED_SHORT), when the primitive has it. A malformed one is dropped with a warning:
    /// the object is then drawn without its texture rather than refused.
    void read_texcoords(const tinygltf::Primitive& primitive, const std::string& name, Object& object) {
        const auto texcoord = primitive.attributes.find("TEXCOORD_0");
        if (texcoord == primitive.attributes.end()) return;
        const std::size_t vertices = object.mesh.positions.size();
        try {
            const std::vector<double> st =
                read_numbers(model_, texcoord->second, TINYGLTF_TYPE_VEC2, NormalizedIntegers::unsigned_only);
            if (st.size() != 2 * vertices) {
                throw GltfDataError(cat("has ", st.size() / 2, " elements for ", vertices, " positions"));
            }
            std::vector<glm::vec2>& texcoords = object.mesh.texcoords.edit();
            texcoords.resize(vertices);
            for (std::size_t v = 0; v < vertices; ++v) {
                texcoords[v] = glm::vec2(float(st[2 * v]), float(st[2 * v + 1]));
            }
        } catch (const GltfDataError& e) {
            object.mesh.texcoords.clear();
            warn({.kind = "TEXCOORD_0 unreadable",
                  .item = cat("object '", name, "'"),
                  .detail = e.what(),
                  .effect = "drawn without texture coordinates"});
        }
    }

    /// The scene texture for glTF image `image` (added on first use): its file, relative to
    /// the document's folder, or its bytes (a data: URI, or a bufferView).
    std::uint32_t texture_of(int image, Scene& scene) {
        const auto [found, added] = texture_of_image_.try_emplace(image, std::uint32_t(scene.textures.size()));
        if (!added) return found->second;
        const tinygltf::Image& source = model_.images[static_cast<std::size_t>(image)];
        Texture texture;
        texture.mime_type = source.mimeType;
        if (!source.uri.empty()) {
            texture.path = (std::filesystem::path(name_).parent_path() / source.uri).string();
            texture.name = texture.path;
        } else {
            texture.name = cat(name_, " image ", image, source.name.empty() ? "" : cat(" '", source.name, "'"));
            if (source.bufferView >= 0) {
                try {
                    texture.encoded = read_buffer_view(model_, source.bufferView);
                } catch (const GltfDataError& e) {
                    // The texture then reads as broken, and the renderer says so per material.
                    warn({.kind = "image unreadable", .kinds = "images unreadable",
                          .item = cat("image ", image), .detail = e.what()});
                }
            } else {
                texture.encoded = source.image;
            }
        }
        scene.textures.push_back(std::move(texture));
        return found->second;
    }

    /// Maps the material's baseColorTexture (glTF 2.0 section 3.9.2: sRGB texels multiplying
    /// baseColorFactor, through TEXCOORD_0) with its sampler's wrap modes. Only TEXCOORD_0 is
    /// read: a texture on another set is left out, with a warning.
    void map_base_color(const tinygltf::Material& source, Material& material, Scene& scene) {
        material.diffuse_map = texture_map(source.pbrMetallicRoughness.baseColorTexture, "baseColorTexture",
                                           "the base colour factor alone is used", material, scene);
        // The emission map only matters where the factor is not 0.
        if (material.emission != glm::vec3(0.0f)) {
            material.emission_map = texture_map(source.emissiveTexture, "emissiveTexture",
                                                "the emissive factor alone is used", material, scene);
        }
    }

    /// The map `info` gives (`slot` names it in messages; `effect` says what is used instead
    /// when it cannot be read), or none.
    std::optional<TextureMap> texture_map(const tinygltf::TextureInfo& info, const char* slot, const char* effect,
                                          const Material& material, Scene& scene) {
        if (info.index < 0) return std::nullopt;
        if (static_cast<std::size_t>(info.index) >= model_.textures.size()) {
            fail(cat("material '", material.name, "': ", slot, " ", info.index, " does not exist (",
                     model_.textures.size(), " textures)"));
        }
        const tinygltf::Texture& texture = model_.textures[static_cast<std::size_t>(info.index)];
        if (texture.source < 0 || static_cast<std::size_t>(texture.source) >= model_.images.size()) {
            warn({.kind = "texture without an image dynrt can read (no 'source')",
                  .kinds = "textures without an image dynrt can read (no 'source')",
                  .item = cat("texture ", info.index),
                  .user = cat("material '", material.name, "'"),
                  .users = "materials",
                  .effect = effect});
            return std::nullopt;
        }
        if (info.texCoord != 0) {
            warn({.kind = cat(slot, " on TEXCOORD_", info.texCoord, " (only TEXCOORD_0 is read)"),
                  .item = cat("material '", material.name, "'"),
                  .effect = effect});
            return std::nullopt;
        }
        TextureMap map;
        map.texture = texture_of(texture.source, scene);
        if (texture.sampler >= 0 && static_cast<std::size_t>(texture.sampler) < model_.samplers.size()) {
            const tinygltf::Sampler& sampler = model_.samplers[static_cast<std::size_t>(texture.sampler)];
            map.wrap_s = wrap_of(sampler.wrapS);
            map.wrap_t = wrap_of(sampler.wrapT);
        }
        return map;
    }

    static TextureWrap wrap_of(int mode) {
        switch (mode) {
            case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
                return TextureWrap::clamp;
            case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
                return TextureWrap::mirror;
            default:
                return TextureWrap::repeat;
        }
    }

    std::string name_;
    std::map<int, std::uint32_t> texture_of_image_;
    /// What the file says that dynrt leaves out, one line each in Scene::ignored (as BART's
    /// loader does): textures other than baseColorTexture and emissiveTexture
    /// (transmissionTexture included; the factors are used), a BLEND material's texture alpha
    /// (convert_alpha), and the extensions the file requires or uses but dynrt does not
    /// implement (all but KHR_materials_transmission, KHR_materials_ior and
    /// KHR_materials_emissive_strength, which convert_material maps, and KHR_lights_punctual,
    /// which read_lights reads).
    void note_ignored(Scene& scene) const {
        std::size_t textured = 0;
        for (const tinygltf::Material& m : model_.materials) {
            const bool any = m.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0 ||
                             m.normalTexture.index >= 0 || m.occlusionTexture.index >= 0 ||
                             has_transmission_texture(m);
            textured += any ? 1 : 0;
        }
        if (textured > 0) {
            scene.ignored.push_back(cat("textures other than base colour and emission of ", textured,
                                        " material(s) (metal, roughness and transmission from their factors)"));
        }
        // What of alpha is approximated (convert_alpha): a BLEND material's texture alpha.
        std::size_t varying = 0;
        for (const tinygltf::Material& m : model_.materials) {
            varying += m.alphaMode == "BLEND" && m.pbrMetallicRoughness.baseColorTexture.index >= 0 ? 1 : 0;
        }
        if (varying > 0) {
            scene.ignored.push_back(cat("partial cover from the base colour texture's alpha of ", varying,
                                        " BLEND material(s) (cut out where below 1/2)"));
        }
        // The material extensions convert_material maps are not "left out".
        const auto implemented = [](const std::string& extension) {
            return extension == kTransmission || extension == kIor || extension == kEmissiveStrength ||
                   extension == "KHR_lights_punctual";
        };
        for (const std::string& extension : model_.extensionsRequired) {
            if (implemented(extension)) continue;
            scene.ignored.push_back(cat("required extension ", extension, " (not implemented; rendered without it)"));
        }
        for (const std::string& extension : model_.extensionsUsed) {
            const bool required = std::find(model_.extensionsRequired.begin(), model_.extensionsRequired.end(),
                                            extension) != model_.extensionsRequired.end();
            if (!required && !implemented(extension)) {
                scene.ignored.push_back(cat("extension ", extension, " (not implemented)"));
            }
        }
    }

    const tinygltf::Model& model_;
    std::size_t skipped_ = 0;
    /// The mesh of every primitive read so far without morph targets: a later node that
    /// references the same glTF mesh shares its arrays.
    std::unordered_map<const tinygltf::Primitive*, Mesh> meshes_read_;
    /// Arrays read so far, by accessor and the vertex count they were checked against:
    /// primitives of different glTF meshes that read the same accessors share them too
    /// (MetalRoughSpheresNoTextures' 102 meshes are one sphere's vertices and indices), so
    /// they are held once and a trace reading them through compact leaves finds them cached.
    using AccessorKey = std::pair<int, std::size_t>;
    std::map<AccessorKey, SharedArray<glm::vec3>> positions_read_, normals_read_;
    std::map<AccessorKey, SharedArray<glm::uvec3>> triples_read_;

    /// The array `read` makes of an accessor, read once per `key`.
    template <class T, class Read>
    static SharedArray<T> read_shared(std::map<AccessorKey, SharedArray<T>>& arrays, AccessorKey key,
                                      Read&& read) {
        if (const auto found = arrays.find(key); found != arrays.end()) return found->second;
        SharedArray<T> array(read());
        arrays.emplace(key, array);
        return array;
    }
};

}  // namespace

Scene load_gltf(const std::filesystem::path& path) {
    tinygltf::Model model = read_gltf_model(path);
    // A big file's buffers are let go before the normals are made beside the scene's arrays.
    Scene scene = GltfSceneBuilder(path.string(), model).build([&model] {
        for (tinygltf::Buffer& buffer : model.buffers) std::vector<unsigned char>().swap(buffer.data);
    });
    // Buffers in files of their own, resolved as tinygltf did (beside the document).
    std::vector<std::string> read{path.string()};
    for (const tinygltf::Buffer& buffer : model.buffers) {
        if (!buffer.uri.empty() && buffer.uri.rfind("data:", 0) != 0) {
            read.push_back((path.parent_path() / buffer.uri).string());
        }
    }
    set_read_files(scene, read);
    return scene;
}

Scene load_gltf_from_memory(std::span<const unsigned char> bytes, GltfFormat format, const std::string& name) {
    const tinygltf::Model model = read_gltf_model_from_memory(bytes, format, name);
    return GltfSceneBuilder(name, model).build();
}

}  // namespace dynrt
