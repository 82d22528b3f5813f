#include "rendering/object_versions.h"

#include "update/held_bytes.h"
#include "update/scene_accel.h"

namespace dynrt {

void ObjectVersions::advance(std::span<const ObjectState> states) {
    if (states.size() < versions_.size()) versions_.clear();
    while (versions_.size() < states.size()) versions_.push_back(++last_version_);
    for (std::size_t i = 0; i < states.size(); ++i) {
        if (states[i].changed) versions_[i] = ++last_version_;
    }
    for (std::size_t i = 0; i < invalidated_.size() && i < versions_.size(); ++i) {
        if (invalidated_[i]) versions_[i] = ++last_version_;
    }
    invalidated_.clear();
}

void ObjectVersions::invalidate(std::size_t object) {
    if (invalidated_.size() <= object) invalidated_.resize(object + 1, 0);
    invalidated_[object] = 1;
}

std::span<const std::vector<bvh::Aabb>> ObjectVersions::parts(const SceneAccel& accel) {
    const std::size_t count = versions_.size();
    parts_.resize(count);
    parts_versions_.resize(count, 0);
    for (std::size_t i = 0; i < count; ++i) {
        if (parts_versions_[i] == versions_[i]) continue;
        parts_[i].clear();
        accel.object_world_parts(i, kPartsPerObject, parts_[i]);
        parts_versions_[i] = versions_[i];
    }
    return parts_;
}

std::size_t ObjectVersions::memory_bytes() const {
    std::size_t bytes = held_bytes(versions_) + held_bytes(invalidated_) + held_bytes(parts_) +
                        held_bytes(parts_versions_);
    for (const std::vector<bvh::Aabb>& parts : parts_) bytes += held_bytes(parts);
    return bytes;
}

}  // namespace dynrt
