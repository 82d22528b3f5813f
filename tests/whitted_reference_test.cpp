// Whitted's reflection and refraction rays (renderer.h, top comment) against the exact
// reference renderer (tests/reference/reference_renderer.h), on procedural scenes built here:
// two parallel mirrors, a glass sphere over a checkerboard, a glass prism whose pixels see
// total internal reflection on one side of a row and refraction on the other, the first two
// again 10^5 from the origin, and max_depth = 0 against the same scene without mirror or glass.
// With smooth shading normals (renderer.h, "Shading normals"): the glass sphere and a mirror
// ball shaded smooth, and a mirror whose vertex normals are bent so far that at some pixels
// the split must fall back to the geometric normal.
//
// WhittedReference checks the reference on its own, against answers worked out here in closed
// form (a mirror reflecting a quad, a pane of ior 1, the critical angle inside a glass cube)
// and against itself (the recursion changes the image, a far scene looks like the near one,
// depth 0 is the Phong-only model), so that the oracle is trusted before anything is compared
// with it. WhittedRenderer compares dynrt::Renderer with it pixel by pixel, for the packet and
// the single-ray tracer, which must also agree with each other bit for bit: the camera ray's
// hit object and triangle wherever the reference says they are determined, colour within 1e-3
// per channel wherever the whole ray tree is unambiguous (as in render_reference_test.cpp),
// and bounds on the ambiguous pixels and on the mirror or glass pixels compared, so that no
// case passes by skipping everything. WhittedRendererDepth checks the renderer's max_depth.

#include "same_bits.h"
#include "bvh_test_geometry.h"
#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/scene/vertex_normals.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace dynrt::reference {
namespace {

// ---- Building scenes -----------------------------------------------------------------------

/// Where a scene built in local coordinates is put: world = offset + scale * local. Lights and
/// the camera move with it; Phong has no distance falloff, so the image stays the same.
struct Placement {
    double scale = 1.0;
    glm::dvec3 offset{0.0};

    glm::vec3 point(const glm::dvec3& local) const { return glm::vec3(offset + scale * local); }
};

/// About 10^5 from the origin, where float positions are good to 2^-7 = 0.008 and the
/// renderer pushes a secondary ray's origin 256 ulps, some 2 units, off the surface. The scene
/// is scaled too, so that its parts stay large next to that push: the reference must leave open
/// whatever passes within the push of an edge (Tolerances::shadow_rel), and a glass sphere's
/// facets 0.27 units across, translated unscaled, would be all edge. At 4000 the facets are
/// ~1000 units across and the scene sits 4 to 8 times its size from the origin.
const Placement kFar{4000.0, {1.0e5, -0.5e5, 0.75e5}};

Material phong(glm::vec3 diffuse, glm::vec3 specular = glm::vec3(0.2f), float shininess = 32.0f) {
    Material m;
    m.diffuse = diffuse;
    m.specular = specular;
    m.shininess = shininess;
    return m;
}

Material mirror(glm::vec3 reflectance) {
    Material m = phong(glm::vec3(0.05f), glm::vec3(0.3f), 64.0f);
    m.name = "mirror";
    m.reflectance = reflectance;
    return m;
}

Material glass(float transmittance, float ior) {
    Material m = phong(glm::vec3(0.02f), glm::vec3(0.3f), 64.0f);
    m.name = "glass";
    m.transmittance = glm::vec3(transmittance);
    m.ior = ior;
    return m;
}

class SceneBuilder {
public:
    explicit SceneBuilder(Placement place = {}) : place_(place) {
        scene_.source = "whitted test";
        scene_.materials.push_back(Material{});
    }

    std::uint32_t material(Material m) {
        scene_.materials.push_back(std::move(m));
        return static_cast<std::uint32_t>(scene_.materials.size() - 1);
    }

    /// A mesh given in local coordinates; returns its object index.
    int mesh(std::string name, const std::vector<glm::dvec3>& local,
             std::vector<glm::uvec3> triangles, std::uint32_t material) {
        Object object;
        object.name = std::move(name);
        for (const glm::dvec3& p : local) object.mesh.positions.push_back(place_.point(p));
        object.mesh.triangles = std::move(triangles);
        object.material = material;
        scene_.objects.push_back(std::move(object));
        return static_cast<int>(scene_.objects.size() - 1);
    }

    /// Gives object `object` vertex normals: its area-weighted ones, or `normals` (local, one
    /// per vertex; placement only translates and scales uniformly, so they stay as they are).
    void smooth(int object, std::vector<glm::vec3> normals = {}) {
        Mesh& mesh = scene_.objects[static_cast<std::size_t>(object)].mesh;
        mesh.normals = normals.empty() ? area_weighted_normals(mesh.positions, mesh.triangles) : std::move(normals);
    }

    /// Quad a b c d as triangles (a, b, c) and (a, c, d): its winding normal is (b - a) x (c - a).
    int quad(std::string name, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d,
             std::uint32_t material) {
        return mesh(std::move(name), {a, b, c, d}, {{0, 1, 2}, {0, 2, 3}}, material);
    }

    void light(const glm::dvec3& local, float intensity = 1.0f) {
        scene_.lights.push_back(PointLight{place_.point(local), intensity});
    }

