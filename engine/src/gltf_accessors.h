#pragma once
// Validated reads of glTF accessors: every byte range is checked against its bufferView and
// buffer before it is touched, so a corrupt file throws instead of reading out of bounds.

#include <tiny_gltf.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynrt {

/// The FLOAT VEC3 elements of accessor `accessor` (byteOffset and byteStride respected), each
/// checked finite. Sparse accessors and accessors without a bufferView are rejected. Throws
/// GltfDataError naming the accessor and the problem.
std::vector<glm::vec3> read_positions(const tinygltf::Model& model, int accessor);

/// The SCALAR UNSIGNED_BYTE/SHORT/INT elements of accessor `accessor` widened to 32 bits, each
/// checked below `vertex_count`. Throws GltfDataError naming the accessor and the problem.
std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, int accessor, std::size_t vertex_count);

}  // namespace dynrt
