#pragma once
// The heap bytes a scene model holds (the report's scene_bytes, issue 43): what loading it
// costs in memory before any tree is built.

#include "dynrt/scene/scene.h"

#include <cstddef>
#include <unordered_set>

namespace dynrt {

/// Bytes of `scene`'s allocated storage: its objects' meshes (positions, triangles, normals,
/// texture coordinates), skin weights and morph targets, its textures' embedded file bytes and
/// texel arrays, nodes, skins and animation clips (vectors' capacities; names and other small
/// strings left out). A mesh array that several objects share (SharedArray) counts once.
std::size_t scene_bytes(const Scene& scene);

/// Of those, one object's: its mesh's arrays (in full, shared or not), skin weights and morph
/// targets.
std::size_t object_bytes(const Object& object);

/// The same over several objects, a mesh array they share counted once.
class ObjectBytes {
public:
    void add(const Object& object);
    std::size_t total() const { return total_; }

private:
    std::unordered_set<const void*> shared_counted_;
    std::size_t total_ = 0;
};

}  // namespace dynrt
