#pragma once
// The scene model every front end (glTF, procedural specs) produces and every later stage
// (animation, BVH update, rendering) reads. Objects own their vertex buffers in object space and
// carry a transform, so animation can move either without touching the other. What animates
// them lives beside them, one concept per header: the node hierarchy (node.h), skins (skin.h),
// morph targets (morph_targets.h), keyframe clips (animation_clip.h), cameras (scene_camera.h)
// and user-added procedural motions (procedural_motion.h). dynrt::anim evaluates it all.

#include "dynrt/scene/animation_clip.h"
#include "dynrt/scene/morph_targets.h"
#include "dynrt/scene/node.h"
#include "dynrt/scene/procedural_motion.h"
#include "dynrt/scene/scene_camera.h"
#include "dynrt/scene/scene_setup.h"
#include "dynrt/scene/shared_array.h"
#include "dynrt/scene/skin.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dynrt {

/// The longest side of a texture dynrt holds (a larger image cannot be read, with a warning):
/// every MIP level's start then fits the filter's 16-entry table and every texel index its
/// 32-bit gathers.
inline constexpr int kMaxTextureSide = 16384;

/// Texels given as they are, not as a file (the library API's and Python's arrays): `width` x
/// `height` texels of `channels` values each (1 grey, 2 grey and alpha, 3 RGB, 4 RGBA; alpha
/// is read by cut-outs only, Material::alpha_cutoff), row by row from the image's top-left corner, 8-bit (0-255) or 32-bit float.
struct TexelArray {
    int width = 0;
    int height = 0;
    int channels = 0;
    bool floating = false;  ///< float texels (4 bytes each), else 8-bit
    std::vector<unsigned char> bytes;  ///< width * height * channels values

    bool empty() const { return width == 0; }
};

/// An image a material's colour is read from: a file, a file's bytes held in memory (a glTF
/// image embedded in the document or its binary buffer), or texels given directly.
struct Texture {
    /// For messages: the file's path, or "<scene source> image <i>" for an embedded image.
    std::string name;
    /// The file to read (as given, or made relative to the scene file's folder by the
    /// loader); empty when the image is `encoded`.
    std::string path;
    /// An embedded image's file bytes (PNG, JPEG...) and MIME type ("image/png"); empty for a
    /// file.
    std::vector<unsigned char> encoded;
    std::string mime_type;
    /// Or the texels themselves (the library API's arrays); empty for a file or its bytes.
    TexelArray texels;
    /// The texel values are sRGB-encoded (glTF base colour, 8-bit images): lookups convert
    /// them to linear. False: they are linear already.
    bool srgb = true;
};

/// How texture coordinates outside [0, 1] are folded back (glTF's sampler wrap modes).
enum class TextureWrap : std::uint8_t {
    repeat,  ///< the image tiles (glTF REPEAT, the default)
    clamp,   ///< the edge texels extend (CLAMP_TO_EDGE)
    mirror,  ///< the image tiles, every other copy mirrored (MIRRORED_REPEAT)
};

/// A texture mapped onto a material's surfaces through the objects' texture coordinates.
struct TextureMap {
    std::uint32_t texture = 0;  ///< index into Scene::textures
    TextureWrap wrap_s = TextureWrap::repeat;
    TextureWrap wrap_t = TextureWrap::repeat;

    bool operator==(const TextureMap&) const = default;
};

