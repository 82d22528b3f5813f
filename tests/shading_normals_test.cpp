// Smooth shading normals (renderer.h, "Shading normals"): vertex normals from the files (glTF
// NORMAL and its morph displacements, BART's pp, ttp, m and tpa normals) or area-weighted
// where a file has none (dynrt/scene/vertex_normals.h), posed with the mesh (anim), looked up
// and interpolated at each hit, flipped to the geometric normal's side, and the fallback of
// Whitted's split to the geometric normal (shading_split_holds). The renderer's smooth images
// against the exact reference are in render_reference_test.cpp (the procedural and bundled
// scenes have normals), whitted_reference_test.cpp (smooth mirror and glass) and here.

#include "gltf_test_file.h"
#include "rendering/tile_shading.h"

#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/vertex_normals.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace dynrt {
namespace {

::testing::AssertionResult near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    if (glm::length(a - b) <= tolerance) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "(" << a.x << ", " << a.y << ", " << a.z << ") vs ("
                                         << b.x << ", " << b.y << ", " << b.z << ")";
}

// ---- Computed normals and the normal transform ----------------------------------------------

TEST(VertexNormals, SharedVerticesAreSmoothedByAreaAndUnsharedOnesKeepTheirFacets) {
    // A roof: two faces at right angles meeting at the ridge (vertices 0 and 1), the left one
    // twice as wide, so the ridge normal leans toward it (the unweighted mean of the two face
    // normals would point straight up): the sum of the faces' cross products.
    const std::vector<glm::vec3> roof = {{0, 1, 0}, {0, 1, 1}, {-2, -1, 0}, {-2, -1, 1}, {1, 0, 0}, {1, 0, 1}};
    const std::vector<glm::uvec3> tris = {{0, 2, 3}, {0, 3, 1}, {0, 1, 5}, {0, 5, 4}};
    const std::vector<glm::vec3> n = area_weighted_normals(roof, tris);
    ASSERT_EQ(n.size(), roof.size());
    const glm::vec3 left = glm::cross(roof[2] - roof[0], roof[3] - roof[0]);
    const glm::vec3 right = glm::cross(roof[1] - roof[0], roof[5] - roof[0]);
    EXPECT_TRUE(near(n[0], glm::normalize(2.0f * left + 2.0f * right), 1e-6f));
    EXPECT_TRUE(near(n[2], glm::normalize(left), 1e-6f));  // eaves: one face each
    EXPECT_TRUE(near(n[4], glm::normalize(right), 1e-6f));
    EXPECT_LT(n[0].x, 0.0f) << "leans toward the wider face";

    // The same faces unshared (a soup) keep each its own normal; an unused vertex gets 0.
    std::vector<glm::vec3> soup;
    std::vector<glm::uvec3> soup_tris;
    for (const glm::uvec3& t : tris) {
        const auto base = std::uint32_t(soup.size());
        soup.insert(soup.end(), {roof[t.x], roof[t.y], roof[t.z]});
        soup_tris.push_back({base, base + 1, base + 2});
    }
    soup.push_back(glm::vec3(5.0f));
    const std::vector<glm::vec3> flat = area_weighted_normals(soup, soup_tris);
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const glm::vec3 face = glm::normalize(glm::cross(soup[3 * t + 1] - soup[3 * t], soup[3 * t + 2] - soup[3 * t]));
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(flat[3 * t + std::size_t(k)], face, 1e-6f));
    }
    EXPECT_EQ(flat.back(), glm::vec3(0.0f));
    // A soup skips the sums (each vertex has one triangle): the very normals the sums give,
    // which a triangle that uses a vertex of its own three times brings back.
    std::vector<glm::vec3> summed_soup = soup;
    std::vector<glm::uvec3> summed_tris = soup_tris;
    const auto extra = std::uint32_t(summed_soup.size());
    summed_soup.push_back(glm::vec3(7.0f));
    summed_tris.push_back({extra, extra, extra});
    const std::vector<glm::vec3> summed = area_weighted_normals(summed_soup, summed_tris);
    ASSERT_EQ(summed.size(), flat.size() + 1);
    EXPECT_EQ(std::memcmp(summed.data(), flat.data(), flat.size() * sizeof(glm::vec3)), 0);
}

