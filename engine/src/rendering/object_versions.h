#pragma once
// Per object, a version that moves whenever its geometry may have changed: at an update that
// said it changed, and at the first update after it was invalidated (its triangles replaced,
// or its slot taken by another mesh). Pixel reuse compares versions between traces to tell
// which objects changed (exact reuse, the render cache, frameless mode); exact reuse also
// tests rays against each object's parts, the world boxes of a cut through its tree, kept
// here per version so that an object that holds still is not cut again.

#include "dynrt/bvh/aabb.h"
#include "dynrt/engine/update_plan.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dynrt {

class SceneAccel;

class ObjectVersions {
public:
    /// Moves the versions to an update's `states` (one per object): a new object gets a new
    /// version, as does one that changed or was invalidated since the last update. Called
    /// before the trees change, so that an update that throws half way has still moved what
    /// it touched.
    void advance(std::span<const ObjectState> states);

    /// Object `object` changes at the next update (its version moves then, not now: a trace
    /// before it still shows the object as it was).
    void invalidate(std::size_t object);

    /// Forgets object `object`'s parts (its mesh went away with its triangles).
    void release(std::size_t object) {
        if (object < parts_.size()) parts_[object] = {};
    }

    /// Forgets every version: the next update gives every object a new one.
    void clear() {
        versions_.clear();
        invalidated_.clear();
    }

    std::span<const std::uint64_t> versions() const { return versions_; }

    /// Per object, the world boxes of a cut through its tree in `accel`
    /// (SceneAccel::object_world_parts), cut again for the objects whose version moved.
    std::span<const std::vector<bvh::Aabb>> parts(const SceneAccel& accel);

    /// Heap bytes held.
    std::size_t memory_bytes() const;

private:
    std::vector<std::uint64_t> versions_;
    std::uint64_t last_version_ = 0;
    /// Per object, whether it was invalidated since the last update: a flag per object rather
    /// than a list, so that objects added and removed many times between two updates do not
    /// grow it.
    std::vector<std::uint8_t> invalidated_;
    /// Per object, its parts and the version they were taken at.
    std::vector<std::vector<bvh::Aabb>> parts_;
    std::vector<std::uint64_t> parts_versions_;
    /// Boxes per object: 16 follow a skinned figure's limbs closely enough that a still camera
    /// re-traces about half the pixels its one box covers (CesiumMan, Fox).
    static constexpr std::size_t kPartsPerObject = 16;
};

}  // namespace dynrt