    Camera camera(const glm::dvec3& eye, const glm::dvec3& target, float fov_y_deg,
                  glm::vec3 up = glm::vec3(0.0f, 1.0f, 0.0f)) const {
        Camera c;
        c.eye = place_.point(eye);
        c.target = place_.point(target);
        c.up = up;
        c.fov_y_deg = fov_y_deg;
        return c;
    }

    const Scene& scene() const { return scene_; }

private:
    Placement place_;
    Scene scene_;
};

/// The convex polygon `polygon` (counter-clockwise seen from +z, in xy) extruded from z0 to
/// z1 as a closed mesh wound outward, each point then passed through `transform`.
template <class Transform>
void extruded(const std::vector<glm::dvec2>& polygon, double z0, double z1, Transform transform,
              std::vector<glm::dvec3>& positions, std::vector<glm::uvec3>& triangles) {
    const auto n = static_cast<std::uint32_t>(polygon.size());
    for (const glm::dvec2& p : polygon) positions.push_back(transform(glm::dvec3(p, z0)));
    for (const glm::dvec2& p : polygon) positions.push_back(transform(glm::dvec3(p, z1)));
    for (std::uint32_t i = 1; i + 1 < n; ++i) {
        triangles.push_back({n, n + i, n + i + 1});  // top cap, facing +z
        triangles.push_back({0, i + 1, i});          // bottom cap, facing -z
    }
    for (std::uint32_t i = 0; i < n; ++i) {  // sides: (p_{i+1} - p_i) x z points outward
        const std::uint32_t j = (i + 1) % n;
        triangles.push_back({i, j, n + j});
        triangles.push_back({i, n + j, n + i});
    }
}

/// Six times the signed volume: positive when a closed mesh is wound outward.
double signed_volume6(const std::vector<glm::dvec3>& p, const std::vector<glm::uvec3>& tris) {
    double v = 0.0;
    for (const glm::uvec3& t : tris) v += glm::dot(p[t.x], glm::cross(p[t.y], p[t.z]));
    return v;
}

/// Icosphere (bvh_test_geometry.h) in local coordinates, wound outward.
void icosphere(int levels, double radius, const glm::dvec3& center,
               std::vector<glm::dvec3>& positions, std::vector<glm::uvec3>& triangles) {
    const bvh::testing::ClosedMesh m = bvh::testing::icosphere_mesh(levels);
    for (const glm::vec3& v : m.vertices) positions.push_back(center + radius * glm::dvec3(v));
    for (const auto& f : m.faces) triangles.push_back({f[0], f[1], f[2]});
}

/// A scene, its camera and how it is rendered.
struct Shot {
    Scene scene;
    Camera camera;
    RenderOptions options;
};

RenderOptions small_image(int size, int max_depth) {
    RenderOptions options;
    options.width = size;
    options.height = size;
    options.secondary.max_depth = max_depth;
    return options;
}

// (a) Two parallel mirrors (x = -2 facing +x, x = +2 facing -x) over a grey floor, a red box
// turned 30 degrees floating between them, seen at an angle from between the mirrors: the box
// and the floor repeat in the mirrors, fainter at each bounce.
Shot mirrors_shot(Placement place = {}) {
    SceneBuilder b(place);
    const std::uint32_t mirror_mat = b.material(mirror(glm::vec3(0.8f)));
    const std::uint32_t floor_mat = b.material(phong(glm::vec3(0.55f, 0.55f, 0.5f)));
    const std::uint32_t box_mat = b.material(phong(glm::vec3(0.85f, 0.15f, 0.1f), glm::vec3(0.4f)));
    b.quad("left mirror", {-2, -1.5, 4}, {-2, -1.5, -4}, {-2, 1.5, -4}, {-2, 1.5, 4}, mirror_mat);
    b.quad("right mirror", {2, -1.5, -4}, {2, -1.5, 4}, {2, 1.5, 4}, {2, 1.5, -4}, mirror_mat);
    b.quad("floor", {-2, -1.5, -4}, {-2, -1.5, 4}, {2, -1.5, 4}, {2, -1.5, -4}, floor_mat);
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    const double c = std::cos(glm::radians(30.0)), s = std::sin(glm::radians(30.0));
    extruded({{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}, -0.5, 0.5,
             [&](glm::dvec3 p) {  // box [-0.5, 0.5]^3 turned about y, centred at (0, -0.3, -0.5)
                 return glm::dvec3(c * p.x + s * p.z, p.y - 0.3, -s * p.x + c * p.z - 0.5);
             },
             positions, triangles);
    b.mesh("box", positions, triangles, box_mat);
    b.light({0.5, 4.0, 2.0});
    return Shot{b.scene(), b.camera({1.2, 0.3, 2.5}, {-2.0, -0.5, -0.5}, 60.0f),
                small_image(64, 5)};
}

/// A checkerboard floor y = 0 over [-4, 4]^2, two materials.
void checkerboard(SceneBuilder& b) {
    const std::uint32_t light_mat = b.material(phong(glm::vec3(0.9f, 0.85f, 0.7f)));
    const std::uint32_t dark_mat = b.material(phong(glm::vec3(0.1f, 0.2f, 0.45f)));
    for (int parity = 0; parity < 2; ++parity) {
        std::vector<glm::dvec3> positions;
        std::vector<glm::uvec3> triangles;
        for (int i = 0; i < 8; ++i) {
            for (int j = 0; j < 8; ++j) {
                if ((i + j) % 2 != parity) continue;
                const double x = -4.0 + i, z = -4.0 + j;
                const auto base = static_cast<std::uint32_t>(positions.size());
                positions.insert(positions.end(),
                                 {{x, 0, z}, {x, 0, z + 1}, {x + 1, 0, z + 1}, {x + 1, 0, z}});
                triangles.push_back({base, base + 1, base + 2});  // facing +y
                triangles.push_back({base, base + 2, base + 3});
            }
        }
        b.mesh(parity ? "dark cells" : "light cells", positions, triangles,
               parity ? dark_mat : light_mat);
    }
}

// (b) A glass sphere (icosphere, 320 triangles, transmittance 0.9, ior 1.5) floating over a
// checkerboard floor of two materials, one light; flat, or shaded smooth.
Shot glass_shot(Placement place = {}, bool smooth = false) {
    SceneBuilder b(place);
    checkerboard(b);
    const std::uint32_t glass_mat = b.material(glass(0.9f, 1.5f));
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    icosphere(2, 1.0, {0.0, 1.2, 0.0}, positions, triangles);
    const int sphere = b.mesh("glass sphere", positions, triangles, glass_mat);
    if (smooth) b.smooth(sphere);
    b.light({3.0, 6.0, 2.0});
    return Shot{b.scene(), b.camera({0.3, 2.6, 5.0}, {0.0, 0.7, 0.0}, 45.0f),
                small_image(64, 5)};
}

// (d) A mirror ball shaded smooth (icosphere, 1280 triangles, reflectance 0.8) over the
// checkerboard, beside a diffuse block it reflects.
Shot mirror_ball_shot() {
    SceneBuilder b;
    checkerboard(b);
    const std::uint32_t mirror_mat = b.material(mirror(glm::vec3(0.8f)));
    const std::uint32_t block_mat = b.material(phong(glm::vec3(0.8f, 0.3f, 0.1f), glm::vec3(0.3f)));
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    icosphere(3, 1.0, {0.0, 1.1, 0.0}, positions, triangles);
    b.smooth(b.mesh("mirror ball", positions, triangles, mirror_mat));
    positions.clear();
    triangles.clear();
    extruded({{1.4, -0.5}, {2.4, -0.5}, {2.4, 0.5}, {1.4, 0.5}}, -1.5, -0.5,
             [](glm::dvec3 p) { return glm::dvec3(p.x, p.z + 1.5, p.y - 1.0); }, positions, triangles);
    b.mesh("block", positions, triangles, block_mat);
    b.light({3.0, 6.0, 2.0});
    return Shot{b.scene(), b.camera({0.5, 2.2, 4.5}, {0.2, 0.9, 0.0}, 40.0f), small_image(64, 5)};
}

// (e) A mirror y = 0 (reflectance 0.9) whose vertex normals lean 35 degrees toward +x and -x
// at its left (far) and right (near) edges, seen at a grazing angle from +x over a red wall at
// x = -4 and a blue one at z = -4: toward its near edge the interpolated normal leans along
// the view so far that the ray comes from behind it, and the split falls back to the
// geometric normal (shading_split_holds); toward the far edge it holds.
constexpr double kBentMirrorLeanDeg = 35.0;

Shot bent_mirror_shot() {
    SceneBuilder b;
    const std::uint32_t mirror_mat = b.material(mirror(glm::vec3(0.9f)));
    const std::uint32_t red_mat = b.material(phong(glm::vec3(0.8f, 0.15f, 0.1f)));
    const std::uint32_t blue_mat = b.material(phong(glm::vec3(0.1f, 0.2f, 0.8f)));
    const int m = b.quad("bent mirror", {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, mirror_mat);  // +y
    const float s = float(std::sin(glm::radians(kBentMirrorLeanDeg)));
    const float c = float(std::cos(glm::radians(kBentMirrorLeanDeg)));
    b.smooth(m, {{s, c, 0}, {s, c, 0}, {-s, c, 0}, {-s, c, 0}});
    b.quad("red wall", {-4, -1, -4}, {-4, -1, 4}, {-4, 4, 4}, {-4, 4, -4}, red_mat);
    b.quad("blue wall", {-4, -1, -4}, {-4, 4, -4}, {4, 4, -4}, {4, -1, -4}, blue_mat);
    b.light({1.0, 5.0, 3.0});
    return Shot{b.scene(), b.camera({6.0, 0.9, 0.5}, {-1.0, 0.0, 0.0}, 50.0f), small_image(64, 5)};
}

// (c) A glass prism (ior 1.5) seen through its entry face x = 0, nearly head-on: inside, the
// rays meet the exit face x = 2 - y tan(43 deg) at about 43 degrees, just past the critical
// angle asin(1 / 1.5) = 41.8: rays tilted up by more than 1.2 degrees inside (1.8 outside)
// refract out toward a blue wall at x = 6, the others are reflected totally down through the
// bottom face toward a green floor at y = -2.
constexpr double kPrismExitDeg = 43.0;

Shot prism_shot() {
    SceneBuilder b;
    const std::uint32_t glass_mat = b.material(glass(0.9f, 1.5f));
    const std::uint32_t wall_mat = b.material(phong(glm::vec3(0.15f, 0.3f, 0.9f)));
    const std::uint32_t floor_mat = b.material(phong(glm::vec3(0.2f, 0.8f, 0.25f)));
    const double tan_exit = std::tan(glm::radians(kPrismExitDeg));
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    extruded({{0, -1}, {2 + tan_exit, -1}, {2 - tan_exit, 1}, {0, 1}}, -1.0, 1.0,
             [](glm::dvec3 p) { return p; }, positions, triangles);
    b.mesh("prism", positions, triangles, glass_mat);
    b.quad("wall", {6, -3, -4}, {6, -3, 4}, {6, 4, 4}, {6, 4, -4}, wall_mat);
    b.quad("floor", {-1, -2, -4}, {-1, -2, 4}, {6, -2, 4}, {6, -2, -4}, floor_mat);
    b.light({4.0, 2.5, 4.0});
    return Shot{b.scene(), b.camera({-5.0, 0.0, 0.2}, {0.0, 0.0, 0.2}, 16.0f),
                small_image(64, 5)};
}

// ---- Rendering and comparing ---------------------------------------------------------------

ReferenceFrame reference_of(const Shot& shot, const RenderOptions& options) {
    anim::PosedScene posed;
    anim::pose_scene(shot.scene, 0, posed);
    const ReferenceTracer tracer(shot.scene, posed);
    return render_reference(shot.scene, tracer, shot.camera, options.width, options.height,
                            shading_from(shot.scene, options));
}

ReferenceFrame reference_of(const Shot& shot) { return reference_of(shot, shot.options); }

RenderedFrame render_with(const Shot& shot, Tracer tracer) {
    RenderOptions options = shot.options;
    options.tracer = tracer;
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(shot.scene, shot.camera, 0, frame);
    return frame;
}

/// Whether the pixel's colour is compared: hit and the whole ray tree determined.
bool determined(const ReferencePixel& p) {
    return p.hit.ambiguity == Ambiguity::kNone && !p.shading_ambiguous;
}

int count_open(const ReferenceFrame& ref) {
    return static_cast<int>(std::count_if(ref.pixels.begin(), ref.pixels.end(),
                                          [](const ReferencePixel& p) { return !determined(p); }));
}

double max_abs_diff(const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 d = glm::abs(a - b);
    return std::max({d.x, d.y, d.z});
}

/// Pixels whose colours differ by more than `tol` in some channel.
int count_different(const ReferenceFrame& a, const ReferenceFrame& b, double tol) {
    int n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        n += max_abs_diff(a.pixels[i].color, b.pixels[i].color) > tol;
    }
    return n;
}

int count_different(const RenderedFrame& a, const RenderedFrame& b, float tol) {
    int n = 0;
    for (std::size_t i = 0; i < a.color.size(); ++i) {
        const glm::vec3 d = glm::abs(a.color[i] - b.color[i]);
        n += std::max({d.x, d.y, d.z}) > tol;
    }
    return n;
}

using dynrt::test::same_bits;

/// Every buffer of the two frames, bit for bit; on failure names the first differing pixel.
::testing::AssertionResult frames_identical(const RenderedFrame& a, const RenderedFrame& b) {
    if (a.width != b.width || a.height != b.height) {
        return ::testing::AssertionFailure() << "sizes differ";
    }
    if (same_bits(a.color, b.color) && same_bits(a.depth, b.depth) &&
        same_bits(a.object, b.object) && same_bits(a.prim, b.prim) &&
        same_bits(a.normal, b.normal)) {
        return ::testing::AssertionSuccess();
    }
    for (std::size_t i = 0; i < a.color.size(); ++i) {
        if (std::memcmp(&a.color[i], &b.color[i], sizeof(glm::vec3)) != 0 ||
            std::memcmp(&a.depth[i], &b.depth[i], sizeof(float)) != 0 ||
            a.object[i] != b.object[i] || a.prim[i] != b.prim[i] ||
            std::memcmp(&a.normal[i], &b.normal[i], sizeof(glm::vec3)) != 0) {
            const int x = static_cast<int>(i % static_cast<std::size_t>(a.width));
            const int y = static_cast<int>(i / static_cast<std::size_t>(a.width));
            return ::testing::AssertionFailure()
                   << "first difference at (" << x << "," << y << "): object " << a.object[i]
                   << " / " << b.object[i] << ", prim " << a.prim[i] << " / " << b.prim[i]
                   << ", colour (" << a.color[i].x << ", " << a.color[i].y << ", "
                   << a.color[i].z << ") / (" << b.color[i].x << ", " << b.color[i].y << ", "
                   << b.color[i].z << ")";
        }
    }
    return ::testing::AssertionFailure() << "buffer sizes differ";
}

// ---- The reference on its own --------------------------------------------------------------

/// Phong at point p with unit facing normal n, seen along unit direction d (renderer.h).
glm::dvec3 phong_at(const Material& m, const ReferenceShading& shading, const glm::dvec3& p,
                    const glm::dvec3& n, const glm::dvec3& d) {
    const glm::dvec3 kd(m.diffuse), ks(m.specular);
    glm::dvec3 color = shading.ambient * kd;
    for (const PointLight& light : shading.lights) {
        const glm::dvec3 l = glm::normalize(glm::dvec3(light.position) - p);
        const double n_dot_l = glm::dot(n, l);
        if (n_dot_l <= 0.0) continue;
        const glm::dvec3 r = 2.0 * n_dot_l * n - l;
        const double r_dot_v = std::max(0.0, glm::dot(r, -d));
        color += double(light.intensity) * (kd * n_dot_l + ks * std::pow(r_dot_v, m.shininess));
    }
    return color;
}

// A mirror z = 0 (reflectance (0.8, 0.6, 0.4)) seen from z = 1, and above the eye a diffuse
// quad z = 2 facing down, lit from the side (nothing casts a shadow): a pixel's colour is the
// mirror's own Phong at p plus kr times the quad's Phong where the reflected ray
// (d.x, d.y, -d.z) meets z = 2, or kr times the background where it misses the quad.
TEST(WhittedReference, MirrorReflectsAQuadAsWorkedOutByHand) {
    SceneBuilder b;
    const glm::vec3 kr(0.8f, 0.6f, 0.4f);
    const std::uint32_t mirror_mat = b.material(mirror(kr));
    const std::uint32_t quad_mat =
        b.material(phong(glm::vec3(0.9f, 0.3f, 0.2f), glm::vec3(0.5f), 16.0f));
    b.quad("mirror", {-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}, mirror_mat);  // +z
    const double qx0 = -1.0, qx1 = 2.0, qy0 = -1.5, qy1 = 1.0;
    b.quad("quad", {qx0, qy0, 2}, {qx0, qy1, 2}, {qx1, qy1, 2}, {qx1, qy0, 2}, quad_mat);  // -z
    b.light({4.0, 0.0, 1.0});
    const Scene& scene = b.scene();
    const Camera camera = b.camera({0.3, -0.4, 1.0}, {0.0, 0.0, 0.0}, 90.0f);
    const int size = 48;

    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const ReferenceTracer tracer(scene, posed);
    for (int max_depth : {1, 5}) {
        SCOPED_TRACE("max_depth " + std::to_string(max_depth));
        RenderOptions options = small_image(size, max_depth);
        const ReferenceShading shading = shading_from(scene, options);
        const ReferenceFrame ref = render_reference(scene, tracer, camera, size, size, shading);
        const packet::PinholeRays rays(camera, size, size);
        int on_quad = 0, off_quad = 0, open = 0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const ReferencePixel& pixel = ref.at(x, y);
                ASSERT_EQ(pixel.hit.object, 0) << "(" << x << "," << y << ") must see the mirror";
                if (!determined(pixel)) {
                    ++open;
                    continue;
                }
                const bvh::Ray ray = rays.ray(x, y);
                const glm::dvec3 d = glm::normalize(glm::dvec3(ray.dir));
                const glm::dvec3 eye(ray.org);
                const glm::dvec3 p = eye + (-eye.z / d.z) * d;
                glm::dvec3 expected =
                    phong_at(scene.materials[mirror_mat], shading, p, {0, 0, 1}, d);
                const glm::dvec3 r(d.x, d.y, -d.z);
                const glm::dvec3 q = p + (2.0 / r.z) * r;
                const bool hits_quad = q.x > qx0 && q.x < qx1 && q.y > qy0 && q.y < qy1;
                const glm::dvec3 reflected =
                    hits_quad ? phong_at(scene.materials[quad_mat], shading, q, {0, 0, -1}, r)
                              : shading.background;
                expected += glm::dvec3(kr) * reflected;
                (hits_quad ? on_quad : off_quad)++;
                EXPECT_LT(max_abs_diff(pixel.color, expected), 1e-9)
                    << "(" << x << "," << y << ") " << (hits_quad ? "reflects the quad" : "misses");
            }
        }
        EXPECT_GT(on_quad, size * size / 8);
        EXPECT_GT(off_quad, size * size / 8);
        EXPECT_LT(open, size * size / 20) << "the quad's outline only";
    }
}

