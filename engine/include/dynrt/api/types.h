#pragma once
// Plain value types of the library API (dynrt/dynrt.h): no maths library is needed to use it.
// Vectors are three floats, transforms are column-major 4x4 float matrices (the layout of GLM
// and OpenGL, so glm::value_ptr(m) can be passed as it is).

#include "dynrt/api/export.h"

#include <array>
#include <cstdint>
#include <limits>

namespace dynrt {

struct Vec3 {
    float x = 0.0f, y = 0.0f, z = 0.0f;
};

/// An affine object-to-world transform. `m[column * 4 + row]`; the last row must be
/// (0, 0, 0, 1).
struct DYNRT_API Transform {
    std::array<float, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

    static Transform identity() { return {}; }
    /// From 16 floats in column-major order (glm::value_ptr of a glm::mat4).
    static Transform from_column_major(const float* values);
    static Transform translation(Vec3 offset);
    /// Rotation by `radians` about the unit-length `axis` (right-handed), then `offset`.
    static Transform rotation(Vec3 axis, float radians, Vec3 offset = {});
};

/// Identifies a mesh within its Engine. Ids are never reused, not even after remove_mesh.
struct MeshId {
    std::uint32_t value = std::numeric_limits<std::uint32_t>::max();
    bool operator==(const MeshId&) const = default;
};

/// Identifies a texture within its Engine (Engine::add_texture). Textures are kept for the
/// engine's life. The default value is no texture.
struct TextureId {
    std::uint32_t value = std::numeric_limits<std::uint32_t>::max();
    bool operator==(const TextureId&) const = default;
    bool valid() const { return value != std::numeric_limits<std::uint32_t>::max(); }
};

/// How texture coordinates outside [0, 1] are folded back (glTF's sampler wrap modes).
enum class Wrap : std::uint8_t {
    repeat,  ///< the image tiles
    clamp,   ///< the edge texels extend
    mirror,  ///< the image tiles, every other copy mirrored
};

/// A ray for trace queries: points origin + t * direction for t in [tmin, tmax]. The direction
/// need not be unit length (t is then in its units); it must be finite and non-zero, the
/// origin finite, 0 <= tmin <= tmax (tmax may be +inf).
struct Ray {
    Vec3 origin;
    Vec3 direction{0.0f, 0.0f, -1.0f};
    float tmin = 0.0f;
    float tmax = std::numeric_limits<float>::infinity();
};

/// The closest hit of a ray. On a miss: t = +inf, mesh invalid (hit() false), primitive -1.
struct RayHit {
    float t = std::numeric_limits<float>::infinity();
    MeshId mesh;
    /// The triangle's index in the mesh's index buffer (triangle k = indices 3k, 3k+1, 3k+2).
    std::uint32_t primitive = std::numeric_limits<std::uint32_t>::max();
    /// Barycentrics: the hit point is (1 - u - v) p0 + u p1 + v p2 of triangle `primitive`.
    float u = 0.0f, v = 0.0f;

    bool hit() const { return mesh.value != std::numeric_limits<std::uint32_t>::max(); }
};

/// A pinhole camera, with the command line's conventions (README "Camera convention").
struct View {
    Vec3 eye{0.0f, 0.0f, 5.0f};
    Vec3 target{0.0f, 0.0f, 0.0f};
    Vec3 up{0.0f, 1.0f, 0.0f};
    /// Vertical field of view in degrees, in (0, 180).
    float fov_y_deg = 45.0f;
};

/// A point light; no distance falloff.
struct Light {
    Vec3 position;
    float intensity = 1.0f;
};

/// A mesh's material: Phong terms plus Whitted's mirror and refraction weights (README
/// "Shading", "Materials"). Colours and weights are linear RGB, meant to lie in [0, 1]; every
/// value must be finite, colours (a negative one would shade darker than black), shininess,
/// reflectance and transmittance >= 0, ior > 0.
struct Surface {
    Vec3 diffuse{0.8f, 0.8f, 0.8f};
    Vec3 specular{0.2f, 0.2f, 0.2f};
    float shininess = 32.0f;
    /// Weight of the mirror-reflected ray's colour; 0 (the default) traces no reflection ray.
    Vec3 reflectance{0.0f, 0.0f, 0.0f};
    /// Weight of the refracted ray's colour before Fresnel; 0 (the default) is opaque.
    Vec3 transmittance{0.0f, 0.0f, 0.0f};
    /// Index of refraction of the inside (the side the triangles' winding normal points away
    /// from) relative to the outside: 1.5 for glass; only used where transmittance > 0.
    float ior = 1.0f;
    /// A texture (Engine::add_texture) whose linear colour multiplies `diffuse` at each hit,
    /// looked up at the mesh's texture coordinates (MeshDesc::texcoords, which a mesh must
    /// have to take a textured surface) and filtered as `dynrt render` filters (README
    /// "Textures"). Default: none.
    TextureId diffuse_texture{};
    /// How the texture coordinates s (across) and t (down) wrap outside [0, 1].
    Wrap wrap_s = Wrap::repeat;
    Wrap wrap_t = Wrap::repeat;
};

}  // namespace dynrt
