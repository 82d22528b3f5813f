// scene_bytes (dynrt/scene/scene_bytes.h).

#include "dynrt/scene/scene_bytes.h"

namespace dynrt {

namespace {

/// A vector's allocated bytes (its capacity: what stays allocated after a clear()).
template <typename Vector>
std::size_t held(const Vector& v) {
    return v.capacity() * sizeof(typename Vector::value_type);
}

/// Bytes of `mesh`'s arrays but the shared ones `seen` holds already (which it then holds).
std::size_t unseen_mesh_bytes(const Mesh& mesh, std::unordered_set<const void*>& seen) {
    std::size_t bytes = 0;
    const auto count = [&](const auto& array) {
        if (array.holders() > 1 && !seen.insert(array.data()).second) return;
        bytes += held(array);
    };
    count(mesh.positions);
    count(mesh.triangles);
    count(mesh.normals);
    count(mesh.texcoords);
    return bytes;
}

std::size_t rig_bytes(const Object& object) {
    std::size_t bytes = 0;
    if (object.skin) bytes += held(object.skin->joints) + held(object.skin->weights);
    if (object.morph) {
        const MorphTargets& m = *object.morph;
        bytes += held(m.base_positions) + held(m.position_deltas) + held(m.default_weights) + held(m.base_normals) +
                 held(m.normal_deltas);
        for (const auto& d : m.position_deltas) bytes += held(d);
        for (const auto& d : m.normal_deltas) bytes += held(d);
    }
    return bytes;
}

}  // namespace

std::size_t object_bytes(const Object& object) {
    ObjectBytes bytes;
    bytes.add(object);
    return bytes.total();
}

void ObjectBytes::add(const Object& object) {
    total_ += unseen_mesh_bytes(object.mesh, shared_counted_) + rig_bytes(object);
}

std::size_t scene_bytes(const Scene& scene) {
    std::size_t bytes = held(scene.objects) + held(scene.materials) + held(scene.nodes) + held(scene.skins) +
                        held(scene.clips) + held(scene.textures);
    ObjectBytes objects;
    for (const Object& object : scene.objects) objects.add(object);
    bytes += objects.total();
    for (const Skin& skin : scene.skins) bytes += held(skin.joints) + held(skin.inverse_bind_matrices);
    for (const AnimationClip& clip : scene.clips) {
        bytes += held(clip.samplers) + held(clip.channels);
        for (const AnimationSampler& s : clip.samplers) bytes += held(s.times) + held(s.values);
    }
    for (const Texture& t : scene.textures) bytes += held(t.encoded) + held(t.texels.bytes);
    return bytes;
}

}  // namespace dynrt
