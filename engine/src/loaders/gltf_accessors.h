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

/// Which integer component types a numeric accessor may use besides FLOAT. Integers must be
/// `normalized` and map to [0, 1] (unsigned: c / (2^bits - 1)) or [-1, 1] (signed:
/// max(c / (2^(bits-1) - 1), -1)), as glTF 2.0 sections 3.7.2.1 and 3.11 define.
enum class NormalizedIntegers {
    none,           ///< FLOAT only
    unsigned_only,  ///< also UNSIGNED_BYTE and UNSIGNED_SHORT (skin weights)
    any,            ///< also BYTE and SHORT (rotations and morph weights in animations)
};

/// The elements of accessor `accessor` of type `type` (TINYGLTF_TYPE_SCALAR ... MAT4) as
/// doubles, flattened element by element (count * components numbers), each checked finite.
/// MAT4 must be FLOAT. Throws GltfDataError naming the accessor and the problem.
std::vector<double> read_numbers(const tinygltf::Model& model, int accessor, int type, NormalizedIntegers integers);

/// The joint indices of a JOINTS_n accessor: VEC4 UNSIGNED_BYTE or UNSIGNED_SHORT, flattened.
/// Throws GltfDataError naming the accessor and the problem.
std::vector<std::uint16_t> read_joint_indices(const tinygltf::Model& model, int accessor);

/// The bytes of bufferView `view` (an embedded image's file), checked to lie within its buffer.
/// Throws GltfDataError naming the bufferView when it or its buffer does not exist or it
/// exceeds the buffer.
std::vector<unsigned char> read_buffer_view(const tinygltf::Model& model, int view);

/// The element count of accessor `accessor`; throws GltfDataError when it does not exist.
std::size_t accessor_count(const tinygltf::Model& model, int accessor);

/// The SCALAR UNSIGNED_BYTE/SHORT/INT elements of accessor `accessor` widened to 32 bits, each
/// checked below `vertex_count`. Throws GltfDataError naming the accessor and the problem.
std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, int accessor, std::size_t vertex_count);

/// The same read as a triangle list's corners, each three a triangle (assemble_triangles' list,
/// without the indices held twice): a remainder of one or two indices is checked and ignored.
std::vector<glm::uvec3> read_index_triples(const tinygltf::Model& model, int accessor, std::size_t vertex_count);

}  // namespace dynrt