// A pane of ior 1 (transmittance 1, no colour of its own) at z = 1 over a diffuse quad at
// z = 0: a matched interface reflects nothing (Fresnel's F is 0 at every angle) and the
// refracted ray goes straight on, so a pixel is the quad's Phong where the camera ray itself
// meets z = 0, or the background beyond the quad.
TEST(WhittedReference, PaneOfIorOnePassesRaysStraightThrough) {
    SceneBuilder b;
    Material pane = phong(glm::vec3(0.0f), glm::vec3(0.0f));
    pane.transmittance = glm::vec3(1.0f);
    pane.ior = 1.0f;
    const std::uint32_t pane_mat = b.material(pane);
    const std::uint32_t back_mat =
        b.material(phong(glm::vec3(0.2f, 0.7f, 0.4f), glm::vec3(0.3f), 8.0f));
    b.quad("pane", {-3, -3, 1}, {3, -3, 1}, {3, 3, 1}, {-3, 3, 1}, pane_mat);  // +z
    b.quad("back", {-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}, back_mat);  // +z
    b.light({1.0, 1.0, 0.5});  // between the two: the pane casts no shadow on the quad
    const Scene& scene = b.scene();
    const Camera camera = b.camera({0.2, 0.1, 4.0}, {0.0, 0.0, 0.0}, 70.0f);
    const int size = 48;

    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const ReferenceTracer tracer(scene, posed);
    const ReferenceShading shading = shading_from(scene, small_image(size, 5));
    const ReferenceFrame ref = render_reference(scene, tracer, camera, size, size, shading);
    const packet::PinholeRays rays(camera, size, size);
    int through = 0, beside = 0, open = 0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const ReferencePixel& pixel = ref.at(x, y);
            ASSERT_EQ(pixel.hit.object, 0) << "(" << x << "," << y << ") must see the pane";
            EXPECT_EQ(pixel.refracted_at, 1u);
            EXPECT_EQ(pixel.total_internal_at, 0u);
            if (!determined(pixel)) {
                ++open;
                continue;
            }
            const bvh::Ray ray = rays.ray(x, y);
            const glm::dvec3 d = glm::normalize(glm::dvec3(ray.dir));
            const glm::dvec3 eye(ray.org);
            const glm::dvec3 q = eye + (-eye.z / d.z) * d;
            const bool hits_back = std::abs(q.x) < 2.0 && std::abs(q.y) < 2.0;
            const glm::dvec3 expected =
                hits_back ? phong_at(scene.materials[back_mat], shading, q, {0, 0, 1}, d)
                          : shading.background;
            (hits_back ? through : beside)++;
            EXPECT_LT(max_abs_diff(pixel.color, expected), 1e-9) << "(" << x << "," << y << ")";
        }
    }
    EXPECT_GT(through, size * size / 4);
    EXPECT_GT(beside, size * size / 8);
    EXPECT_LT(open, size * size / 10);
}

