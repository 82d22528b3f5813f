#pragma once

// The AFF parser: text in BART's Animated File Format to a plain model of what the files say,
// with no interpretation (no triangulation, no transform evaluation, no interpolation). The
// scene conversion (issue 8) reads this model.
//
// Format: J. Lext, U. Assarsson, T. Moller, "BART: A Benchmark for Animated Ray Tracing",
// IEEE Computer Graphics and Applications 21(2), 2001, and its file format description
// (AFF, an animated extension of E. Haines' NFF from the Standard Procedural Databases).
// Commands as found in the kitchen, robots and museum scenes:
//   v / from / at / up / angle / hither / resolution     viewpoint (NFF)
//   b r g b                                               background colour
//   am r g b                                              ambient light
//   l x y z [r g b], la name x y z [r g b]                point light, animated light
//   f r g b Kd Ks shine T ior                             NFF material
//   fm amb(3) diff(3) spec(3) shine T ior                 BART material
//   p n / pp n                                            polygon, polygon with normals
//   tt tex / ttp tex                                      textured triangle (3 x: x y z u v),
//                                                         patch (3 x: x y z nx ny nz u v)
//   s x y z r, c base(3) r0 apex(3) r1                    sphere, cone (NFF)
//   m, vertices n, normals n, texturecoords n [tex],
//     triangles n                                         mesh block: `triangles` ends it; each
//                                                         triangle lists 3 vertex indices, then 3
//                                                         normal indices if the mesh has normals,
//                                                         then 3 texture indices if it has them
//   i detail file                                         include, relative to the including file;
//                                                         skipped when detail exceeds `d`'s level
//   d level                                               detail level (0 by default)
//   xs scale(3) axis(3) angle_deg translate(3) { ... }    static transform
//   x name { ... }                                        animated transform, bound to `k name`
//   k name { transl n (t x y z T C B)*  rot n (t ax ay az angle_deg T C B)*
//            scale n (t x y z T C B)* }                  keyframes, Kochanek-Bartels TCB
//   tpa n (t, 3 x (x y z nx ny nz))*                      triangle with per-vertex keyframes
//   a start end frames                                    animation time range and frame count
// Comments start with `#` (NFF) or `%` (seen in museum5.aff) and run to the end of the line.
// Where the paper is silent, BART's own previewer (parse.c, animation.c, kbsplpos.c,
// kbsplrot.c) decides: mesh triangles list vertex, then normal, then texture indices; `rot`
// angles are degrees; a hither below 0.0001 reads as 1. `visibility` keys (in BART's format
// but unused by its three scenes) are refused with an error.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dynrt::aff {

using Vec2 = std::array<float, 2>;
using Vec3 = std::array<float, 3>;

/// Where a command came from, for messages of later stages.
struct SourceLocation {
    std::string file;
    int line = 0;
};

/// `v`: the NFF viewpoint. `angle_deg` is the full vertical field of view: BART's format
/// description reads it "in the y-direction (from top to bottom)" with aspect width / height.
struct View {
    Vec3 from{}, at{}, up{};
    float angle_deg = 0;
    float hither = 0;
    int width = 0, height = 0;
};

/// `l`: a point light; `la` names its `k` block (`animation`), whose `transl` moves it.
struct Light {
    Vec3 position{};
    std::optional<Vec3> color;  ///< absent: NFF's default white
    std::string animation;
    int node = 0;  ///< the transform node it sits under (index into AffModel::nodes)
    SourceLocation where;
};

/// `f` or `fm`. For `f`, ambient is zero, diffuse is colour * Kd and specular is Ks * colour
/// (NFF); for `fm` all three are given.
struct Material {
    Vec3 ambient{}, diffuse{}, specular{};
    float shine = 0, transmittance = 0, ior = 1;
};

/// Every shape below records the material in force (index into AffModel::materials, -1 for
/// none) and the transform node it sits under (index into AffModel::nodes, 0 the root).
struct Placement {
    int material = -1;
    int node = 0;
    SourceLocation where;
};

