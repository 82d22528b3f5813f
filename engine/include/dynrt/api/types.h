#pragma once
// Plain value types of the library API (dynrt/dynrt.h): no maths library is needed to use it.
// Vectors are three floats, transforms are column-major 4x4 float matrices (the layout of GLM
// and OpenGL, so glm::value_ptr(m) can be passed as it is).

#include "dynrt/api/export.h"

#include <array>
#include <cstdint>
#include <limits>

namespace dynrt {

/// A point or a direction: three floats.
struct Vec3 {
    float x = 0.0f;  ///< the first coordinate
    float y = 0.0f;  ///< the second coordinate (up, in the command line's convention)
    float z = 0.0f;  ///< the third coordinate
};

/// An affine object-to-world transform. `m[column * 4 + row]`; the last row must be
/// (0, 0, 0, 1).
struct DYNRT_API Transform {
    /// The matrix, column-major: `m[column * 4 + row]`. The identity by default.
    std::array<float, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

    /// The identity: object space is world space.
    static Transform identity() { return {}; }
    /// From 16 floats in column-major order (glm::value_ptr of a glm::mat4).
    static Transform from_column_major(const float* values);
    /// A translation by `offset`.
    static Transform translation(Vec3 offset);
    /// Rotation by `radians` about the unit-length `axis` (right-handed), then `offset`.
    static Transform rotation(Vec3 axis, float radians, Vec3 offset = {});
};

/// Identifies a mesh within its Engine. Ids are never reused, not even after remove_mesh.
struct MeshId {
    /// The id's number; the largest std::uint32_t is no mesh (a ray's miss).
    std::uint32_t value = std::numeric_limits<std::uint32_t>::max();
    /// Whether two ids name the same mesh.
    bool operator==(const MeshId&) const = default;
};

/// Identifies a texture within its Engine (Engine::add_texture). Textures are kept for the
/// engine's life. The default value is no texture.
struct TextureId {
    /// The id's number; the largest std::uint32_t is no texture.
    std::uint32_t value = std::numeric_limits<std::uint32_t>::max();
    /// Whether two ids name the same texture.
    bool operator==(const TextureId&) const = default;
    /// Whether the id names a texture (false for the default value).
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
    Vec3 origin;                                          ///< where the ray starts; finite
    Vec3 direction{0.0f, 0.0f, -1.0f};                    ///< finite and non-zero
    float tmin = 0.0f;                                    ///< the nearest t a hit may have, >= 0
    float tmax = std::numeric_limits<float>::infinity();  ///< the farthest t, >= tmin; may be +inf
};

/// The closest hit of a ray. On a miss: t = +inf, mesh invalid (hit() false), primitive -1.
struct RayHit {
    /// The hit's distance along the ray, in units of its direction; +inf on a miss.
    float t = std::numeric_limits<float>::infinity();
    /// The mesh hit; no mesh (hit() false) on a miss.
    MeshId mesh;
    /// The triangle's index in the mesh's index buffer (triangle k = indices 3k, 3k+1, 3k+2).
    std::uint32_t primitive = std::numeric_limits<std::uint32_t>::max();
    /// Barycentrics: the hit point is (1 - u - v) p0 + u p1 + v p2 of triangle `primitive`.
    float u = 0.0f;
    float v = 0.0f;  ///< the second barycentric coordinate (see u)