TEST(VertexNormals, CofactorMatrixKeepsNormalsPerpendicularEvenThroughAMirror) {
    const glm::vec3 a(1.0f, 0.2f, -0.3f), b(-0.4f, 1.0f, 0.5f);
    for (const glm::mat3& m : {glm::mat3(glm::scale(glm::mat4(1.0f), glm::vec3(3.0f, 0.5f, 1.0f))),
                               glm::mat3(glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 2.0f, 1.0f))),
                               glm::mat3(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(1, 2, 3)))}) {
        const glm::vec3 n = normal_matrix(m) * glm::cross(a, b);
        EXPECT_TRUE(near(n, glm::cross(m * a, m * b), 1e-5f)) << "the winding normal of the image";
    }
}

TEST(VertexNormals, ProceduralSpheresAreSmoothPlanesAndSoupsFlat) {
    const Scene scene = load_scene("sphere:800+plane:3@0,-2,0+soup:50");
    const Mesh& sphere = scene.objects[0].mesh;
    ASSERT_EQ(sphere.normals.size(), sphere.positions.size());
    float worst = 1.0f;
    for (std::size_t v = 0; v < sphere.positions.size(); ++v) {
        worst = std::min(worst, glm::dot(sphere.normals[v], glm::normalize(sphere.positions[v])));
    }
    EXPECT_GT(worst, 0.995f) << "a unit sphere's vertex normals are nearly radial";
    for (const glm::vec3& n : scene.objects[1].mesh.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));
    // A soup's area-weighted normals would be its faces' own: it keeps none, and is shaded
    // with its triangles' geometric normals.
    EXPECT_TRUE(scene.objects[2].mesh.normals.empty());
}

// ---- Loaders ---------------------------------------------------------------------------------

TEST(GltfNormals, NormalAttributeIsReadAndNormalisedAndItsAbsenceComputed) {
    test::GltfTestFile file;
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    // Not unit length (and tilted differently at each corner): normalised as read.
    const std::vector<float> normals = {0, 0, 2, 0, 0.6f, 0.8f, 0.3f, 0, 0.4f};
    const int with = file.add_mesh(positions, {{"NORMAL", file.add_floats(normals, "VEC3")}}, nullptr, "with");
    const int without = file.add_mesh(positions, nlohmann::json::object(), nullptr, "without");
    file.add_node({{"name", "a"}, {"mesh", with}});
    file.add_node({{"name", "b"}, {"mesh", without}, {"translation", {3, 0, 0}}});
    const Scene scene = load_gltf(file.write("normals.gltf"));
    ASSERT_EQ(scene.objects.size(), 2u);
    const std::vector<glm::vec3>& read = scene.objects[0].mesh.normals;
    ASSERT_EQ(read.size(), 3u);
    EXPECT_TRUE(near(read[0], {0, 0, 1}, 1e-7f));
    EXPECT_TRUE(near(read[1], {0, 0.6f, 0.8f}, 1e-7f));
    EXPECT_TRUE(near(read[2], {0.6f, 0, 0.8f}, 1e-7f));
    // Without NORMAL, a lone triangle (a soup) is shaded with its geometric normal and keeps
    // none; the same corners indexed twice over (two triangles sharing an edge) are smoothed.
    EXPECT_TRUE(scene.objects[1].mesh.normals.empty());
    test::GltfTestFile indexed;
    const int shared = indexed.add_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, -1});
    indexed.doc()["meshes"][shared]["primitives"][0]["indices"] =
        indexed.add_accessor(std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}, "SCALAR", test::kGltfUnsignedInt);
    indexed.add_node({{"name", "c"}, {"mesh", shared}});
    const Scene smooth = load_gltf(indexed.write("computed_normals.gltf"));
    const std::vector<glm::vec3>& made = smooth.objects[0].mesh.normals;
    ASSERT_EQ(made.size(), 4u);
    EXPECT_TRUE(near(made[0], {0, 0, 1}, 1e-7f)) << "one face";
    // (2, 1, 3): (v1 - v2) x (v3 - v2) = (1, -1, 0) x (1, 0, -1) = (1, 1, 1).
    const glm::vec3 tilted = glm::normalize(glm::vec3(1, 1, 1));
    EXPECT_TRUE(near(made[3], tilted, 1e-6f)) << "the other";
    EXPECT_FALSE(near(made[1], {0, 0, 1}, 1e-3f)) << "a shared corner leans between them";
}

TEST(GltfNormals, BadNormalAttributesAreErrorsNamingTheObject) {
    test::GltfTestFile file;
    const int mesh = file.add_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0},
                                   {{"NORMAL", file.add_floats({0, 0, 1, 0, 0, 1}, "VEC3")}});
    file.add_node({{"name", "short"}, {"mesh", mesh}});
    try {
        (void)load_gltf(file.write("short_normals.gltf"));
        FAIL() << "two normals for three positions must be refused";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("short"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("NORMAL has 2 elements for 3 positions"), std::string::npos) << e.what();
    }
}

