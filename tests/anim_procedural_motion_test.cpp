// The procedural motions against their written definitions (procedural_motion.h): hash32 values
// worked out by hand, rigid / wave / explode positions recomputed from the formulas, a
// degenerate triangle, evaluation from the rest pose at every frame, and the `--anim` parsing.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::anim {
namespace {

/// A scene of hand-made objects, each with its rest transform a translation.
Scene make_scene(const std::vector<std::pair<std::string, Mesh>>& meshes, glm::vec3 offset = glm::vec3(0.0f)) {
    Scene scene;
    scene.source = "hand-made";
    scene.materials.push_back(Material{});
    for (const auto& [name, mesh] : meshes) {
        Object object;
        object.name = name;
        object.mesh = mesh;
        object.transform[3] = glm::vec4(offset, 1.0f);
        scene.objects.push_back(object);
    }
    return scene;
}

/// Two triangles sharing the edge (1,0,0)-(1,1,0): one in the z = 0 plane (normal +Z), one in
/// the x = 1 plane (normal +X); then a degenerate (collinear) one. Box [0,1]^3.
Mesh folded_mesh() {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0.5f, 0.5f, 0}};
    mesh.triangles = {{0, 1, 2}, {1, 2, 3}, {0, 4, 2}};
    return mesh;
}

void expect_near(const glm::vec3& actual, const glm::dvec3& expected, double tolerance, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], tolerance) << what << " component " << c;
}

TEST(ProceduralMotion, Hash32ByHand) {
    // i = 1: x ^= x >> 16 -> 0x1; x *= 0x7feb352d -> 0x7feb352d; x ^= x >> 15 (0xffd6) ->
    // 0x7febcafb; x *= 0x846ca68b -> 0x6889f849 (mod 2^32); x ^= x >> 16 (0x6889) -> 0x688990c0.
    EXPECT_EQ(hash32(1), 0x688990c0u);
    EXPECT_EQ(hash32(0), 0u);  // every step keeps 0
    EXPECT_EQ(hash32(2), 0xd1132181u);
    EXPECT_EQ(hash32(3), 0x53f1e9ddu);
    EXPECT_EQ(hash32(12345), 0x912efcf7u);
    EXPECT_EQ(hash32(0xffffffffu), 0x6768824au);
    // h(i) = (hash32(i) >> 8) / 2^24.
    EXPECT_EQ(explode_hash(0), 0.0);
    EXPECT_EQ(explode_hash(1), 0x688990 / 16777216.0);
    EXPECT_EQ(explode_hash(2), 0xd11321 / 16777216.0);
    EXPECT_LT(explode_hash(0xffffffffu), 1.0);
}

TEST(ProceduralMotion, FaceNormalIsUnitOrZeroForDegenerateTriangles) {
    EXPECT_EQ(face_normal({0, 0, 0}, {2, 0, 0}, {0, 3, 0}), glm::dvec3(0, 0, 1));
    EXPECT_EQ(face_normal({0, 0, 0}, {1, 1, 0}, {2, 2, 0}), glm::dvec3(0.0));
    EXPECT_EQ(face_normal({1, 1, 1}, {1, 1, 1}, {1, 1, 1}), glm::dvec3(0.0));
}

TEST(ProceduralMotion, RigidRotatesAboutTheVerticalAxisThroughTheFrame0BoxCentre) {
    const glm::vec3 offset(5.0f, -1.0f, 2.0f);
    Scene scene = make_scene({{"folded", folded_mesh()}}, offset);
    const std::vector<std::string> specs = {"rigid"};
    add_procedural_motions(scene, specs);
    ASSERT_EQ(scene.motions.size(), 1u);
    EXPECT_EQ(scene.objects[0].mesh.positions.size(), 5u);  // rigid keeps shared vertices

    const ScenePoser poser(scene, {});
    EXPECT_EQ(poser.motion_class(0), MotionClass::rigid);
    const glm::dvec3 c = glm::dvec3(offset) + glm::dvec3(0.5, 0.5, 0.5);
    for (const int f : {0, 1, 10, 45, -7}) {
        PosedScene posed;
        poser.pose(f, posed);
        const double a = 2.0 * f * std::numbers::pi / 180.0;
        for (std::size_t v = 0; v < 5; ++v) {
            const glm::dvec3 p = glm::dvec3(scene.objects[0].mesh.positions[v]) + glm::dvec3(offset);
            const glm::dvec3 d = p - c;
            const glm::dvec3 expected =
                c + glm::dvec3(d.x * std::cos(a) + d.z * std::sin(a), d.y, -d.x * std::sin(a) + d.z * std::cos(a));
            expect_near(posed.objects[0].positions[v], expected, 1e-6, "frame " + std::to_string(f));
        }
        // Instanced evaluation gives the same: transform * object-space positions.
        for (std::size_t v = 0; v < 5; ++v) {
            const glm::dvec4 h = posed.objects[0].transform * glm::dvec4(glm::dvec3(poser.object_space_positions(0)[v]), 1.0);
            expect_near(posed.objects[0].positions[v], glm::dvec3(h), 1e-6, "transform");
        }
    }
    PosedScene frame0;
    poser.pose(0, frame0);
    for (std::size_t v = 0; v < 5; ++v) {
        EXPECT_EQ(frame0.objects[0].positions[v], scene.objects[0].mesh.positions[v] + offset) << v;
    }
}