/// `p`, `pp`, `tt`, `ttp`: one planar polygon; normals and uvs empty or one per vertex.
struct Polygon : Placement {
    std::vector<Vec3> vertices, normals;
    std::vector<Vec2> uvs;
    std::string texture;
};

/// `s`.
struct Sphere : Placement {
    Vec3 center{};
    float radius = 0;
};

/// `c`: a cone or cylinder without end caps.
struct Cone : Placement {
    Vec3 base{}, apex{};
    float base_radius = 0, apex_radius = 0;
};

/// `m` ... `triangles`: an indexed triangle mesh. Index arrays are empty when the mesh has no
/// such attribute, otherwise one triple per triangle; every index was checked in range.
struct Mesh : Placement {
    std::vector<Vec3> vertices, normals;
    std::vector<Vec2> uvs;
    std::string texture;
    std::vector<std::array<std::uint32_t, 3>> vertex_indices, normal_indices, uv_indices;
};

/// One key of `tpa`: the triangle's three vertices and normals at `time`.
struct TriangleKey {
    float time = 0;
    std::array<Vec3, 3> positions{}, normals{};
};

/// `tpa`: a triangle whose vertices have their own keyframes (a deforming object).
struct AnimatedTriangle : Placement {
    std::vector<TriangleKey> keys;
};

/// A key of a `transl` or `scale` track, with Kochanek-Bartels tension, continuity, bias.
struct VectorKey {
    float time = 0;
    Vec3 value{};
    float tension = 0, continuity = 0, bias = 0;
};

/// A key of a `rot` track: rotation by `angle_deg` about `axis` (not necessarily unit).
struct RotationKey {
    float time = 0;
    Vec3 axis{};
    float angle_deg = 0;
    float tension = 0, continuity = 0, bias = 0;
};

/// `k name { ... }`: the tracks of one animated transform, light or the camera ("camera").
struct Animation {
    std::string name;
    std::vector<VectorKey> translations, scales;
    std::vector<RotationKey> rotations;
    SourceLocation where;
};

/// A node of the transform hierarchy. Node 0 is the root (identity). A static node (`xs`)
/// applies scale, then the rotation, then the translation; an animated one (`x name`) is
/// bound by name to an Animation.
struct TransformNode {
    enum class Kind { root, fixed, animated };
    Kind kind = Kind::root;
    int parent = -1;
    Vec3 scale{1, 1, 1};
    Vec3 rotation_axis{0, 0, 1};
    float rotation_deg = 0;
    Vec3 translation{};
    std::string animation;
    SourceLocation where;
};

/// `a start end frames`.
struct AnimationParams {
    float start_time = 0, end_time = 0;
    int frame_count = 0;
};

/// Everything one top-level AFF file and its includes say, in file order.
struct AffModel {
    std::optional<View> view;
    std::optional<Vec3> background, ambient;
    std::optional<AnimationParams> animation_params;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<Polygon> polygons;
    std::vector<Sphere> spheres;
    std::vector<Cone> cones;
    std::vector<Mesh> meshes;
    std::vector<AnimatedTriangle> animated_triangles;
    std::vector<TransformNode> nodes;  ///< nodes[0] is the root
    std::vector<Animation> animations;
    std::vector<std::string> files;  ///< every file read, the top-level one first

    /// The animation called `name`, or null.
    [[nodiscard]] const Animation* find_animation(std::string_view name) const;
};

/// Parses the AFF file at `path` and, recursively, the files it includes (each resolved
/// relative to the directory of the file that includes it). Throws SceneError with one line
/// "file:line: what is wrong" on unreadable files, unknown commands, missing or malformed
/// numbers, out-of-range mesh indices, unbalanced braces and include cycles. Thread safe.
[[nodiscard]] AffModel parse_aff_file(const std::filesystem::path& path);

/// Parses AFF text as if it were the file `name`; includes resolve relative to
/// `name`'s directory. For tests and for text already in memory.
[[nodiscard]] AffModel parse_aff_text(std::string_view text, const std::filesystem::path& name);

}  // namespace dynrt::aff