TEST(GltfNormals, MorphTargetNormalDisplacementsMorphTheNormals) {
    test::GltfTestFile file;
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    nlohmann::json targets = nlohmann::json::array(
        {{{"POSITION", file.add_floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3")},
          {"NORMAL", file.add_floats({1, 0, -1, 1, 0, -1, 1, 0, -1}, "VEC3")}}});
    const int mesh = file.add_mesh(positions, {{"NORMAL", file.add_floats(normals, "VEC3")}}, targets);
    const int node = file.add_node({{"name", "m"}, {"mesh", mesh}, {"weights", {0.5}}});
    file.add_animation("w", {{node, "weights", {0.0f, 1.0f}, {0.0f, 1.0f}}});
    const Scene scene = load_gltf(file.write("morph_normals.gltf"));
    const Object& object = scene.objects[0];
    ASSERT_TRUE(object.morph.has_value());
    ASSERT_EQ(object.morph->normal_deltas.size(), 1u);
    // Default weight 0.5: (0.5, 0, 0.5), normalised.
    EXPECT_TRUE(near(object.mesh.normals[0], glm::normalize(glm::vec3(0.5f, 0, 0.5f)), 1e-6f));
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);  // weight 0
    EXPECT_TRUE(near(posed.objects[0].normals[1], {0, 0, 1}, 1e-6f));
    anim::pose_scene(scene, 24, posed);  // t = 1 s: weight 1
    EXPECT_TRUE(near(posed.objects[0].normals[2], {1, 0, 0}, 1e-6f));
}

TEST(AffNormals, PatchMeshAndAnimatedTriangleNormalsAreKeptAndTurnedByStaticTransforms) {
    // Under xs 2 1 1 (scale x by 2): a normal (1, 0, 1) turns by the cofactor matrix
    // diag(1, 2, 2) to (1, 0, 2): still perpendicular to the stretched surface.
    const Scene scene = load_aff_text(R"(
f 1 1 1 1 0 10 0 1
xs 2 1 1  0 0 1 0  0 0 0 {
pp 3
 0 0 0  1 0 1
 1 0 0  1 0 1
 0 1 0  1 0 1
}
m
 vertices 4
  0 0 5  1 0 5  1 1 5  0 1 5
 normals 2
  0 0 1  0 1 1
 triangles 2
  0 1 2  0 0 1
  0 2 3  1 1 1
p 3
 0 0 9  1 0 9  0 1 9
)",
                                      "normals.aff");
    ASSERT_EQ(scene.objects.size(), 1u);  // one static object for material 0
    const Mesh& mesh = scene.objects[0].mesh;
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    const glm::vec3 turned = glm::normalize(glm::vec3(1, 0, 2));
    for (int v = 0; v < 3; ++v) EXPECT_TRUE(near(mesh.normals[std::size_t(v)], turned, 1e-6f));
    // Polygons come first (pp, then p), then the mesh, whose corners index positions and
    // normals apart: (0, n0), (1, n0), (2, n1), (0, n1) and (3, n1) are five distinct vertices.
    ASSERT_EQ(mesh.positions.size(), 3u + 3u + 5u);
    int up = 0, slanted = 0;
    for (std::size_t v = 6; v < 11; ++v) {
        up += near(mesh.normals[v], {0, 0, 1}, 1e-6f) ? 1 : 0;
        slanted += near(mesh.normals[v], glm::normalize(glm::vec3(0, 1, 1)), 1e-6f) ? 1 : 0;
    }
    EXPECT_EQ(up, 2);
    EXPECT_EQ(slanted, 3);
    // The plain polygon gets its own flat normal.
    for (std::size_t v = 3; v < 6; ++v) EXPECT_TRUE(near(mesh.normals[v], {0, 0, 1}, 1e-6f));
    for (const std::string& line : scene.ignored) {
        EXPECT_EQ(line.find("normals"), std::string::npos) << line;
    }
}

