// OBJ, PLY, FBX, Collada and assimp's other formats -> scene model, through assimp 5 (Open Asset
// Import Library, https://github.com/assimp/assimp). assimp reads the file into its own scene
// (aiScene: a node tree, meshes, materials, cameras, lights, animations); this file maps that
// onto Nodes, Objects, Cameras and Lights, the same model glTF files load into, and names every
// problem by file and object. Materials (assimp_materials), skins (assimp_skins) and
// animations (assimp_animations) live in their own files.
//
// Post-processing asked of assimp, each keeping the file's triangles exactly:
//   Triangulate            polygons into fans of triangles (triangles are left as they are);
//   JoinIdenticalVertices  corners equal in every attribute share one vertex: indices change,
//                          triangles do not, and shared vertices get smooth normals below as
//                          glTF's indexed meshes do;
//   FlipUVs                t = 1 - t: assimp's texture origin is bottom-left, the scene
//                          model's top-left (Mesh::texcoords);
//   ValidateDataStructure  assimp's own check of what its reader made.
// Not asked: GenNormals (meshes without normals get add_missing_normals, as glTF's do),
// LimitBoneWeights (it keeps 4; assimp_skins keeps 8), PreTransformVertices (nodes are kept).

#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"
#include "dynrt/scene/warnings.h"

#include "assimp_animations.h"
#include "assimp_convert.h"
#include "assimp_materials.h"
#include "assimp_skins.h"
#include "message_text.h"
#include "scene_file_kind.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <set>

namespace dynrt {

namespace {

constexpr unsigned kPostProcessing = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_FlipUVs |
                                     aiProcess_ValidateDataStructure;

bool is_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

/// Positions, normals (renormalised, as glTF's are read) and UV channel 0 of `source`.
void read_vertex_attributes(const aiMesh& source, Mesh& mesh) {
    const std::size_t vertices = source.mNumVertices;
    mesh.positions.reserve(vertices);
    for (std::size_t v = 0; v < vertices; ++v) {
        mesh.positions.emplace_back(source.mVertices[v].x, source.mVertices[v].y, source.mVertices[v].z);
    }
    if (source.mNormals != nullptr) {
        mesh.normals.reserve(vertices);
        for (std::size_t v = 0; v < vertices; ++v) {
            mesh.normals.push_back(normalize_or_zero(glm::vec3(source.mNormals[v].x, source.mNormals[v].y, source.mNormals[v].z)));
        }
    }
    if (source.mTextureCoords[0] != nullptr && source.mNumUVComponents[0] >= 2) {
        mesh.texcoords.reserve(vertices);
        for (std::size_t v = 0; v < vertices; ++v) {
            mesh.texcoords.emplace_back(source.mTextureCoords[0][v].x, source.mTextureCoords[0][v].y);
        }
    }
}

/// Turns one imported aiScene into a Scene, naming problems by file and object.
class AssimpSceneBuilder {
public:
    AssimpSceneBuilder(const std::filesystem::path& path, const aiScene& ai) : path_(path), name_(path.string()), ai_(ai) {}

    Scene build() {
        Scene scene;
        scene.source = name_;
        add_materials(scene);
        const std::vector<std::string> animated = assimp_animated_nodes(ai_);
        animated_.insert(animated.begin(), animated.end());
        add_nodes(*ai_.mRootNode, scene);
        if (shared_names_ > 0) {
            warn({.kind = cat(shared_names_, " node(s) share their name with an earlier node"),
                  .effect = "bones, animation channels, cameras and lights naming them are bound to the one "
                            "without meshes, else the first"});
        }
        // Meshes after every node: bones name nodes anywhere in the tree.
        for (std::size_t i = 0; i < ai_nodes_.size(); ++i) add_meshes(*ai_nodes_[i], std::int32_t(i), scene);
        add_cameras(scene);
        add_lights(scene);
        std::vector<Warning> warnings;
        try {
            scene.clips = read_assimp_animations(ai_, node_of_name_, warnings);
        } catch (const AssimpDataError& e) {
            fail(e.what());
        }
        for (Warning& warning : warnings) warn(std::move(warning));
        if (scene.objects.empty()) {
            fail(cat("no triangles: the file has ", ai_.mNumMeshes, " meshes and none of them has a triangle (",
                     skipped_, " skipped)"));
        }
        // Meshes without normals get area-weighted ones, as glTF's do (docs/rendering.md "Shading normals").
        add_missing_normals(scene);
        check_scene(scene);
        return scene;
    }

private:
    [[noreturn]] void fail(const std::string& what) const { throw SceneError(cat(name_, ": ", what)); }

