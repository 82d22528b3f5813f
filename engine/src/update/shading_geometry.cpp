#include "update/shading_geometry.h"

#include "dynrt/scene/vertex_normals.h"
#include "update/held_bytes.h"
#include "update/scene_accel.h"

#include <glm/mat3x3.hpp>

namespace dynrt {

void ShadingGeometry::refresh(const Scene& scene, std::span<const ObjectState> states,
                              const FixedPositions& fixed) {
    objects_.resize(scene.objects.size());
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        ObjectShading& object = objects_[i];
        object.corners = scene.objects[i].mesh.triangles;
        object.rigid = states[i].motion_class == anim::MotionClass::rigid;
        switch (states[i].motion_class) {
            case anim::MotionClass::static_:
                object.normals = object.own_normals;  // taken when the static group was built
                if (object.borrowed_static) {
                    object.normals = fixed.world_normals(i, scratch_);
                    // Made in the scratch after all (not expected for an object borrowed at
                    // its build): kept as a copy from now on.
                    if (!object.normals.empty() && object.normals.data() == scratch_.data()) {
                        keep_static_normals(i, object.normals, false);
                        object.normals = object.own_normals;
                    }
                }
                break;
            case anim::MotionClass::rigid:
                object.normals = fixed.object_space_normals(i);
                object.normal_to_world = glm::mat3(normal_matrix(glm::dmat3(states[i].transform)));
                break;
            default:
                object.normals = states[i].world_normals;
                break;
        }
    }
}

void ShadingGeometry::keep_static_normals(std::size_t object, std::span<const glm::vec3> normals, bool borrowed) {
    if (objects_.size() <= object) objects_.resize(object + 1);
    ObjectShading& o = objects_[object];
    o.borrowed_static = borrowed;
    if (borrowed) {
        std::vector<glm::vec3>().swap(o.own_normals);
    } else {
        o.own_normals.assign(normals.begin(), normals.end());
    }
}

void ShadingGeometry::forget(std::size_t object) {
    if (object < objects_.size()) objects_[object] = ObjectShading{};
}

bool ShadingGeometry::world_vertex_normals(std::size_t object, std::uint32_t prim,
                                           glm::vec3 (&out)[3]) const {
    const ObjectShading& o = objects_[object];
    if (!vertex_normals_ || o.normals.empty()) return false;
    const glm::uvec3& corner = o.corners[prim];
    out[0] = o.normals[corner.x];
    out[1] = o.normals[corner.y];
    out[2] = o.normals[corner.z];
    if (o.rigid) {
        for (glm::vec3& n : out) n = normalize_or_zero(o.normal_to_world * n);
    }
    return true;
}

std::size_t ShadingGeometry::memory_bytes() const {
    std::size_t bytes = held_bytes(objects_) + held_bytes(scratch_);
    for (const ObjectShading& o : objects_) bytes += held_bytes(o.own_normals);
    return bytes;
}

}  // namespace dynrt