TEST(AffNormals, AnimatedTriangleNormalsMorphWithTheirKeys) {
    const Scene scene = load_aff_text(R"(
a 0 1 2
tpa 2
 0  0 0 0  0 0 1   1 0 0  0 0 1   0 1 0  0 0 1
 1  0 0 0  1 0 0   1 0 0  1 0 0   0 1 0  1 0 0
)",
                                      "tpa.aff");
    ASSERT_EQ(scene.objects.size(), 1u);
    ASSERT_TRUE(scene.objects[0].morph.has_value());
    EXPECT_EQ(scene.objects[0].morph->normal_deltas.size(), 1u);
    anim::PoseSettings settings;
    settings.fps = scene.setup ? scene.setup->fps : 1.0;
    anim::PosedScene posed;
    anim::pose_scene(scene, settings, 0, posed);
    EXPECT_TRUE(near(posed.objects[0].normals[0], {0, 0, 1}, 1e-6f));
    anim::pose_scene(scene, settings, 1, posed);
    EXPECT_TRUE(near(posed.objects[0].normals[0], {1, 0, 0}, 1e-6f));
}

// ---- Posing ----------------------------------------------------------------------------------

TEST(PosedNormals, FixedObjectsTurnByTheirTransformsCofactorAndCanBeSkipped) {
    Scene scene = load_scene("sphere:200");
    glm::mat4& m = scene.objects[0].transform;
    m = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(4, 5, 6)), glm::vec3(3.0f, 0.5f, -1.0f));
    const anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    poser.pose(0, posed);
    const Mesh& mesh = scene.objects[0].mesh;
    const std::vector<glm::vec3>& normals = posed.objects[0].normals;
    ASSERT_EQ(normals.size(), mesh.normals.size());
    for (std::size_t v = 0; v < normals.size(); ++v) {
        const glm::vec3 want = glm::normalize(normal_matrix(glm::mat3(m)) * mesh.normals[v]);
        ASSERT_TRUE(near(normals[v], want, 1e-6f)) << "vertex " << v;
    }
    // fixed_world_normals gives the same, and with skipped positions nothing is posed.
    std::vector<glm::vec3> fixed;
    poser.fixed_world_normals(0, posed, fixed);
    EXPECT_EQ(fixed, normals);
    anim::PoseSettings skip;
    skip.skip_fixed_positions = true;
    anim::ScenePoser(scene, skip).pose(0, posed);
    EXPECT_TRUE(posed.objects[0].normals.empty());
    anim::PoseSettings none;
    none.normals = false;
    anim::ScenePoser(scene, none).pose(0, posed);
    EXPECT_TRUE(posed.objects[0].normals.empty());
    EXPECT_FALSE(posed.objects[0].positions.empty());
}

TEST(PosedNormals, AWavingPlaneHasTheNormalsOfItsPosedSurface) {
    // Central differences of the posed grid against the posed normals: they agree up to the
    // differences' own O(h^2) error.
    Scene scene = load_scene("plane:96");
    anim::add_procedural_motions(scene, std::vector<std::string>{"wave"});
    const anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    const int n = 97;  // vertices per row
    for (const int frame : {0, 3, 11}) {
        poser.pose(frame, posed);
        const std::vector<glm::vec3>& p = posed.objects[0].positions;
        const std::vector<glm::vec3>& normals = posed.objects[0].normals;
        ASSERT_EQ(normals.size(), p.size());
        float worst = 0.0f, tilt = 0.0f;
        for (const glm::vec3& normal : normals) tilt = std::max(tilt, std::abs(normal.x));
        for (int r = 1; r + 1 < n; r += 7) {
            for (int c = 1; c + 1 < n; ++c) {
                const auto at = [&](int rr, int cc) { return p[std::size_t(rr * n + cc)]; };
                const glm::vec3 along_x = at(r, c + 1) - at(r, c - 1), along_z = at(r + 1, c) - at(r - 1, c);
                glm::vec3 surface = glm::normalize(glm::cross(along_z, along_x));
                if (surface.y < 0.0f) surface = -surface;
                worst = std::max(worst, glm::length(surface - normals[std::size_t(r * n + c)]));
            }
        }
        EXPECT_LT(worst, 5e-3f) << "frame " << frame;
        EXPECT_GT(tilt, 0.2f) << "the wave tilts them (its slope reaches 0.3)";
    }
}

TEST(PosedNormals, ExplodingPiecesKeepTheirSmoothNormals) {
    Scene scene = load_scene("sphere:300");
    const std::vector<glm::uvec3> shared = scene.objects[0].mesh.triangles;
    const std::vector<glm::vec3> rest_normals = scene.objects[0].mesh.normals;
    anim::add_procedural_motions(scene, std::vector<std::string>{"explode"});
    const anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    poser.pose(20, posed);
    const std::vector<glm::vec3>& normals = posed.objects[0].normals;
    ASSERT_EQ(normals.size(), 3 * shared.size());
    for (std::size_t t = 0; t < shared.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(normals[3 * t + std::size_t(k)], rest_normals[shared[t][k]]) << "triangle " << t;
        }
    }
}

