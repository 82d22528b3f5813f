#pragma once
// Reading a glTF 2.0 file into tinygltf's document model. Every container-level problem
// (missing file, malformed JSON, truncated or corrupt GLB, missing .bin) becomes one SceneError
// line naming the file; the model's contents are validated later, where they are used.

#include "dynrt/engine/scene_loading.h"

#include <tiny_gltf.h>

#include <filesystem>
#include <span>
#include <string>

namespace dynrt {

/// True when `path` ends in .gltf or .glb, case-insensitive.
bool is_gltf_path(const std::filesystem::path& path);

/// Reads `path` as JSON glTF or as binary GLB, chosen by extension (case-insensitive). Images
/// are neither decoded nor required (dynrt uses no textures); tinygltf's other warnings go to
/// stderr. The GLB container is validated here before tinygltf sees it, and its BIN chunk is
/// read from the file once, straight into buffer 0 (no copy of the whole file). Throws
/// SceneError.
tinygltf::Model read_gltf_model(const std::filesystem::path& path);

/// The same for a document in memory, named `name` in errors. Buffers and images given by a
/// URI other than data: are never looked up on the filesystem: such a buffer is a SceneError.
tinygltf::Model read_gltf_model_from_memory(std::span<const unsigned char> bytes, GltfFormat format,
                                            const std::string& name);

}  // namespace dynrt