    /// Reports a problem the loader works around (dynrt/scene/warnings.h), naming this file.
    void warn(Warning warning) const {
        warning.source = name_;
        dynrt::warn(std::move(warning));
    }

    /// dynrt's default material 0, then every assimp material (assimp_materials.h).
    void add_materials(Scene& scene) {
        scene.materials.push_back(Material{.name = "default", .diffuse = glm::vec3(0.8f)});
        AssimpMaterials materials(ai_, path_);
        std::vector<Warning> warnings;
        for (unsigned i = 0; i < ai_.mNumMaterials; ++i) scene.materials.push_back(materials.convert(i, scene, warnings));
        for (Warning& warning : warnings) warn(std::move(warning));
        for (std::string& line : materials.ignored()) scene.ignored.push_back(std::move(line));
    }

    /// Adds `root` and its subtree to Scene::nodes in depth-first pre-order (parents first),
    /// with an explicit stack: a file may nest nodes deeper than the call stack would go.
    void add_nodes(const aiNode& root, Scene& scene) {
        struct Pending {
            const aiNode* node;
            std::int32_t parent;
        };
        std::vector<Pending> stack{{&root, -1}};
        while (!stack.empty()) {
            const Pending next = stack.back();
            stack.pop_back();
            const std::int32_t index = add_node(*next.node, next.parent, scene);
            for (unsigned c = next.node->mNumChildren; c > 0; --c) stack.push_back({next.node->mChildren[c - 1], index});
        }
    }

    /// Adds `source` under Scene::nodes[parent] (-1: a root) and returns its index.
    std::int32_t add_node(const aiNode& source, std::int32_t parent, Scene& scene) {
        const auto index = static_cast<std::int32_t>(scene.nodes.size());
        Node node;
        node.name = source.mName.length > 0 ? to_string(source.mName) : cat("node", index);
        node.parent = parent;
        const glm::dmat4 local = to_dmat4(source.mTransformation);
        if (!is_finite(local)) fail(cat("node '", node.name, "': transform is not finite"));
        if (animated_.count(node.name) != 0) {
            // Channels replace translation, rotation or scale: the rest pose is kept as those.
            aiVector3D scale, translation;
            aiQuaternion rotation;
            source.mTransformation.Decompose(scale, rotation, translation);
            node.translation = to_dvec3(translation);
            node.rotation = glm::dvec4(rotation.x, rotation.y, rotation.z, rotation.w);
            node.scale = to_dvec3(scale);
            const double length2 = glm::dot(node.rotation, node.rotation);
            if (!(length2 > 0.0 && std::isfinite(length2))) {
                fail(cat("node '", node.name, "': its transform is no translation, rotation and scale"));
            }
        } else {
            node.matrix = local;
        }
        name_node(node.name, index, source.mNumMeshes > 0);
        const glm::dmat4 parent_world = parent < 0 ? glm::dmat4(1.0) : world_[std::size_t(parent)];
        world_.push_back(parent_world * node.rest_local());
        scene.nodes.push_back(std::move(node));
        ai_nodes_.push_back(&source);
        return index;
    }

    /// The meshes of scene node `index` (assimp node `source`) as objects named "node/mesh"
    /// ("node/mesh#k" for the k-th of several).
    void add_meshes(const aiNode& source, std::int32_t index, Scene& scene) {
        for (unsigned k = 0; k < source.mNumMeshes; ++k) {
            std::string name = cat(scene.nodes[std::size_t(index)].name, "/", mesh_name(source.mMeshes[k]));
            if (source.mNumMeshes > 1) name += cat("#", k);
            add_mesh(source.mMeshes[k], name, index, world_[std::size_t(index)], scene);
        }
    }

