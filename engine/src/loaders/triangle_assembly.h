#pragma once
// Index lists in list, strip or fan order -> independent triangles, following the glTF 2.0
// specification, section 3.7.2.1 "Topology Types".

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace dynrt {

enum class TriangleTopology { list, strip, fan };

/// Triangles of `indices` read as `topology`:
/// list  i = 0..n/3-1:  (v[3i], v[3i+1], v[3i+2]); a remainder of 1 or 2 indices is ignored;
/// strip i = 0..n-3:    (v[i], v[i+1+i%2], v[i+2-i%2]), i.e. odd triangles swap their last two
///                      vertices so all share one winding;
/// fan   i = 0..n-3:    (v[i+1], v[i+2], v[0]).
/// Degenerate triangles (repeated indices, as used to stitch strips) are kept as they are.
std::vector<glm::uvec3> assemble_triangles(TriangleTopology topology, std::span<const std::uint32_t> indices);

}  // namespace dynrt