// Inside a glass cube (ior 1.5), looking up at its top face: a ray leaving through it is
// reflected totally exactly when its angle to the face's normal exceeds asin(1 / 1.5).
TEST(WhittedReference, TotalInternalReflectionBeyondTheCriticalAngle) {
    SceneBuilder b;
    const std::uint32_t glass_mat = b.material(glass(1.0f, 1.5f));
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
    extruded({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -2.0, 2.0, [](glm::dvec3 p) { return p; },
             positions, triangles);
    ASSERT_GT(signed_volume6(positions, triangles), 0.0);
    const int box = b.mesh("glass cube", positions, triangles, glass_mat);
    b.light({0.5, 0.5, 0.5});
    const Scene& scene = b.scene();
    // Looking up +z at the cap z = 2 (the extrusion's top).
    const Camera camera = b.camera({0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 100.0f);
    const int size = 64;

    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const ReferenceTracer tracer(scene, posed);
    const ReferenceShading shading = shading_from(scene, small_image(size, 1));
    const ReferenceFrame ref = render_reference(scene, tracer, camera, size, size, shading);
    const packet::PinholeRays rays(camera, size, size);
    const double critical = std::asin(1.0 / 1.5);
    int total = 0, refracted = 0, open = 0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const ReferencePixel& pixel = ref.at(x, y);
            ASSERT_EQ(pixel.hit.object, box);
            if (pixel.normal != glm::dvec3(0.0, 0.0, -1.0)) continue;  // a side face
            if (!determined(pixel)) {
                ++open;
                continue;
            }
            const glm::dvec3 d = glm::normalize(glm::dvec3(rays.ray(x, y).dir));
            const bool beyond = std::acos(d.z) > critical;
            EXPECT_EQ(pixel.total_internal_at, beyond ? 1u : 0u) << "(" << x << "," << y << ")";
            EXPECT_EQ(pixel.refracted_at, beyond ? 0u : 1u) << "(" << x << "," << y << ")";
            (beyond ? total : refracted)++;
        }
    }
    EXPECT_GT(total, 100);
    EXPECT_GT(refracted, 100);
    EXPECT_LT(open, size * size / 20);
}

