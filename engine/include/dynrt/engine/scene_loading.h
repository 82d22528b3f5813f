#pragma once
// Scene front ends: glTF 2.0 files, BART's AFF files, OBJ, PLY, FBX, Collada and the other
// formats assimp reads, and procedural spec strings, all producing the scene model.

#include "dynrt/scene/scene.h"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace dynrt {

/// Loads `source`. A file that exists is read by its kind, told by extension and content: .gltf
/// or .glb (case-insensitive), or GLB's magic "glTF" in its first bytes, as glTF; .aff as BART's
/// AFF (load_aff); anything else through assimp (load_assimp), which tells OBJ, PLY, FBX,
/// Collada... by extension and content, and refuses a file of no kind it reads with
/// "X: not a scene file dynrt reads (glTF .gltf/.glb, BART .aff, OBJ, PLY, ...)". A `source`
/// that names no file but looks like a path (a '/', or an extension such as ".obj") is
/// "X: no such file"; anything else is parsed as a procedural spec (make_procedural_scene).
/// Throws SceneError with a one-line message naming the file or spec, the object and the
/// problem. The result has at least one triangle and only finite positions and in-range
/// indices.
Scene load_scene(const std::string& source);

/// Reads a scene file through assimp 5 (OBJ with its MTL, PLY, FBX, Collada .dae, STL, 3DS,
/// Blender...; assimp tells the format by extension and content). Polygons are triangulated;
/// every mesh of every node becomes one Object named "node/mesh" ("node/mesh#k" for the k-th of
/// a node's meshes), with the node's world matrix as transform. What animates the scene comes
/// along, as from glTF: the node tree (Scene::nodes, parents first), node animations as clips
/// (Scene::clips), bones as skins with up to 8 influences per vertex (Object::skin),
/// perspective cameras (Scene::cameras), point and spot lights (Scene::lights), Phong
/// materials with their diffuse textures (docs/scene-input.md "Scene input"). Morph targets, mesh
/// animations, other lights and other textures are left out with a warning on stderr or a
/// line in Scene::ignored. Throws SceneError naming the file and the object, with assimp's own
/// message when its reader fails.
Scene load_assimp(const std::filesystem::path& path);

/// Reads a glTF 2.0 file (.gltf with external or embedded buffers, or .glb). Every triangle
/// primitive of the default scene (or scene 0) becomes one Object in node-tree order, named
/// "node/mesh" ("node/mesh#k" for the k-th primitive of a multi-primitive mesh), with the
/// node's world matrix as transform and materials mapped from metallic-roughness,
/// KHR_materials_transmission and KHR_materials_ior (docs/scene-input.md "Materials"). Strips and fans are
/// converted to lists; points and lines are skipped with a warning on stderr. What animates
/// the scene comes along, validated: the default scene's nodes (Scene::nodes, parents first,
/// Object::node), skins with up to 8 influences per vertex (Object::skin), position morph
/// targets with the default weights applied to mesh.positions (Object::morph), every animation
/// as a clip (Scene::clips) and the perspective cameras (Scene::cameras). Throws SceneError
/// naming the file and the element ("animation 'Walk' channel 3: ...").
Scene load_gltf(const std::filesystem::path& path);

/// Reads a BART scene (Lext, Assarsson and Moller, "BART: A Benchmark for Animated Ray
/// Tracing", IEEE CG&A 21(2), 2001): the AFF file at `path` and the files it includes, relative
/// to the including file. Its viewpoint becomes cameras[0] and Scene::setup (image size, frame
/// rate, frame count, background); `x`/`k` transforms become animated nodes (rigid objects),
/// `tpa` triangles morphing objects (deformable), the rest static objects, one per material;
/// materials keep their specular colour as reflectance, T and the index of refraction
/// (docs/scene-input.md "Materials"); textures are ignored. The conversion rules are in
/// engine/src/loaders/aff_scene.h. Throws SceneError naming the file and line.
Scene load_aff(const std::filesystem::path& path);

/// Reads AFF text as if it were the file `name`, as load_aff does (includes resolve relative
/// to `name`'s folder and are read from the filesystem). Lets tests and the fuzz target feed
/// text without writing it out.
Scene load_aff_text(std::string_view text, const std::filesystem::path& name);

/// The two encodings of a glTF 2.0 document.
enum class GltfFormat { json, binary };

/// Reads a glTF 2.0 document held in memory (`bytes`, borrowed for the call), as load_gltf
/// does, with `name` standing for the file in errors and as Scene::source. The document must be
/// self-contained: buffers come from data: URIs or the GLB BIN chunk, and a buffer given by any
/// other URI is a SceneError; the filesystem is never touched. Same result and errors as
/// load_gltf otherwise. Lets the fuzz targets and other embedders load untrusted bytes.
Scene load_gltf_from_memory(std::span<const unsigned char> bytes, GltfFormat format, const std::string& name);

/// The most triangles a procedural spec may make, per part and in total: 100M triangles already
/// need about 2.4 GB of vertices and indices.
inline constexpr std::uint64_t kMaxProceduralTriangles = 100'000'000;

/// Builds a procedural scene from its spec (grammar in README.md, "Procedural scenes"):
/// `sphere:N`, `soup:N`, `plane:N`, joined with '+', each optionally placed with
/// `@x,y,z[,scale]` and coloured with `#rrggbb`. Exact definitions so other tools can build the
/// same triangles. Throws SceneError for a malformed spec, or for one making more than
/// `max_triangles` triangles (per part or in total), before any mesh is built. A lower limit
/// keeps a caller feeding arbitrary specs (the fuzz target) from building huge meshes.
Scene make_procedural_scene(const std::string& spec, std::uint64_t max_triangles = kMaxProceduralTriangles);

/// Throws SceneError when `scene` has no triangles, an index out of range, a non-finite
/// position or transform, or a material with a non-finite or negative reflectance or
/// transmittance or a non-finite or non-positive ior, naming the object and the material
/// ("object 'x': material 'glass' (index 2): ior 0 must be finite and > 0"; a material no
/// object uses is named alone). Loaders call it; callers building scenes by hand may too.
void check_scene(const Scene& scene);

/// The bundled default scene (scenes/default.gltf), found next to the source tree or the
/// installed executable.
std::filesystem::path default_scene_path();

}  // namespace dynrt