/// Phong material with Whitted's mirror and transmission terms (the model is in
/// dynrt/engine/renderer.h). Colours and weights are linear RGB in [0, 1].
struct Material {
    std::string name;
    glm::vec3 diffuse{0.8f};
    glm::vec3 specular{0.2f};
    float shininess = 32.0f;
    /// Weight of the mirror-reflected ray's colour (0: no reflection ray).
    glm::vec3 reflectance{0.0f};
    /// Weight of the refracted ray's colour before Fresnel (0: opaque).
    glm::vec3 transmittance{0.0f};
    /// Index of refraction of the inside (the side the triangles' winding normal points away
    /// from) relative to the outside; > 0 and finite.
    float ior = 1.0f;
    /// Light the surface gives off itself (linear, each channel >= 0 and finite): added to its
    /// shaded colour whatever lights it, at camera and secondary hits alike; it lights nothing
    /// else. glTF's emissiveFactor times KHR_materials_emissive_strength.
    glm::vec3 emission{0.0f};
    /// When present, the ambient colour a hit shows whatever lights it, in place of the
    /// renderer's ambient fraction times the diffuse colour (times the texture's colour where
    /// the material maps one): BART's `am` ambient light times the material's ambient
    /// coefficients. Linear, each channel finite and >= 0.
    std::optional<glm::vec3> ambient = std::nullopt;
    /// When present, the diffuse colour at a hit is `diffuse` times this texture's linear
    /// colour at the hit's texture coordinates (Mesh::texcoords); objects without texture
    /// coordinates, and textures that cannot be read, use `diffuse` alone.
    std::optional<TextureMap> diffuse_map = std::nullopt;
    /// When present, the emission is `emission` times this texture's linear colour at the hit
    /// (glTF's emissiveTexture), looked up as diffuse_map is.
    std::optional<TextureMap> emission_map = std::nullopt;

    /// When present, the material is a cut-out (glTF alphaMode MASK): where its alpha,
    /// `base_alpha` times the diffuse map's alpha at the hit (dynrt/engine/alpha_mask.h), is
    /// below this cutoff, its surface is not there: camera, shadow, reflection and refraction
    /// rays all pass through it as if it had no triangle. In [0, 1].
    std::optional<float> alpha_cutoff = std::nullopt;
    /// glTF baseColorFactor's alpha, in [0, 1]: the alpha of a cut-out without a diffuse map,
    /// and the factor its map's alpha is multiplied by.
    float base_alpha = 1.0f;

    /// Whether a hit on this material spawns reflection or refraction rays.
    bool traces_secondary() const {
        return reflectance.x > 0.0f || reflectance.y > 0.0f || reflectance.z > 0.0f ||
               transmittance.x > 0.0f || transmittance.y > 0.0f || transmittance.z > 0.0f;
    }
};

/// A triangle mesh in object space. `triangles` index into `positions`.
///
/// Copies share their arrays until one is written (SharedArray): objects that hold copies of
/// one mesh (a glTF mesh referenced by several nodes, the trees of a procedural forest) cost
/// its bytes once, and the engine builds one tree for all of them where their classes allow
/// (docs/animation.md, "Instancing").
struct Mesh {
    SharedArray<glm::vec3> positions;
    SharedArray<glm::uvec3> triangles;
    /// Per-vertex shading normals in object space, indexed as `positions` (unit length, or 0
    /// where none could be made), or empty: then the object is shaded with its triangles'
    /// geometric normals. The loaders fill them from the file (glTF NORMAL, BART's normals)
    /// or, where the file has none, with area_weighted_normals (vertex_normals.h); the
    /// renderer interpolates them at each hit (dynrt/engine/renderer.h, "Shading normals").
    SharedArray<glm::vec3> normals;
    /// Per-vertex texture coordinates (s, t), indexed as `positions`, or empty. s runs to the
    /// right and t down an image from its top-left corner (glTF's TEXCOORD_0 convention, and
    /// OpenImageIO's), one unit across the image.
    SharedArray<glm::vec2> texcoords;
};

/// One traceable thing. Unanimated and unskinned, its world-space triangles are
/// `transform * mesh.positions`; dynrt::anim::pose_scene gives them at any frame.
struct Object {
    /// For reports and errors: glTF "node/mesh" (with "#k" for the k-th primitive when a mesh
    /// has several), or the procedural spec that made it.
    std::string name;
    Mesh mesh;
    /// The node's world matrix in the rest pose (ignored by skinning, as glTF requires).
    glm::mat4 transform{1.0f};
    std::uint32_t material = 0;
    /// The node it hangs on (index into Scene::nodes), or -1 when it has none (procedural
    /// scenes): then `transform` never changes.
    std::int32_t node = -1;
    /// Joint influences when the object is skinned; vertex count as mesh.positions.
    std::optional<SkinWeights> skin;
    /// Position morph targets when it has some (with their normal deltas); vertex count as
    /// mesh.positions.
    std::optional<MorphTargets> morph;
};

