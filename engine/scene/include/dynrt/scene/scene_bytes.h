#pragma once
// The heap bytes a scene model holds (the report's scene_bytes, issue 43): what loading it
// costs in memory before any tree is built.

#include "dynrt/scene/scene.h"

#include <cstddef>

namespace dynrt {

/// Bytes of `scene`'s allocated storage: its objects' meshes (positions, triangles, normals,
/// texture coordinates), skin weights and morph targets, its textures' embedded file bytes and
/// texel arrays, nodes, skins and animation clips (vectors' capacities; names and other small
/// strings left out).
std::size_t scene_bytes(const Scene& scene);

/// Of those, one object's: its mesh's arrays, skin weights and morph targets.
std::size_t object_bytes(const Object& object);

}  // namespace dynrt
