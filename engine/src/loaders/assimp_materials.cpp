// aiMaterial -> Material: a Phong model already (OBJ's Kd/Ks/Ns/d/Ni, Collada's <phong>, FBX's
// Lambert and Phong), so the mapping is direct; only transparency is turned into dynrt's
// Whitted transmission (docs/scene-input.md "Materials").

#include "assimp_materials.h"

#include "assimp_convert.h"
#include "message_text.h"

#include <assimp/material.h>

#include <algorithm>
#include <cmath>

namespace dynrt {

namespace {

constexpr float kDefaultGrey = 0.8f;
/// The index of refraction of a transparent material that gives none (glTF's default too).
constexpr float kDefaultIor = 1.5f;

/// Each channel of `c` clamped to [0, 1]; a non-finite channel is `fallback`.
glm::vec3 clamped(const aiColor3D& c, float fallback) {
    const auto one = [&](float x) { return std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : fallback; };
    return {one(c.r), one(c.g), one(c.b)};
}

bool get_color(const aiMaterial& m, const char* key, unsigned type, unsigned index, aiColor3D& out) {
    return m.Get(key, type, index, out) == aiReturn_SUCCESS;
}

bool get_float(const aiMaterial& m, const char* key, unsigned type, unsigned index, float& out) {
    return m.Get(key, type, index, out) == aiReturn_SUCCESS && std::isfinite(out);
}

TextureWrap wrap_of(int mode) {
    switch (mode) {
        case aiTextureMapMode_Clamp:
        case aiTextureMapMode_Decal:
            return TextureWrap::clamp;
        case aiTextureMapMode_Mirror:
            return TextureWrap::mirror;
        default:
            return TextureWrap::repeat;
    }
}

/// The texture types read as a colour map, in order of preference.
constexpr aiTextureType kDiffuseTypes[] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR};

}  // namespace

AssimpMaterials::AssimpMaterials(const aiScene& scene, const std::filesystem::path& scene_file)
    : scene_(scene), folder_(scene_file.parent_path()), name_(scene_file.string()) {}

Material AssimpMaterials::convert(unsigned index, Scene& scene, std::vector<Warning>& warnings) {
    const aiMaterial& source = *scene_.mMaterials[index];
    Material material;
    aiString name;
    material.name = source.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS && name.length > 0 ? to_string(name)
                                                                                            : cat("material", index);
    float opacity = 1.0f;
    if (get_float(source, AI_MATKEY_OPACITY, opacity)) opacity = std::clamp(opacity, 0.0f, 1.0f);
    aiColor3D color;
    material.diffuse = glm::vec3(kDefaultGrey);
    if (get_color(source, AI_MATKEY_COLOR_DIFFUSE, color)) material.diffuse = clamped(color, kDefaultGrey);
    material.diffuse *= opacity;
    if (get_color(source, AI_MATKEY_COLOR_SPECULAR, color)) {
        float strength = 1.0f;
        get_float(source, AI_MATKEY_SHININESS_STRENGTH, strength);
        material.specular = glm::clamp(clamped(color, 0.2f) * std::max(strength, 0.0f), 0.0f, 1.0f);
    }
    float shininess = 0.0f;
    if (get_float(source, AI_MATKEY_SHININESS, shininess)) material.shininess = std::clamp(shininess, 1.0f, 128.0f);
    float reflectivity = 0.0f;
    if (get_color(source, AI_MATKEY_COLOR_REFLECTIVE, color) && get_float(source, AI_MATKEY_REFLECTIVITY, reflectivity)) {
        material.reflectance = glm::clamp(clamped(color, 0.0f) * std::max(reflectivity, 0.0f), 0.0f, 1.0f);
    }
    if (opacity < 1.0f) {
        material.transmittance = glm::vec3(1.0f - opacity);
        float ior = kDefaultIor;
        if (source.Get(AI_MATKEY_REFRACTI, ior) != aiReturn_SUCCESS) ior = kDefaultIor;
        material.ior = ior;
    }

    for (const aiTextureType type : kDiffuseTypes) {
        if (source.GetTextureCount(type) == 0) continue;
        aiString path;
        aiTextureMapMode wrap[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
        unsigned uv_channel = 0;
        if (source.GetTexture(type, 0, &path, nullptr, &uv_channel, nullptr, nullptr, wrap) != aiReturn_SUCCESS) break;
        if (uv_channel != 0) {
            warnings.push_back({.kind = cat("diffuse texture on UV channel ", uv_channel, " (only channel 0 is read)"),
                                .item = cat("material '", material.name, "'"),
                                .effect = "the diffuse colour is used alone"});
            break;
        }
        const aiTexture* embedded = scene_.GetEmbeddedTexture(path.C_Str());
        if (embedded != nullptr && embedded->mHeight != 0) {
            warnings.push_back({.kind = "diffuse texture embedded uncompressed, which dynrt does not read",
                                .kinds = "diffuse textures embedded uncompressed, which dynrt does not read",
                                .item = cat("material '", material.name, "'"),
                                .detail = embedded->achFormatHint,
                                .effect = "the diffuse colour is used alone"});
            break;
        }
        TextureMap map;
        map.texture = texture_of(to_string(path), scene);
        map.wrap_s = wrap_of(wrap[0]);
        map.wrap_t = wrap_of(wrap[1]);
        material.diffuse_map = map;
        break;
    }
    for (int type = aiTextureType_NONE + 1; type <= AI_TEXTURE_TYPE_MAX; ++type) {
        if (type == aiTextureType_DIFFUSE || type == aiTextureType_BASE_COLOR) continue;
        if (source.GetTextureCount(static_cast<aiTextureType>(type)) > 0) {
            ++other_textures_;
            break;
        }
    }
    return material;
}

std::vector<std::string> AssimpMaterials::ignored() const {
    if (other_textures_ == 0) return {};
    return {cat("textures other than diffuse of ", other_textures_, " material(s) (their factors are used)")};
}

std::uint32_t AssimpMaterials::texture_of(const std::string& reference, Scene& scene) {
    const auto [found, added] = texture_of_reference_.try_emplace(reference, std::uint32_t(scene.textures.size()));
    if (!added) return found->second;
    Texture texture;
    if (const aiTexture* embedded = scene_.GetEmbeddedTexture(reference.c_str())) {
        // Compressed (mHeight 0): mWidth bytes of a PNG, JPEG... file; the hint is its extension.
        const auto* bytes = reinterpret_cast<const unsigned char*>(embedded->pcData);
        texture.encoded.assign(bytes, bytes + embedded->mWidth);
        texture.mime_type = cat("image/", embedded->achFormatHint[0] == 'j' ? "jpeg" : embedded->achFormatHint);
        texture.name = cat(name_, " image '", reference, "'");
    } else {
        // Files written on Windows (FBX, some OBJ) name textures with backslashes.
        std::string relative = reference;
        std::replace(relative.begin(), relative.end(), '\\', '/');
        texture.path = (folder_ / relative).string();
        texture.name = texture.path;
    }
    scene.textures.push_back(std::move(texture));
    return found->second;
}

}  // namespace dynrt
