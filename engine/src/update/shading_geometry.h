#pragma once
// What shading reads of the objects besides their triangles' positions: each object's triangle
// corners (the scene's vertex indices, which texture coordinates are read through) and its
// unit vertex normals, for smooth shading. Refreshed by every update from what the frame's
// objects hold; the positions themselves live with the trees (SceneAccel::world_triangle).
//
// The spans are borrowed (from the scene's meshes, ObjectState::world_normals and
// FixedPositions) and valid until the next update, as the trees are. A static object's world
// normals are borrowed too when FixedPositions holds them (an object at the identity: its own
// normals), taken again at every update; only those made in FixedPositions' scratch (a static
// object under another transform) are copied, once, when the static group is built.

#include "dynrt/engine/update_plan.h"
#include "dynrt/scene/scene.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace dynrt {

class FixedPositions;

class ShadingGeometry {
public:
    /// Takes the corners and normals of `scene`'s objects as `states` pose them (one per
    /// object, scene order): world space for deformable and exploding objects, object space
    /// turned by the cofactor matrix of the transform for rigid ones, the copy kept by
    /// keep_static_normals for static ones.
    void refresh(const Scene& scene, std::span<const ObjectState> states, const FixedPositions& fixed);

    /// Static object `object`'s world-space unit normals (empty: flat), given when the static
    /// group is built: `borrowed`, they are FixedPositions' own storage, which refresh takes
    /// again from FixedPositions::world_normals at every update; else (made in a scratch
    /// buffer) a copy is kept.
    void keep_static_normals(std::size_t object, std::span<const glm::vec3> normals, bool borrowed);

    /// The world-space unit normals of triangle `prim`'s three vertices of `object` at the last
    /// refresh, into `out` in corner order; false, leaving `out` alone, when the object has none
    /// or use_vertex_normals(false) turned them off. A rigid object's are turned and
    /// renormalised in float.
    bool world_vertex_normals(std::size_t object, std::uint32_t prim, glm::vec3 (&out)[3]) const;

    /// The vertex indices of `object`'s triangles at the last refresh, in the order hits count
    /// them; empty for an object it did not see. A mesh removed from the library API since
    /// keeps its hits, and these, until the next update.
    std::span<const glm::uvec3> object_triangles(std::size_t object) const {
        return object < objects_.size() ? objects_[object].corners : std::span<const glm::uvec3>{};
    }

    /// Whether world_vertex_normals gives the objects' normals (true after construction); a
    /// trace sets it from TraceSettings::smooth_normals. Not thread-safe with traces.
    void use_vertex_normals(bool on) { vertex_normals_ = on; }

    /// Forgets everything of every object, or of one (its mesh is gone, or another took its slot).
    void clear() { objects_.clear(); }
    void forget(std::size_t object);

    /// Heap bytes held (the records and the static objects' copied normals).
    std::size_t memory_bytes() const;

private:
    struct ObjectShading {
        std::span<const glm::uvec3> corners;
        /// In the space of the object's triangles: world, or object space for a rigid object.
        std::span<const glm::vec3> normals;
        /// A static object's copy (normals points into it), unless borrowed_static.
        std::vector<glm::vec3> own_normals;
        bool borrowed_static = false;
        bool rigid = false;
        glm::mat3 normal_to_world{1.0f};
    };
    std::vector<ObjectShading> objects_;
    /// FixedPositions::world_normals' scratch at refresh (unused for borrowed normals, which
    /// are never made in it).
    std::vector<glm::vec3> scratch_;
    bool vertex_normals_ = true;
};

}  // namespace dynrt
