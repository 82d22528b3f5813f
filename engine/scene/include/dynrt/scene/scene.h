#pragma once
// The scene model every front end (glTF, procedural specs) produces and every later stage
// (animation, BVH update, rendering) reads. Objects own their vertex buffers in object space and
// carry a transform, so animation can later move either without touching the other.

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace dynrt {

/// Phong material. Colours are linear RGB in [0, 1].
struct Material {
    std::string name;
    glm::vec3 diffuse{0.8f};
    glm::vec3 specular{0.2f};
    float shininess = 32.0f;
};

/// A triangle mesh in object space. `triangles` index into `positions`.
struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
};

/// One traceable thing. Its world-space triangles are `transform * mesh.positions`.
struct Object {
    /// For reports and errors: glTF "node/mesh" (with "#k" for the k-th primitive when a mesh
    /// has several), or the procedural spec that made it.
    std::string name;
    Mesh mesh;
    glm::mat4 transform{1.0f};
    std::uint32_t material = 0;
};

struct PointLight {
    glm::vec3 position{0.0f};
    float intensity = 1.0f;
};

struct Scene {
    /// Where the scene came from (file path or spec string), for messages.
    std::string source;
    std::vector<Object> objects;
    /// Always holds at least one material (index 0, the default) once a loader has run.
    std::vector<Material> materials;
    /// Lights the scene itself defines; empty means "use the renderer's default light".
    std::vector<PointLight> lights;

    std::size_t triangle_count() const;
};

}  // namespace dynrt
