#pragma once
// assimp materials (aiMaterial's Phong keys, as OBJ's MTL, PLY, FBX and Collada give them) as
// the scene model's Materials, and their diffuse textures as Scene::textures.

#include "dynrt/scene/scene.h"
#include "dynrt/scene/warnings.h"

#include <assimp/scene.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace dynrt {

/// Maps the materials of one imported scene; remembers the textures it added so a file used by
/// several materials is one Texture.
class AssimpMaterials {
public:
    /// `scene_file`: the file the scene came from (texture paths are relative to its folder).
    /// Borrows `scene` for the object's lifetime.
    AssimpMaterials(const aiScene& scene, const std::filesystem::path& scene_file);

    /// Material `index` of the assimp scene (docs/scene-input.md "Materials", OBJ, PLY, FBX, Collada):
    ///   diffuse       = COLOR_DIFFUSE * OPACITY (clamped to [0, 1]; default 0.8 grey,
    ///                   opacity 1): what is not opaque is transmitted, not scattered;
    ///   specular      = COLOR_SPECULAR * SHININESS_STRENGTH (clamped; default 0.2 grey);
    ///   shininess     = SHININESS, clamped to [1, 128] (default 32; 0, OBJ's "no highlight",
    ///                   gives 1);
    ///   reflectance   = COLOR_REFLECTIVE * REFLECTIVITY (clamped; 0 unless both are given);
    ///   transmittance = 1 - OPACITY, grey (0 for an opaque material);
    ///   ior           = REFRACTI when transmittance > 0 and REFRACTI is given (a value <= 0 is
    ///                   passed on for check_scene to refuse), 1.5 when it is not, else 1.
    /// The diffuse texture 0 (aiTextureType_DIFFUSE, else BASE_COLOR) becomes diffuse_map, with
    /// its wrap modes; a texture on another UV channel than 0, or embedded uncompressed, is left
    /// out with a warning in `warnings`. Other texture types are counted for Scene::ignored.
    Material convert(unsigned index, Scene& scene, std::vector<Warning>& warnings);

    /// Lines for Scene::ignored: the texture types other than diffuse that materials have.
    std::vector<std::string> ignored() const;

private:
    std::uint32_t texture_of(const std::string& reference, Scene& scene);

    const aiScene& scene_;
    std::filesystem::path folder_;
    std::string name_;
    std::map<std::string, std::uint32_t> texture_of_reference_;
    std::size_t other_textures_ = 0;
};

}  // namespace dynrt