TEST(ProceduralMotion, WaveMovesVerticesVertically) {
    Mesh grid;
    for (int i = 0; i < 5; ++i) {
        grid.positions.push_back({static_cast<float>(i), 0.0f, 0.0f});
        grid.positions.push_back({static_cast<float>(i), 0.0f, 2.0f});
    }
    for (std::uint32_t i = 0; i + 1 < 5; ++i) {
        grid.triangles.push_back({2 * i, 2 * i + 1, 2 * i + 2});
        grid.triangles.push_back({2 * i + 1, 2 * i + 3, 2 * i + 2});
    }
    Scene scene = make_scene({{"grid", grid}}, {1.0f, 3.0f, 0.0f});
    add_procedural_motions(scene, std::vector<std::string>{"wave:grid"});
    const ScenePoser poser(scene, {});
    EXPECT_EQ(poser.motion_class(0), MotionClass::deformable);
    // Box: x in [1, 5], y = 3, z in [0, 2]: R = sqrt(16 + 4) / 2.
    const double r = std::sqrt(20.0) / 2.0;
    PosedScene posed;
    for (const int f : {0, 7, 3}) {
        poser.pose(f, posed);
        for (std::size_t v = 0; v < grid.positions.size(); ++v) {
            const glm::dvec3 p = glm::dvec3(grid.positions[v]) + glm::dvec3(1.0, 3.0, 0.0);
            const glm::dvec3 expected = p + 0.05 * r * std::sin(6.0 * p.x / r + 0.5 * f) * glm::dvec3(0, 1, 0);
            expect_near(posed.objects[0].positions[v], expected, 1e-6, "frame " + std::to_string(f));
        }
        EXPECT_TRUE(posed.objects[0].changed);
    }
}

TEST(ProceduralMotion, ExplodeUnsharesTrianglesAndMovesThemAlongFrame0Normals) {
    Scene scene = make_scene({{"folded", folded_mesh()}, {"other", folded_mesh()}});
    add_procedural_motions(scene, std::vector<std::string>{"explode:folded"});
    const Object& folded = scene.objects[0];
    ASSERT_EQ(folded.mesh.positions.size(), 9u);
    EXPECT_EQ(folded.mesh.triangles[1], glm::uvec3(3, 4, 5));
    EXPECT_EQ(folded.mesh.positions[3], glm::vec3(1, 0, 0));  // triangle 1's first corner
    EXPECT_EQ(scene.objects[1].mesh.positions.size(), 5u);    // the other object keeps its mesh

    const ScenePoser poser(scene, {});
    EXPECT_EQ(poser.motion_class(0), MotionClass::deformable);  // same triangles, moved
    EXPECT_EQ(poser.motion_class(1), MotionClass::static_);
    const double r = std::sqrt(3.0) / 2.0;  // box [0,1]^3
    const glm::dvec3 normals[3] = {{0, 0, 1}, {1, 0, 0}, {0, 0, 0}};  // the last one is degenerate
    PosedScene posed;
    for (const int f : {5, 0, 12, 5}) {
        poser.pose(f, posed);
        ASSERT_EQ(posed.objects[0].positions.size(), 9u);
        for (std::uint32_t i = 0; i < 3; ++i) {
            const glm::dvec3 offset = f * 0.02 * r * (0.5 + explode_hash(i)) * normals[i];
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::size_t v = 3 * i + k;
                expect_near(posed.objects[0].positions[v], glm::dvec3(folded.mesh.positions[v]) + offset, 1e-6,
                            "frame " + std::to_string(f) + " vertex " + std::to_string(v));
            }
        }
    }
    // Frame 5, hand-computed for triangle 0 (h(0) = 0): moves 5 * 0.02 * R * 0.5 along +Z.
    EXPECT_NEAR(posed.objects[0].positions[0].z, 0.05 * r, 1e-7);
    // The degenerate triangle never moves.
    EXPECT_EQ(posed.objects[0].positions[7], glm::vec3(0.5f, 0.5f, 0.0f));
}