// ---- Shading ---------------------------------------------------------------------------------

// The kernel lights with the shading normal, and only where it faces the light too.
TEST(ShadingNormalKernel, LightsWithTheShadingNormalAndSkipsLightsBehindIt) {
    packet::SurfacePacket surface;
    surface.hit = packet::LaneMask{};
    const glm::vec3 geometric(0, 0, 1), view(0, 0, 1);
    const glm::vec3 bent[3] = {glm::vec3(0, 0, 1), glm::normalize(glm::vec3(0.6f, 0, 0.8f)),
                               glm::normalize(glm::vec3(-0.99f, 0, 0.1f))};
    for (int lane = 0; lane < 3; ++lane) {
        surface.hit.set(lane);
        for (int a = 0; a < 3; ++a) {
            surface.point[a][lane] = 0.0f;
            surface.normal[a][lane] = geometric[a];
            surface.shading_normal[a][lane] = bent[lane][a];
            surface.view[a][lane] = view[a];
        }
        surface.material[lane] = 0;
    }
    const packet::PhongMaterial material{glm::vec3(1.0f), glm::vec3(0.0f), 1.0f};
    // A light up and to the right: the geometric normal faces it (n.l > 0) in every lane.
    const packet::ShadingLight light{glm::vec3(3, 0, 4), 1.0f};
    packet::LaneMask visible = surface.hit;
    packet::ShadedColors colors;
    packet::shade(surface, std::span(&material, 1), std::span(&light, 1), std::span(&visible, 1), 0.0f, colors);
    const glm::vec3 l = glm::normalize(light.position);
    EXPECT_NEAR(colors.rgb[0][0], glm::dot(bent[0], l), 1e-6f);
    EXPECT_NEAR(colors.rgb[0][1], glm::dot(bent[1], l), 1e-6f);
    EXPECT_GT(colors.rgb[0][1], colors.rgb[0][0]) << "the bent normal faces the light better";
    EXPECT_EQ(colors.rgb[0][2], 0.0f) << "a shading normal facing away adds nothing";
}

TEST(ShadingSplit, HoldsOnlyWhenNeitherDirectionCrossesTheGeometricSurface) {
    using detail::shading_split_holds;
    const glm::vec3 n(0, 0, 1);
    const glm::vec3 d = glm::normalize(glm::vec3(1, 0, -1));
    const auto reflect = [&](const glm::vec3& s) { return glm::normalize(d - 2.0f * glm::dot(d, s) * s); };
    const glm::vec3 mild = glm::normalize(glm::vec3(-0.2f, 0, 1));
    EXPECT_TRUE(shading_split_holds(d, mild, n, reflect(mild), glm::vec3(0.0f)));
    // Tilted 30 degrees along the ray (which comes in at 45): the mirror direction dips below.
    const glm::vec3 dips = glm::vec3(0.5f, 0, std::sqrt(0.75f));
    EXPECT_LT(glm::dot(reflect(dips), n), 0.0f);
    EXPECT_FALSE(shading_split_holds(d, dips, n, reflect(dips), glm::vec3(0.0f)));
    // Tilted away so far that the ray comes from behind the shading normal.
    const glm::vec3 away = glm::normalize(glm::vec3(1.5f, 0, 1));
    EXPECT_FALSE(shading_split_holds(d, away, n, reflect(away), glm::vec3(0.0f)));
    // A refracted direction must go below the surface.
    EXPECT_TRUE(shading_split_holds(d, mild, n, reflect(mild), glm::normalize(glm::vec3(0.5f, 0, -1))));
    EXPECT_FALSE(shading_split_holds(d, mild, n, reflect(mild), glm::normalize(glm::vec3(0.5f, 0, 0.1f))));
}