// The recursion does something: between the mirrors each further bounce changes the image.
TEST(WhittedReference, MirrorsChangeTheImageAtEachDepth) {
    const Shot shot = mirrors_shot();
    std::vector<ReferenceFrame> frames;
    for (int depth : {0, 1, 2, 5}) {
        RenderOptions options = shot.options;
        options.secondary.max_depth = depth;
        frames.push_back(reference_of(shot, options));
    }
    const int pixels = shot.options.width * shot.options.height;
    EXPECT_GT(count_different(frames[0], frames[1], 1e-3), pixels / 4);
    EXPECT_GT(count_different(frames[1], frames[2], 1e-3), pixels / 8);
    EXPECT_GT(count_different(frames[2], frames[3], 1e-3), pixels / 40);
}

// The prism's pixels: inside, some rays are reflected totally at the exit face, their
// neighbours in the next row refracted out, and the reference is sure of both.
TEST(WhittedReference, PrismShowsTotalInternalReflectionBesideRefraction) {
    const Shot shot = prism_shot();
    const ReferenceFrame ref = reference_of(shot);
    int total = 0, refracted = 0, boundary_pairs = 0;
    for (int y = 0; y < ref.height; ++y) {
        for (int x = 0; x < ref.width; ++x) {
            const ReferencePixel& p = ref.at(x, y);
            ASSERT_EQ(p.hit.object, 0) << "(" << x << "," << y << ") must see the prism";
            EXPECT_EQ(p.refracted_at & 1u, 1u) << "(" << x << "," << y << ") enters the glass";
            if (!determined(p)) continue;
            const bool tir = (p.total_internal_at & 2u) != 0;
            total += tir;
            refracted += (p.refracted_at & 2u) != 0;
            if (y + 1 < ref.height && determined(ref.at(x, y + 1))) {
                const bool below_tir = (ref.at(x, y + 1).total_internal_at & 2u) != 0;
                boundary_pairs += tir != below_tir;
            }
        }
    }
    EXPECT_GT(total, 200);
    EXPECT_GT(refracted, 200);
    EXPECT_GT(boundary_pairs, ref.width / 2) << "rows on either side of the critical angle";
}

