#pragma once
// Reading a glTF 2.0 file into tinygltf's document model. Every container-level problem
// (missing file, malformed JSON, truncated or corrupt GLB, missing .bin) becomes one SceneError
// line naming the file; the model's contents are validated later, where they are used.

#include <tiny_gltf.h>

#include <filesystem>

namespace dynrt {

/// True when `path` ends in .gltf or .glb, case-insensitive.
bool is_gltf_path(const std::filesystem::path& path);

/// Reads `path` as JSON glTF or as binary GLB, chosen by extension (case-insensitive). Images
/// are neither decoded nor required (dynrt uses no textures); tinygltf's other warnings go to
/// stderr. The GLB container is validated here before tinygltf sees it. Throws SceneError.
tinygltf::Model read_gltf_model(const std::filesystem::path& path);

}  // namespace dynrt
