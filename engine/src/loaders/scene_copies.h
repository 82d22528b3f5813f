#pragma once
// Copies on a grid: K objects (or K copies of a whole scene file) laid out side by side,
// sharing their meshes' arrays (Mesh, SharedArray), so that a forest of one model costs its
// triangles once (docs/animation.md, "Instancing"). Procedural specs write them `kind:N*K`,
// scene files `FILE*K` (scenes/README.md, "Copies").

#include "dynrt/scene/scene.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace dynrt {

/// At most this many copies of a part or file: a million objects' records, poses and
/// instances are some hundreds of megabytes.
inline constexpr std::uint64_t kMaxCopies = 1'000'000;

/// Where copy k of `copies` of something whose box is [lo, hi] goes: on a square grid of side
/// G = ceil(sqrt(copies)) in the y = 0 plane, centred on the origin, 1.5 times the box's
/// larger side in x and z apart, turned about the vertical axis through the box's centre c by
/// k golden angles (so that no two neighbours face the same way):
/// translate(grid x, c.y, grid z) * rotate_y(k * 2.3999632 radians) * translate(-c), in float.
glm::mat4 copy_matrix(std::uint64_t k, std::uint64_t copies, glm::vec3 lo, glm::vec3 hi);

/// `source` split as FILE*K when it ends in '*' and decimal digits: the file and K (which may
/// be out of range: make_copies checks it).
struct CopiesSpec {
    std::string file;
    std::uint64_t copies = 0;
};
std::optional<CopiesSpec> parse_copies_spec(const std::string& source);

/// Replaces `scene`'s objects by `copies` copies of them all, copy k of each object placed by
/// copy_matrix over the box of the whole scene's vertices (at their rest transforms) and named
/// "NAME[k]". The copies hang on no node. Throws SceneError naming `source` for a count out of
/// [1, kMaxCopies] and for a scene with clips, skins or morph targets (driven by its nodes,
/// its copies would move as one).
void make_copies(Scene& scene, std::uint64_t copies, const std::string& source);

}  // namespace dynrt