TEST(ProceduralMotion, SeveralMotionsComposeInOrder) {
    Scene scene = make_scene({{"folded", folded_mesh()}});
    add_procedural_motions(scene, std::vector<std::string>{"wave", "rigid:folded"});
    const ScenePoser poser(scene, {});
    EXPECT_EQ(poser.motion_class(0), MotionClass::deformable);
    PosedScene posed;
    poser.pose(9, posed);
    const MotionReference reference{glm::dvec3(0.5), std::sqrt(3.0) / 2.0};
    for (std::size_t v = 0; v < 5; ++v) {
        const glm::dvec3 p(scene.objects[0].mesh.positions[v]);
        expect_near(posed.objects[0].positions[v], rigid_motion(wave_motion(p, reference, 9), reference, 9), 1e-6,
                    "vertex " + std::to_string(v));
    }
}

TEST(ProceduralMotion, WorksOnProceduralScenesWithFixedVertexCounts) {
    Scene scene = make_procedural_scene("sphere:200+plane:50@0,-2,0");
    const std::size_t before = scene.objects[0].mesh.positions.size();
    PosedScene rest;
    pose_scene(scene, 0, rest);
    add_procedural_motions(scene, std::vector<std::string>{"explode:sphere:200", "wave:plane:50@0,-2,0"});
    EXPECT_EQ(scene.objects[0].mesh.positions.size(), 3 * scene.objects[0].mesh.triangles.size());
    EXPECT_GT(scene.objects[0].mesh.positions.size(), before);
    const ScenePoser poser(scene, {});
    PosedScene posed;
    poser.pose(0, posed);
    // Frame 0 of explode is the original geometry, corner by corner.
    const std::vector<glm::uvec3> triangles = make_procedural_scene("sphere:200").objects[0].mesh.triangles;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(posed.objects[0].positions[3 * t + k], rest.objects[0].positions[triangles[t][k]]);
    }
    for (const int f : {1, 30}) {
        poser.pose(f, posed);
        EXPECT_EQ(posed.objects[0].positions.size(), 3 * triangles.size());
        EXPECT_NE(posed.objects[1].positions, rest.objects[1].positions);
    }
}

TEST(ProceduralMotion, ParsingErrorsNameTheSpecAndLeaveTheSceneAlone) {
    Scene scene = make_scene({{"body/mesh#0", folded_mesh()}, {"body/mesh#1", folded_mesh()}, {"wheel", folded_mesh()}});
    const auto expect_invalid = [&](std::vector<std::string> specs, const std::string& fragment) {
        try {
            add_procedural_motions(scene, specs);
            ADD_FAILURE() << "no error for " << specs.back();
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
        EXPECT_TRUE(scene.motions.empty());
        EXPECT_EQ(scene.objects[0].mesh.positions.size(), 5u);
    };
    expect_invalid({"spin"}, "motion spec 'spin': unknown motion 'spin' (expected rigid, wave or explode)");
    expect_invalid({"explode", "wave:"}, "motion spec 'wave:': expected MOTION:OBJECT");
    expect_invalid({"explode", "wave:tyre"}, "motion spec 'wave:tyre': no object named 'tyre' in hand-made");
    expect_invalid({"explode", "wave:body/mesh#3"}, "(objects: 'body/mesh#0', 'body/mesh#1', 'wheel')");
    expect_invalid({"explode", "wave:bo"}, "no object named 'bo'");

    // A node name selects all its primitives, a mesh name with '#k' one of them.
    add_procedural_motions(scene, std::vector<std::string>{"wave:body", "rigid:body/mesh#1", "explode:wheel"});
    ASSERT_EQ(scene.motions.size(), 4u);
    EXPECT_EQ(scene.motions[0].object, 0u);
    EXPECT_EQ(scene.motions[1].object, 1u);
    EXPECT_EQ(scene.motions[2].object, 1u);
    EXPECT_EQ(scene.motions[2].kind, MotionKind::rigid);
    EXPECT_EQ(scene.motions[3].kind, MotionKind::explode);
    // Exploding the same object again keeps its (already unshared) mesh.
    add_procedural_motions(scene, std::vector<std::string>{"explode:wheel"});
    EXPECT_EQ(scene.objects[2].mesh.positions.size(), 9u);
}

}  // namespace
}  // namespace dynrt::anim