/// A light of dynrt's shading model (renderer.h): what it is (`kind`: a point, a spot or a
/// directional light) and what it is sampled over (`shape`: a point, or an area around
/// `position`). Its colour at a hit is intensity * color * falloff, where the falloff is 1, or
/// 1 / d^2 when `inverse_square` (d the distance to the light), times glTF's range window and
/// a spot's cone (renderer.h, "Lights"). The name is historical: every kind is a PointLight.
struct PointLight {
    /// What a light is sampled over: a point, which casts hard shadows, or an area (a sphere's
    /// surface or a parallelogram), which casts soft ones. An area light lights a hit as the
    /// mean of point lights of the same intensity over its surface, estimated with one point
    /// per pixel sample (TraceSettings::sampling; docs/rendering.md "Samples per pixel and
    /// area lights").
    enum class Shape : std::uint8_t { point, sphere, quad };
    /// A point (or area) light shines every way from `position`; a spot only within a cone
    /// around `direction`; a directional light (a sun) shines along `direction` from infinitely
    /// far, the same at every point, and has no position.
    enum class Kind : std::uint8_t { point, spot, directional };

    glm::vec3 position{0.0f};
    float intensity = 1.0f;
    Shape shape = Shape::point;
    /// A sphere light's radius (> 0).
    float radius = 0.0f;
    /// A quad light's two edges: its points are position + a edge_u + b edge_v for a, b in
    /// [-1/2, 1/2] (so `position` is its centre); not parallel.
    glm::vec3 edge_u{0.0f}, edge_v{0.0f};

    Kind kind = Kind::point;
    /// Linear RGB the intensity is multiplied by, each channel finite and >= 0.
    glm::vec3 color{1.0f};
    /// A spot's axis and a directional light's direction of travel (from the light toward
    /// what it lights); unit length once posed. glTF's lights point down their node's -Z.
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
    /// A spot's cone, in radians from its axis: full intensity within inner_cone, none past
    /// outer_cone, and glTF's smooth ramp between (0 <= inner_cone < outer_cone <= pi / 2).
    float inner_cone = 0.0f;
    float outer_cone = 0.7853982f;
    /// Point and spot lights: intensity / d^2 (glTF's candela); otherwise (dynrt's own
    /// lights, the default) no distance falloff.
    bool inverse_square = false;
    /// Point and spot lights: beyond this distance they light nothing, with glTF's window
    /// clamp(1 - (d / range)^4, 0, 1) before it; 0 means no range.
    float range = 0.0f;
    /// The node the light hangs on (index into Scene::nodes), or -1: then position, direction
    /// and edges are in that node's space and the renderer poses them every frame.
    std::int32_t node = -1;
    /// For messages: the file's name for it, or empty (then it is named by its index).
    std::string name{};

    bool operator==(const PointLight&) const = default;
};

struct Scene {
    /// Where the scene came from (file path or spec string), for messages.
    std::string source;
    std::vector<Object> objects;
    /// Always holds at least one material (index 0, the default) once a loader has run.
    std::vector<Material> materials;
    /// Lights the scene itself defines; empty means "use the renderer's default light".
    std::vector<PointLight> lights;
    /// The node hierarchy, parents before children; empty for procedural scenes.
    std::vector<Node> nodes;
    std::vector<Skin> skins;
    /// Keyframe clips in file order.
    std::vector<AnimationClip> clips;
    /// Perspective cameras in node order; the first one is "the scene's camera".
    std::vector<SceneCamera> cameras;
    /// User-added motions, applied in this order (dynrt::anim::add_procedural_motions).
    std::vector<ProceduralMotion> motions;
    /// Present when the file says how it is to be shown (BART's AFF): then cameras[0] is its
    /// viewpoint, and its image size, frame rate and background are the defaults.
    std::optional<SceneSetup> setup;
    /// Images that materials map (Material::diffuse_map).
    std::vector<Texture> textures;
    /// The files the scene was read from: the scene file first, then each file it pulled in
    /// (a glTF's buffers in files of their own, BART's includes, texture images), each once, as
    /// paths the program can open; empty for a procedural spec or a document read from memory.
    /// What `render --resume` digests to tell a changed scene from the one a job began with.
    std::vector<std::string> files;
    /// What the file says that the scene model leaves out (glTF's textures other than base
    /// colour, BART's light colours...), one short line each, for the report; empty when
    /// nothing was left out.
    std::vector<std::string> ignored;

    std::size_t triangle_count() const;
};

}  // namespace dynrt