// A scene 10^5 from the origin renders (in the reference) like the same scene at the origin.
TEST(WhittedReference, FarSceneLooksLikeTheSceneAtTheOrigin) {
    for (const auto& [name, at_origin, far_away] :
         {std::tuple{"mirrors", mirrors_shot(), mirrors_shot(kFar)},
          std::tuple{"glass", glass_shot(), glass_shot(kFar)}}) {
        SCOPED_TRACE(name);
        const ReferenceFrame a = reference_of(at_origin), b = reference_of(far_away);
        int compared = 0, different = 0;
        for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            if (!determined(a.pixels[i]) || !determined(b.pixels[i])) continue;
            ++compared;
            different += max_abs_diff(a.pixels[i].color, b.pixels[i].color) > 1e-3;
        }
        EXPECT_GT(compared, static_cast<int>(a.pixels.size()) * 3 / 4);
        EXPECT_EQ(different, 0);
    }
}

/// `scene` with every material's reflectance and transmittance cleared: the Phong-only model.
Scene without_secondary(Scene scene) {
    for (Material& m : scene.materials) {
        m.reflectance = glm::vec3(0.0f);
        m.transmittance = glm::vec3(0.0f);
    }
    return scene;
}

// (e) max_depth = 0 is the model before secondary rays, pixel for pixel.
TEST(WhittedReference, DepthZeroIsThePhongOnlyModel) {
    for (const Shot& shot : {mirrors_shot(), glass_shot(), prism_shot()}) {
        SCOPED_TRACE(shot.scene.objects.back().name);
        RenderOptions depth0 = shot.options;
        depth0.secondary.max_depth = 0;
        const ReferenceFrame a = reference_of(shot, depth0);
        Shot plain = shot;
        plain.scene = without_secondary(shot.scene);
        const ReferenceFrame b = reference_of(plain);
        for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            const ReferencePixel &p = a.pixels[i], &q = b.pixels[i];
            ASSERT_TRUE(p.color == q.color && p.normal == q.normal &&
                        p.hit.object == q.hit.object && p.hit.prim == q.hit.prim &&
                        p.hit.t == q.hit.t && p.hit.ambiguity == q.hit.ambiguity &&
                        p.shading_ambiguous == q.shading_ambiguous && p.refracted_at == 0 &&
                        p.total_internal_at == 0)
                << "pixel " << i;
        }
    }
}