/// A sphere lit from the side over a floor, small.
struct SphereShot {
    Scene scene = load_scene("sphere:180+plane:2@0,-1.2,0,3");
    Camera camera;
    RenderOptions options;
    SphereShot() {
        camera.eye = glm::vec3(0.4f, 0.6f, 3.2f);
        camera.target = glm::vec3(0.0f, -0.1f, 0.0f);
        camera.fov_y_deg = 50.0f;
        options.width = options.height = 48;
        options.lights = {PointLight{{3.0f, 4.0f, 2.0f}, 0.9f}, PointLight{{-4.0f, 1.0f, 3.0f}, 0.4f}};
        scene.materials[0].specular = glm::vec3(0.4f);
        scene.materials[0].shininess = 40.0f;
    }
    RenderedFrame render(bool smooth, Tracer tracer = Tracer::packet) const {
        RenderOptions o = options;
        o.smooth_normals = smooth;
        o.tracer = tracer;
        Renderer renderer(o);
        RenderedFrame frame;
        renderer.render(scene, camera, 0, frame);
        return frame;
    }
    reference::ReferenceFrame reference(bool smooth) const {
        RenderOptions o = options;
        o.smooth_normals = smooth;
        anim::PosedScene posed;
        anim::pose_scene(scene, 0, posed);
        const reference::ReferenceTracer tracer(scene, posed);
        return reference::render_reference(scene, tracer, camera, o.width, o.height,
                                           reference::shading_from(scene, o));
    }
};

TEST(SmoothShading, SmoothAndFlatBothMatchTheReferenceAndDifferOnTheSphere) {
    const SphereShot shot;
    RenderedFrame frames[2];
    for (const bool smooth : {false, true}) {
        SCOPED_TRACE(smooth ? "smooth" : "flat");
        frames[smooth] = shot.render(smooth);
        const reference::ImageComparison cmp = reference::compare_images(frames[smooth], shot.reference(smooth));
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.color_checked, shot.options.width * shot.options.height / 3);
        // Both tracers give the same bits.
        const RenderedFrame single = shot.render(smooth, Tracer::single);
        EXPECT_EQ(0, std::memcmp(single.color.data(), frames[smooth].color.data(),
                                 single.color.size() * sizeof(glm::vec3)));
    }
    int different = 0, on_sphere = 0;
    for (std::size_t p = 0; p < frames[0].color.size(); ++p) {
        if (frames[0].object[p] != 0) continue;
        ++on_sphere;
        const glm::vec3 d = glm::abs(frames[0].color[p] - frames[1].color[p]);
        different += std::max({d.x, d.y, d.z}) > 1e-3f;
        // The normal AOV stays the geometric normal either way.
        EXPECT_EQ(frames[0].normal[p], frames[1].normal[p]);
    }
    EXPECT_GT(on_sphere, 200);
    EXPECT_GT(different, on_sphere / 2) << "smooth shading changes most of the sphere";
}

TEST(SmoothShading, TheSphereShowsNoFacets) {
    // The largest colour step between horizontal neighbours on the sphere: at facet edges the
    // flat image jumps, the smooth one changes gradually.
    const SphereShot shot;
    float steps[2] = {0.0f, 0.0f};
    for (const bool smooth : {false, true}) {
        const RenderedFrame f = shot.render(smooth);
        for (int y = 0; y < f.height; ++y) {
            for (int x = 0; x + 1 < f.width; ++x) {
                const std::size_t p = std::size_t(y * f.width + x);
                if (f.object[p] != 0 || f.object[p + 1] != 0) continue;
                const glm::vec3 d = glm::abs(f.color[p] - f.color[p + 1]);
                steps[smooth] = std::max(steps[smooth], std::max({d.x, d.y, d.z}));
            }
        }
    }
    EXPECT_LT(steps[1], 0.6f * steps[0]) << "flat " << steps[0] << ", smooth " << steps[1];
}

TEST(SmoothShading, NormalsAgainstTheWindingShadeAsNormalsAlongIt) {
    // Flipping every vertex normal changes nothing: the shading normal is turned to the
    // geometric normal's side either way.
    const SphereShot shot;
    SphereShot flipped;
    for (Object& object : flipped.scene.objects) {
        for (glm::vec3& n : object.mesh.normals.edit()) n = -n;
    }
    const RenderedFrame a = shot.render(true), b = flipped.render(true);
    EXPECT_EQ(0, std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(glm::vec3)));
}

TEST(SmoothShading, FlatOptionIgnoresTheNormalsBitForBit) {
    // --normals flat renders the scene as if it had no normals at all.
    const SphereShot shot;
    SphereShot bare;
    for (Object& object : bare.scene.objects) object.mesh.normals.clear();
    const RenderedFrame flat = shot.render(false), none = bare.render(true);
    EXPECT_EQ(0, std::memcmp(flat.color.data(), none.color.data(), flat.color.size() * sizeof(glm::vec3)));
}

}  // namespace
}  // namespace dynrt
