#pragma once
// Which reader a scene file goes to, told by its extension and its first bytes, so that a path
// that exists never falls through to the procedural spec parser and a file of no kind dynrt
// reads is refused by name.

#include <filesystem>
#include <string>

namespace dynrt {

enum class SceneFileKind {
    gltf,      ///< .gltf or .glb, or a file starting with GLB's magic "glTF"
    aff,       ///< BART's AFF (.aff)
    assimp,    ///< anything else assimp may read (OBJ, PLY, FBX, Collada...): it decides by content
};

/// The formats dynrt reads, for the error about a file of another kind.
inline constexpr const char* kSceneFormatsRead =
    "glTF .gltf/.glb, BART .aff, OBJ, PLY, FBX, Collada .dae, STL, 3DS, Blender .blend and the "
    "other formats of assimp";

/// The kind of the existing file `path`: glTF by extension (case-insensitive) or by GLB's magic
/// in its first four bytes, AFF by extension, else assimp. Does not check that assimp can read
/// it (load_assimp says so when it cannot).
SceneFileKind scene_file_kind(const std::filesystem::path& path);

/// Whether `source`, which names no existing file, was meant as a file rather than a procedural
/// spec: it contains a '/' (specs never do) or ends in an extension, a '.' then a letter then
/// letters and digits (".obj", ".gltf"; never a spec's number, "@1.5" or "#a0a0ff").
bool looks_like_file_path(const std::string& source);

}  // namespace dynrt