// ---- The renderer against the reference ----------------------------------------------------

/// Whether the camera ray's hit is on a mirror or glass.
bool spawns_secondary(const Scene& scene, const ReferencePixel& p) {
    if (!p.hit.is_hit()) return false;
    const Object& object = scene.objects[static_cast<std::size_t>(p.hit.object)];
    return scene.materials[object.material].traces_secondary();
}

struct Case {
    std::string name;
    Shot (*make)();
    /// Largest share of pixels the reference may leave open (hit or ray tree ambiguous).
    double max_open_share;
    /// Smallest share of pixels that see a mirror or glass and whose colour is compared.
    double min_secondary_share;
};

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

class WhittedRenderer : public ::testing::TestWithParam<Case> {};

TEST_P(WhittedRenderer, MatchesTheExactReference) {
    const Case& param = GetParam();
    const Shot shot = param.make();
    const ReferenceFrame ref = reference_of(shot);

    const int pixels = ref.width * ref.height;
    const int open = count_open(ref);
    int hits = 0, secondary = 0;
    for (const ReferencePixel& p : ref.pixels) {
        hits += p.hit.is_hit();
        secondary += determined(p) && spawns_secondary(shot.scene, p);
    }
    EXPECT_GT(hits, pixels / 2);
    EXPECT_GE(secondary, param.min_secondary_share * pixels)
        << secondary << " of " << pixels << " pixels see mirror or glass and are compared";
    EXPECT_LE(open, param.max_open_share * pixels) << open << " of " << pixels << " pixels open";
    RecordProperty("open_pixels", open);
    RecordProperty("compared_secondary_pixels", secondary);

    const RenderedFrame packet = render_with(shot, Tracer::packet);
    const RenderedFrame single = render_with(shot, Tracer::single);
    EXPECT_TRUE(frames_identical(packet, single)) << "packet vs single-ray tracer";

    // The colour tolerance of render_reference_test.cpp: float shading is good to ~1e-6 per
    // term, and a ray tree adds at most a few dozen weighted terms.
    ComparisonOptions tolerance;
    tolerance.color_abs_tol = 1e-3;
    for (const auto& [tracer_name, frame] :
         {std::pair{"packet", &packet}, std::pair{"single", &single}}) {
        SCOPED_TRACE(tracer_name);
        const ImageComparison cmp = compare_images(*frame, ref, tolerance);
        EXPECT_EQ(cmp.unambiguous_mismatches, 0) << cmp.summary();
        EXPECT_EQ(cmp.t_mismatches, 0) << cmp.summary();
        EXPECT_EQ(cmp.color_mismatches, 0) << cmp.summary();
        EXPECT_EQ(cmp.normal_mismatches, 0) << cmp.summary();
        RecordProperty(std::string(tracer_name) + "_max_color_error",
                       std::to_string(cmp.max_color_error));
    }
}