    /// Whether the ray hit anything.
    bool hit() const { return mesh.value != std::numeric_limits<std::uint32_t>::max(); }
};

/// A pinhole camera, with the command line's conventions (docs/rendering.md "Camera convention").
struct View {
    Vec3 eye{0.0f, 0.0f, 5.0f};     ///< where the camera is
    Vec3 target{0.0f, 0.0f, 0.0f};  ///< the point at the image's centre
    Vec3 up{0.0f, 1.0f, 0.0f};      ///< the direction that is up in the image (need not be unit)
    /// Vertical field of view in degrees, in (0, 180).
    float fov_y_deg = 45.0f;
};

/// What a light is sampled over: a point (hard shadows), a sphere's surface or a parallelogram
/// (area lights: soft shadows, one point of the light per pixel sample; RenderSettings::samples_per_pixel).
enum class LightShape : std::uint8_t {
    point,   ///< a point at Light::position
    sphere,  ///< a sphere's surface, centre Light::position, radius Light::radius
    quad,    ///< a parallelogram centred on Light::position, spanned by Light::edge_u and Light::edge_v
};

/// What a light is (docs/rendering.md "Lights").
enum class LightKind : std::uint8_t {
    point,        ///< shines every way from Light::position
    spot,         ///< shines within a cone around Light::direction from Light::position
    directional,  ///< a sun: shines along Light::direction from infinitely far (no position)
};

/// A light. Its colour at a point is intensity * color, times 1 / d^2 when inverse_square (d
/// the distance to it; the default is no falloff), glTF's window before `range`, and a spot's
/// cone. An area light lights a point as the mean of point lights of its intensity over its
/// surface.
struct Light {
    Vec3 position;           ///< where the light is (an area light's centre), in world space
    float intensity = 1.0f;  ///< what the light's colour is multiplied by, >= 0
    LightShape shape = LightShape::point;  ///< a point, or the area it is sampled over
    float radius = 0.0f;     ///< a sphere light's radius, > 0
    /// A quad light's edges: its points are position + a edge_u + b edge_v, a and b in
    /// [-1/2, 1/2]; not parallel.
    Vec3 edge_u{0.0f, 0.0f, 0.0f};
    Vec3 edge_v{0.0f, 0.0f, 0.0f};  ///< a quad light's second edge (see edge_u)
    LightKind kind = LightKind::point;  ///< a point (or area), a spot or a directional light
    Vec3 color{1.0f, 1.0f, 1.0f};   ///< linear RGB, each >= 0
    /// A spot's axis, a directional light's direction of travel (normalised here; not zero).
    Vec3 direction{0.0f, 0.0f, -1.0f};
    /// A spot's cone in degrees from its axis: full within inner, none past outer
    /// (0 <= inner < outer <= 90), glTF's smooth ramp between.
    float inner_cone_deg = 0.0f;
    float outer_cone_deg = 45.0f;  ///< a spot's outer cone in degrees (see inner_cone_deg)
    bool inverse_square = false;  ///< point and spot lights: intensity / d^2
    float range = 0.0f;           ///< point and spot lights: none beyond it; 0: no range
};

/// A mesh's material: Phong terms plus Whitted's mirror and refraction weights (docs/rendering.md
/// "Shading", docs/scene-input.md "Materials"). Colours and weights are linear RGB, meant to lie in [0, 1]; every
/// value must be finite, colours (a negative one would shade darker than black), shininess,
/// reflectance and transmittance >= 0, ior > 0.
struct Surface {
    Vec3 diffuse{0.8f, 0.8f, 0.8f};   ///< Phong's diffuse colour (and the ambient term's)
    Vec3 specular{0.2f, 0.2f, 0.2f};  ///< Phong's specular colour
    float shininess = 32.0f;          ///< Phong's specular exponent
    /// Weight of the mirror-reflected ray's colour; 0 (the default) traces no reflection ray.
    Vec3 reflectance{0.0f, 0.0f, 0.0f};
    /// Weight of the refracted ray's colour before Fresnel; 0 (the default) is opaque.
    Vec3 transmittance{0.0f, 0.0f, 0.0f};
    /// Index of refraction of the inside (the side the triangles' winding normal points away
    /// from) relative to the outside: 1.5 for glass; only used where transmittance > 0.
    float ior = 1.0f;
    /// A texture (Engine::add_texture) whose linear colour multiplies `diffuse` at each hit,
    /// looked up at the mesh's texture coordinates (MeshDesc::texcoords, which a mesh must
    /// have to take a textured surface) and filtered as `dynrt render` filters (docs/rendering.md
    /// "Textures"). Default: none.
    TextureId diffuse_texture{};
    /// How the texture coordinate s (across) wraps outside [0, 1].
    Wrap wrap_s = Wrap::repeat;
    /// How the texture coordinate t (down) wraps outside [0, 1].
    Wrap wrap_t = Wrap::repeat;
    /// Light the surface gives off itself, added to its shaded colour whatever lights it (it
    /// lights nothing else); linear, each channel >= 0. 0 (the default): none.
    Vec3 emission{0.0f, 0.0f, 0.0f};
    /// A cut-out (glTF's alphaMode MASK): where the surface's alpha, `alpha` times the diffuse
    /// texture's alpha at the hit, is below this, the surface is not there and every ray
    /// passes through it (docs/rendering.md "Alpha"). In [0, 1]; 0 (the default): never cut.
    float alpha_cutoff = 0.0f;
    /// The surface's alpha before its texture's, in [0, 1]; read by a cut-out only.
    float alpha = 1.0f;
};

}  // namespace dynrt