    /// Records `index` as the node `name` names. assimp links bones, animation channels,
    /// cameras and lights to nodes by name alone, and some files (glTF exporters' armatures,
    /// read back by assimp) give a mesh node and a joint the same name: then the node without
    /// meshes is the one named, as a skin's joints and animated bones are, else the first in
    /// depth-first order (as aiNode::FindNode finds it).
    void name_node(const std::string& name, std::int32_t index, bool has_meshes) {
        const auto [found, added] = node_of_name_.try_emplace(name, index);
        if (added) {
            named_with_meshes_.push_back(has_meshes);
            return;
        }
        ++shared_names_;
        named_with_meshes_.push_back(has_meshes);
        if (named_with_meshes_[std::size_t(found->second)] && !has_meshes) found->second = index;
    }

    /// The mesh's name, or "mesh<i>" when it has none.
    std::string mesh_name(unsigned mesh) const {
        if (mesh >= ai_.mNumMeshes) return cat("mesh", mesh);
        const aiString& name = ai_.mMeshes[mesh]->mName;
        return name.length > 0 ? to_string(name) : cat("mesh", mesh);
    }

    /// Mesh `index` of the assimp scene, hung on scene node `node` (rest world matrix `world`),
    /// as the object `name`: its triangles (points and lines skipped with a warning), vertex
    /// attributes, material and skin. A mesh without triangles is skipped with a warning.
    void add_mesh(unsigned index, const std::string& name, std::int32_t node, const glm::dmat4& world, Scene& scene) {
        const auto fail_object = [&](const std::string& what) { fail(cat("object '", name, "': ", what)); };
        if (index >= ai_.mNumMeshes) fail_object(cat("mesh ", index, " does not exist (", ai_.mNumMeshes, " meshes)"));
        const aiMesh& mesh = *ai_.mMeshes[index];
        Object object;
        object.name = name;
        object.node = node;
        object.transform = glm::mat4(world);
        for (int column = 0; column < 4; ++column) {
            const glm::vec4& c = object.transform[column];
            if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w)) {
                fail_object("node world transform is not finite in single precision");
            }
        }
        if (mesh.mVertices == nullptr && mesh.mNumVertices > 0) fail_object("has vertices but no positions");
        read_vertex_attributes(mesh, object.mesh);
        std::size_t points_and_lines = 0;
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices != 3) {
                ++points_and_lines;
                continue;
            }
            for (unsigned k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= mesh.mNumVertices) {
                    fail_object(cat("face ", f, ": vertex index ", face.mIndices[k], " out of range (", mesh.mNumVertices,
                                    " vertices)"));
                }
            }
            object.mesh.triangles.emplace_back(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
        }
        if (points_and_lines > 0) {
            warn({.kind = "point and line primitives skipped",
                  .item = cat("object '", name, "' (", points_and_lines, ")"),
                  .effect = "only triangles are traced"});
        }
        if (object.mesh.triangles.empty()) {
            ++skipped_;
            warn({.kind = "mesh with no triangles skipped", .kinds = "meshes with no triangles skipped",
                  .item = cat("object '", name, "'")});
            return;
        }
        if (mesh.mMaterialIndex >= ai_.mNumMaterials) {
            fail_object(cat("material ", mesh.mMaterialIndex, " does not exist (", ai_.mNumMaterials, " materials)"));
        }
        // dynrt material 0 is the default; assimp material i is dynrt material i + 1.
        object.material = mesh.mMaterialIndex + 1;
        if (mesh.mNumBones > 0) {
            std::size_t truncated = 0;
            try {
                object.skin = read_assimp_skin(mesh, name, node, node_of_name_, scene.skins, truncated);
            } catch (const AssimpDataError& e) {
                fail_object(e.what());
            }
            if (truncated > 0) {
                warn({.kind = "vertices with more than 8 bone weights",
                      .item = cat("object '", name, "' (", truncated, ")"),
                      .effect = "the 8 largest are used"});
            }
        }
        if (mesh.mNumAnimMeshes > 0) {
            scene.ignored.push_back(cat("object '", name, "': ", mesh.mNumAnimMeshes, " morph targets (not read from this format)"));
        }
        scene.objects.push_back(std::move(object));
    }

    /// The node `name` names, or -1.
    std::int32_t node_named(const aiString& name) const {
        const auto found = node_of_name_.find(to_string(name));
        return found == node_of_name_.end() ? -1 : found->second;
    }

    /// Perspective cameras. assimp places a camera in its node's space at mPosition, looking
    /// along mLookAt with mUp up; the scene model's camera sits at its node's origin looking
    /// down -Z with +Y up, so each camera hangs on a node of its own under its assimp node,
    /// whose matrix is that frame. mHorizontalFOV is the full horizontal angle (as assimp's
    /// glTF, Collada and FBX readers fill it); the vertical one follows from mAspect (1 when
    /// the file gives none).
    void add_cameras(Scene& scene) {
        for (unsigned i = 0; i < ai_.mNumCameras; ++i) {
            const aiCamera& camera = *ai_.mCameras[i];
            const std::string name = camera.mName.length > 0 ? to_string(camera.mName) : cat("camera", i);
            const std::int32_t parent = node_named(camera.mName);
            if (parent < 0) {
                warn({.kind = "camera naming no node skipped", .kinds = "cameras naming no node skipped",
                      .item = cat("camera '", name, "'")});
                continue;
            }
            if (camera.mOrthographicWidth > 0.0f) {
                warn({.kind = "orthographic camera skipped", .kinds = "orthographic cameras skipped",
                      .item = cat("camera '", name, "'"),
                      .effect = "only perspective cameras are used"});
                continue;
            }
            const glm::dvec3 look = to_dvec3(camera.mLookAt);
            const glm::dvec3 z = -normalize_or_zero(look);
            const glm::dvec3 x = normalize_or_zero(glm::cross(to_dvec3(camera.mUp), z));
            if (glm::dot(z, z) == 0.0 || glm::dot(x, x) == 0.0) {
                warn({.kind = "camera whose look-at direction is zero or along its up direction skipped",
                      .kinds = "cameras whose look-at direction is zero or along their up direction skipped",
                      .item = cat("camera '", name, "'")});
                continue;
            }
            const double aspect = camera.mAspect > 0.0f && std::isfinite(camera.mAspect) ? camera.mAspect : 0.0;
            const double yfov = 2.0 * std::atan(std::tan(0.5 * camera.mHorizontalFOV) / (aspect > 0.0 ? aspect : 1.0));
            if (!(yfov > 0.0 && yfov < M_PI)) {
                warn({.kind = "camera whose field of view is not in (0, pi) rad skipped",
                      .kinds = "cameras whose field of view is not in (0, pi) rad skipped",
                      .item = cat("camera '", name, "'"),
                      .detail = cat(camera.mHorizontalFOV, " rad")});
                continue;
            }
            Node frame;
            frame.name = cat(name, " (camera)");
            frame.parent = parent;
            frame.matrix = glm::dmat4(glm::dvec4(x, 0.0), glm::dvec4(glm::cross(z, x), 0.0), glm::dvec4(z, 0.0),
                                      glm::dvec4(to_dvec3(camera.mPosition), 1.0));
            scene.nodes.push_back(std::move(frame));
            scene.cameras.push_back(SceneCamera{.name = name,
                                                .node = static_cast<std::uint32_t>(scene.nodes.size() - 1),
                                                .yfov_rad = yfov,
                                                .aspect_ratio = aspect});
        }
    }

    /// Point, spot and directional lights, on the node of their name (posed with it every
    /// frame, as glTF's are: position and direction are the node's local ones). The colour is
    /// mColorDiffuse: its largest channel is the intensity, the colour that divided by it. A
    /// spot's cone angles are taken as measured from its axis (assimp's glTF importer gives
    /// them so; formats that mean the whole cone get a spot twice as wide), at most pi/2.
    /// Attenuation 1 / (c + l d + q d^2) is kept when it is none (1, 0, 0) or inverse-square
    /// (0, 0, q: intensity / q, with falloff); any other is dropped and listed in
    /// Scene::ignored, as are ambient and area lights.
    void add_lights(Scene& scene) {
        std::size_t left_out = 0, attenuation_dropped = 0;
        for (unsigned i = 0; i < ai_.mNumLights; ++i) {
            const aiLight& source = *ai_.mLights[i];
            const std::int32_t node = node_named(source.mName);
            const bool point = source.mType == aiLightSource_POINT, spot = source.mType == aiLightSource_SPOT;
            const bool directional = source.mType == aiLightSource_DIRECTIONAL;
            if (node < 0 || !(point || spot || directional)) {
                ++left_out;
                continue;
            }
            PointLight light;
            light.name = source.mName.C_Str();
            light.node = node;
            light.position = glm::vec3(to_dvec3(source.mPosition));
            const aiColor3D& c = source.mColorDiffuse;
            const float brightest = std::max({c.r, c.g, c.b, 0.0f});
            light.intensity = brightest;
            light.color = brightest > 0.0f ? glm::vec3(c.r, c.g, c.b) / brightest : glm::vec3(1.0f);
            if (spot || directional) {
                const glm::vec3 axis(to_dvec3(source.mDirection));
                light.direction = glm::length(axis) > 0.0f ? glm::normalize(axis) : glm::vec3(0.0f, 0.0f, -1.0f);
            }
            if (spot) {
                light.kind = PointLight::Kind::spot;
                const float half_pi = 0.5f * 3.14159265f;
                light.outer_cone = std::clamp(source.mAngleOuterCone, 0.0f, half_pi);
                light.inner_cone = std::clamp(source.mAngleInnerCone, 0.0f, light.outer_cone);
                if (light.inner_cone >= light.outer_cone) light.inner_cone = 0.999f * light.outer_cone;
            }
            if (directional) light.kind = PointLight::Kind::directional;
            if (!directional) {
                const float a0 = source.mAttenuationConstant, a1 = source.mAttenuationLinear,
                            a2 = source.mAttenuationQuadratic;
                if (a0 == 0.0f && a1 == 0.0f && a2 > 0.0f) {
                    light.inverse_square = true;
                    light.intensity /= a2;
                } else if (!(a1 == 0.0f && a2 == 0.0f)) {
                    ++attenuation_dropped;
                } else if (a0 > 0.0f) {
                    light.intensity /= a0;
                }
            }
            scene.lights.push_back(light);
        }
        if (left_out > 0) {
            scene.ignored.push_back(cat(left_out, " light(s) other than point, spot and directional lights (ambient, area)"));
        }
        if (attenuation_dropped > 0) {
            scene.ignored.push_back(cat("distance attenuation of ", attenuation_dropped,
                                        " light(s) other than none or inverse-square (lit without falloff)"));
        }
    }

    std::filesystem::path path_;
    std::string name_;
    const aiScene& ai_;
    std::set<std::string> animated_;
    AssimpNodeNames node_of_name_;
    /// By Scene::nodes index: whether the node has meshes (see name_node).
    std::vector<bool> named_with_meshes_;
    std::size_t shared_names_ = 0;
    /// Rest-pose world matrix and assimp node of each node added by add_node, by Scene::nodes
    /// index.
    std::vector<glm::dmat4> world_;
    std::vector<const aiNode*> ai_nodes_;
    std::size_t skipped_ = 0;
};

}  // namespace

Scene load_assimp(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw SceneError(cat(path.string(), ": no such file"));
    if (std::filesystem::is_directory(path, ec)) throw SceneError(cat(path.string(), ": is a folder, not a scene file"));
    if (std::filesystem::file_size(path, ec) == 0) throw SceneError(cat(path.string(), ": empty file"));
    Assimp::Importer importer;
    const aiScene* ai = importer.ReadFile(path.string(), kPostProcessing);
    if (ai == nullptr) {
        const std::string error = importer.GetErrorString();
        if (error.find("No suitable reader") != std::string::npos) {
            throw SceneError(cat(path.string(), ": not a scene file dynrt reads (", kSceneFormatsRead, ")"));
        }
        throw SceneError(cat(path.string(), ": assimp: ", error.empty() ? "could not read the file" : error));
    }
    if (ai->mRootNode == nullptr) throw SceneError(cat(path.string(), ": no node tree (assimp read no scene)"));
    return AssimpSceneBuilder(path, *ai).build();
}

}  // namespace dynrt