Shot mirrors_near() { return mirrors_shot(); }
Shot glass_near() { return glass_shot(); }
Shot prism() { return prism_shot(); }
Shot mirrors_far() { return mirrors_shot(kFar); }
Shot glass_far() { return glass_shot(kFar); }
Shot glass_smooth() { return glass_shot({}, true); }
/// The mirrors' box glows (emission), seen directly and in the mirrors.
Shot glowing_box_in_mirrors() {
    Shot shot = mirrors_shot();
    for (Object& object : shot.scene.objects) {
        if (object.name == "box") shot.scene.materials[object.material].emission = glm::vec3(0.35f, 0.2f, 0.05f);
    }
    return shot;
}

INSTANTIATE_TEST_SUITE_P(Scenes, WhittedRenderer,
                         // Measured: open 0.2%, 2%, 2%, 0.3%, 6%; compared mirror or
                         // glass pixels 52%, 15%, 98%, 51%, 11% (64x64). The smooth glass
                         // sphere's compared share fell to 4.5% when shadow rays began to pass
                         // through glass: those crossing it near a silhouette are open.
                         ::testing::Values(Case{"mirrors", mirrors_near, 0.02, 0.4},
                                           Case{"glassSphere", glass_near, 0.05, 0.12},
                                           Case{"prism", prism, 0.05, 0.8},
                                           Case{"farMirrors", mirrors_far, 0.03, 0.4},
                                           Case{"farGlassSphere", glass_far, 0.12, 0.08},
                                           Case{"smoothGlassSphere", glass_smooth, 0.15, 0.04},
                                           Case{"smoothMirrorBall", mirror_ball_shot, 0.1, 0.1},
                                           Case{"bentMirror", bent_mirror_shot, 0.1, 0.15},
                                           Case{"glowingBoxInMirrors", glowing_box_in_mirrors, 0.02, 0.4}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             return info.param.name;
                         });

// (e) The bent mirror's pixels split both ways: with the shading normal where its mirror
// direction leaves above the surface, with the geometric normal where it would not; and the
// smooth images differ from the flat ones.
TEST(WhittedSmooth, BentMirrorFallsBackToTheGeometricNormalWhereItMust) {
    const Shot shot = bent_mirror_shot();
    const ReferenceFrame ref = reference_of(shot);
    const packet::PinholeRays rays(shot.camera, ref.width, ref.height);
    const glm::vec3 s_left = shot.scene.objects[0].mesh.normals[0], s_right = shot.scene.objects[0].mesh.normals[2];
    int shading = 0, fallback = 0;
    for (int y = 0; y < ref.height; ++y) {
        for (int x = 0; x < ref.width; ++x) {
            const ReferencePixel& p = ref.at(x, y);
            if (p.hit.object != 0 || !determined(p)) continue;
            // The quad's x runs from -3 to 3: the normal leans linearly between its edges.
            const glm::dvec3 d = glm::normalize(glm::dvec3(rays.ray(x, y).dir));
            const glm::dvec3 point = glm::dvec3(rays.ray(x, y).org) + p.hit.t * d;
            const double w = (point.x + 3.0) / 6.0;
            const glm::dvec3 n = glm::normalize((1.0 - w) * glm::dvec3(s_left) + w * glm::dvec3(s_right));
            const glm::dvec3 r = d - 2.0 * glm::dot(d, n) * n;
            (glm::dot(d, n) < 0.0 && r.y > 0.0 ? shading : fallback)++;
        }
    }
    EXPECT_GT(shading, 200);
    EXPECT_GT(fallback, 200);
    Shot flat = shot;
    flat.options.smooth_normals = false;
    EXPECT_GT(count_different(render_with(shot, Tracer::packet), render_with(flat, Tracer::packet), 1e-2f),
              shading / 2);
}

// (a) again through the renderer: depth 0, 1 and 5 give different images.
TEST(WhittedRendererDepth, MirrorsChangeTheImageAtEachDepth) {
    Shot shot = mirrors_shot();
    std::vector<RenderedFrame> frames;
    for (int depth : {0, 1, 5}) {
        shot.options.secondary.max_depth = depth;
        frames.push_back(render_with(shot, Tracer::packet));
    }
    const int pixels = shot.options.width * shot.options.height;
    EXPECT_GT(count_different(frames[0], frames[1], 1e-3f), pixels / 4);
    EXPECT_GT(count_different(frames[1], frames[2], 1e-3f), pixels / 8);
}

// (e) through the renderer: max_depth = 0 renders the scene as if it had no mirror or glass,
// bit for bit, with either tracer.
TEST(WhittedRendererDepth, DepthZeroIsThePhongOnlyImage) {
    for (const Shot& base : {mirrors_shot(), glass_shot()}) {
        SCOPED_TRACE(base.scene.objects.back().name);
        for (Tracer tracer : {Tracer::packet, Tracer::single}) {
            Shot depth0 = base;
            depth0.options.secondary.max_depth = 0;
            Shot plain = base;
            plain.scene = without_secondary(base.scene);
            EXPECT_TRUE(frames_identical(render_with(depth0, tracer), render_with(plain, tracer)));
        }
    }
}

}  // namespace
}  // namespace dynrt::reference
