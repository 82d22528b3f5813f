// glTF animation data through the loader and ScenePoser: node TRS channels with each
// interpolation mode down a hierarchy, skins (several joints, two and eight influences,
// inverse bind matrices), morph targets (default and animated weights), the animated camera,
// and a malformed file for every validation rule the loader promises.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include "gltf_test_file.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace dynrt {
namespace {

using anim::MotionClass;
using anim::PosedScene;
using anim::PoseSettings;
using anim::ScenePoser;
using nlohmann::json;
using test::GltfTestFile;

const std::vector<float> kTriangle = {1, 0, 0, 0, 1, 0, 0, 0, 1};
const float kHalfSqrt2 = static_cast<float>(std::sqrt(0.5));

/// Poses `scene` at time `t` seconds (fps 1000, so t must be a multiple of 1 ms).
PosedScene pose_at(const Scene& scene, double t) {
    PoseSettings settings;
    settings.fps = 1000.0;
    PosedScene posed;
    anim::pose_scene(scene, settings, static_cast<int>(std::lround(t * 1000.0)), posed);
    return posed;
}

void expect_near(const glm::vec3& actual, const glm::dvec3& expected, const std::string& what = "") {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], 1e-5) << what << " component " << c;
}

Scene load(const GltfTestFile& file, const std::string& name = "anim.gltf") { return load_gltf(file.write(name)); }

/// Expects loading `file` to fail with one line starting with its path and holding each fragment.
void expect_error(const GltfTestFile& file, const std::vector<std::string>& fragments) {
    const std::filesystem::path path = file.write("bad.gltf");
    try {
        load_gltf(path);
        ADD_FAILURE() << "no error; expected " << fragments.back();
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        for (const std::string& fragment : fragments) {
            EXPECT_NE(what.find(fragment), std::string::npos) << "'" << fragment << "' not in: " << what;
        }
    }
}

// ---- Node animation --------------------------------------------------------------------------

/// parent (translation LINEAR 0 -> (4,0,0) over [0, 2] s) -> child with the mesh (rotation
/// STEP: identity, then 90 degrees about Z from t = 1; scale CUBICSPLINE 1 -> 2 over [0, 2]
/// with out-tangent 1 at the first key and in-tangent 0 at the second).
GltfTestFile hierarchy_file() {
    GltfTestFile f;
    const int child = f.add_node({{"name", "child"}, {"mesh", f.add_mesh(kTriangle)}}, false);
    const int parent = f.add_node({{"name", "parent"}, {"children", json::array({child})}});
    f.add_animation("Walk", {{parent, "translation", {0, 2}, {0, 0, 0, 4, 0, 0}},
                             {child, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, kHalfSqrt2, kHalfSqrt2}, "STEP"},
                             {child, "scale", {0, 2}, {0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0, 0, 2, 2, 2, 9, 9, 9}, "CUBICSPLINE"}});
    return f;
}

TEST(GltfAnimation, LoadsNodesClipsAndTheirBindings) {
    GltfTestFile f = hierarchy_file();
    f.add_animation("", {{0, "translation", {0}, {0, 0, 1}}});
    const Scene scene = load(f);
    ASSERT_EQ(scene.nodes.size(), 2u);
    EXPECT_EQ(scene.nodes[0].name, "parent");
    EXPECT_EQ(scene.nodes[0].parent, -1);
    EXPECT_EQ(scene.nodes[1].name, "child");
    EXPECT_EQ(scene.nodes[1].parent, 0);
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].node, 1);
    ASSERT_EQ(scene.clips.size(), 2u);
    EXPECT_EQ(scene.clips[1].name, "animation1");
    const AnimationClip& walk = scene.clips[0];
    EXPECT_EQ(walk.name, "Walk");
    ASSERT_EQ(walk.channels.size(), 3u);
    EXPECT_EQ(walk.channels[0].node, 0u);  // scene node indices, not glTF ones
    EXPECT_EQ(walk.channels[1].node, 1u);
    EXPECT_EQ(walk.channels[1].property, AnimatedProperty::rotation);
    EXPECT_EQ(walk.samplers[1].interpolation, Interpolation::step);
    EXPECT_EQ(walk.samplers[2].interpolation, Interpolation::cubic_spline);
    EXPECT_EQ(walk.samplers[2].values.size(), 18u);
    EXPECT_EQ(walk.start_time(), 0.0);
    EXPECT_EQ(walk.end_time(), 2.0);
    // Rotation keys are normalised on load (the file rounds sqrt(1/2) to float).
    const std::vector<double>& q = walk.samplers[1].values;
    EXPECT_NEAR(q[6] * q[6] + q[7] * q[7], 1.0, 1e-15);
}

TEST(GltfAnimation, StepLinearAndCubicSplineDownAHierarchy) {
    const Scene scene = load(hierarchy_file());
    // Vertex 0 is (1, 0, 0) in the child's space: world = T(parent) * R(child) * S(child) * p.
    // t = 0.5: translation (1, 0, 0); rotation still the identity (STEP); scale by the Hermite
    // basis at s = 0.25: 0.84375 * 1 + 2 * 0.140625 * 1 + 0.15625 * 2 = 1.4375.
    expect_near(pose_at(scene, 0.5).objects[0].positions[0], {2.4375, 0, 0}, "t = 0.5");
    // t = 1: translation (2, 0, 0); rotation 90 degrees (STEP reaches key 1); scale at s = 0.5:
    // 0.5 + 2 * 0.125 + 0.5 * 2 = 1.75. (1.75, 0, 0) -> (0, 1.75, 0) -> (2, 1.75, 0).
    expect_near(pose_at(scene, 1.0).objects[0].positions[0], {2, 1.75, 0}, "t = 1");
    // Clamped after the last keys and before the first.
    expect_near(pose_at(scene, 3.0).objects[0].positions[0], {4, 2, 0}, "t = 3");
    expect_near(pose_at(scene, -1.0).objects[0].positions[0], {1, 0, 0}, "t = -1");
    // The object is rigid: its world transform carries the motion, positions follow it.
    const PosedScene posed = pose_at(scene, 1.0);
    EXPECT_EQ(posed.objects[0].motion_class, MotionClass::rigid);
    EXPECT_NEAR(posed.objects[0].transform[3][0], 2.0, 1e-12);
    EXPECT_NEAR(posed.node_world[0][3][0], 2.0, 1e-12);
}

TEST(GltfAnimation, DefaultFpsIs24AndTheOldSignatureAnimates) {
    const Scene scene = load(hierarchy_file());
    PosedScene posed;
    anim::pose_scene(scene, 24, posed);  // t = 1 s
    EXPECT_EQ(posed.time_s, 1.0);
    expect_near(posed.objects[0].positions[0], {2, 1.75, 0});
}

TEST(GltfAnimation, StaticScenesPoseExactlyAsBefore) {
    const Scene scene = load_gltf(default_scene_path());
    PosedScene posed;
    anim::pose_scene(scene, 5, posed);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const glm::dmat4 m(scene.objects[i].transform);
        EXPECT_EQ(posed.objects[i].motion_class, MotionClass::static_);
        for (std::size_t v = 0; v < scene.objects[i].mesh.positions.size(); v += 97) {
            const glm::dvec4 p = m * glm::dvec4(glm::dvec3(scene.objects[i].mesh.positions[v]), 1.0);
            ASSERT_EQ(posed.objects[i].positions[v], glm::vec3(glm::dvec3(p) / p.w)) << scene.objects[i].name;
        }
    }
}

TEST(GltfAnimation, NonFiniteResultsNameObjectAndFrame) {
    GltfTestFile f;
    const int inner = f.add_node({{"name", "inner"}, {"mesh", f.add_mesh(kTriangle)}, {"scale", {1e30, 1e30, 1e30}}}, false);
    const int outer = f.add_node({{"name", "outer"}, {"children", json::array({inner})}});
    f.add_animation("Grow", {{outer, "scale", {0, 1}, {1, 1, 1, 1e30f, 1e30f, 1e30f}}});
    const Scene scene = load(f);
    PosedScene posed;
    anim::pose_scene(scene, 0, posed);  // 1e30: still finite in float
    try {
        anim::pose_scene(scene, 24, posed);
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("object 'inner/mesh', frame 24: vertex 0 has a non-finite position"),
                  std::string::npos)
            << e.what();
    }
}

// ---- Skins -----------------------------------------------------------------------------------

/// A chain of joints j0 (origin) -> j1 (0, 1, 0) -> j2 (0, 1, 0) with inverse bind matrices
/// T(0, 0, 0), T(0, -1, 0), T(0, -2, 0); j1 turns 90 degrees about Z over [0, 1] s. The mesh
/// node (translated by 100, which skinning ignores) has vertices (0.5, 0, 0) on j0,
/// (0.5, 1, 0) half j0 half j1, (0.5, 2, 0) a quarter j1 and three quarters j2.
GltfTestFile chain_file() {
    GltfTestFile f;
    const int j0 = f.add_node({{"name", "j0"}});
    const int j1 = f.add_node({{"name", "j1"}, {"translation", {0.0, 1.0, 0.0}}}, false);
    const int j2 = f.add_node({{"name", "j2"}, {"translation", {0.0, 1.0, 0.0}}}, false);
    f.add_child(j0, j1);
    f.add_child(j1, j2);
    std::vector<float> ibm;
    for (const float y : {0.0f, -1.0f, -2.0f}) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, y, 0, 1});
    f.doc()["skins"] = json::array({json{{"joints", {j0, j1, j2}}, {"inverseBindMatrices", f.add_floats(ibm, "MAT4")}}});
    const int joints =
        f.add_accessor(std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1, 0, 0, 1, 2, 0, 0}, "VEC4", test::kGltfUnsignedByte);
    const int weights = f.add_floats({1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.25f, 0.75f, 0, 0}, "VEC4");
    const int mesh = f.add_mesh({0.5f, 0, 0, 0.5f, 1, 0, 0.5f, 2, 0}, {{"JOINTS_0", joints}, {"WEIGHTS_0", weights}});
    f.add_node({{"name", "body"}, {"mesh", mesh}, {"skin", 0}, {"translation", {100.0, 0.0, 0.0}}});
    f.add_animation("Bend", {{j1, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, kHalfSqrt2, kHalfSqrt2}}});
    return f;
}

TEST(GltfSkinning, SeveralJointsAndTwoInfluences) {
    const Scene scene = load(chain_file());
    ASSERT_EQ(scene.skins.size(), 1u);
    EXPECT_EQ(scene.skins[0].joints, (std::vector<std::uint32_t>{0, 1, 2}));
    EXPECT_EQ(scene.skins[0].inverse_bind_matrices[2][3][1], -2.0);
    ASSERT_TRUE(scene.objects[0].skin.has_value());
    EXPECT_EQ(scene.objects[0].skin->influences, 4u);

    // At rest the bind pose comes back (not shifted by the node's translation of 100).
    const PosedScene rest = pose_at(scene, 0.0);
    expect_near(rest.objects[0].positions[1], {0.5, 1, 0}, "rest");
    EXPECT_EQ(rest.objects[0].motion_class, MotionClass::deformable);
    EXPECT_EQ(rest.objects[0].transform, glm::dmat4(1.0));

    // t = 1: J1 = J2 = T(0, 1, 0) R90 T(0, -1, 0), with R90 (x, y) -> (-y, x).
    const PosedScene bent = pose_at(scene, 1.0);
    expect_near(bent.objects[0].positions[0], {0.5, 0, 0}, "j0 only");
    // 0.5 (0.5, 1, 0) + 0.5 J1 (0.5, 1, 0) = 0.5 (0.5, 1, 0) + 0.5 (0, 1.5, 0).
    expect_near(bent.objects[0].positions[1], {0.25, 1.25, 0}, "half and half");
    // J1 and J2 both take (0.5, 2, 0) to (-1, 1.5, 0).
    expect_near(bent.objects[0].positions[2], {-1, 1.5, 0}, "j1 and j2");
    ASSERT_EQ(bent.objects[0].joint_matrices.size(), 3u);

    // t = 0.5 (slerp: 45 degrees): J1 (0.5, 1, 0) = (0.5 cos 45, 1 + 0.5 sin 45, 0).
    const double c = std::sqrt(0.5);
    expect_near(pose_at(scene, 0.5).objects[0].positions[1], {0.5 * (0.5 + 0.5 * c), 0.5 * (1 + 1 + 0.5 * c), 0}, "t = 0.5");
}

TEST(GltfSkinning, EightInfluencesWithNormalizedWeights) {
    GltfTestFile f;
    std::vector<int> joints;
    for (const std::string name : {"j0", "j1", "j2"}) {
        const double k = static_cast<double>(joints.size());
        joints.push_back(f.add_node({{"name", name}, {"translation", {k + 1.0, 0.0, 10.0 * k}}}));
    }
    f.doc()["skins"] = json::array({json{{"joints", joints}}});
    const int joints0 = f.add_accessor(std::vector<std::uint16_t>(12, 0), "VEC4", test::kGltfUnsignedShort);
    const int joints1 =
        f.add_accessor(std::vector<std::uint16_t>{1, 2, 0, 0, 1, 2, 0, 0, 1, 2, 0, 0}, "VEC4", test::kGltfUnsignedShort);
    const int weights0 = f.add_floats({0.2f, 0, 0, 0, 0.2f, 0, 0, 0, 0.2f, 0, 0, 0}, "VEC4");
    // 51 / 255 = 0.2 and 153 / 255 = 0.6: weights (0.2, 0.2, 0.6) on joints (0, 1, 2).
    const int weights1 = f.add_accessor(std::vector<std::uint8_t>{51, 153, 0, 0, 51, 153, 0, 0, 51, 153, 0, 0}, "VEC4",
                                        test::kGltfUnsignedByte, true);
    const int mesh = f.add_mesh(kTriangle, {{"JOINTS_0", joints0}, {"WEIGHTS_0", weights0},
                                            {"JOINTS_1", joints1}, {"WEIGHTS_1", weights1}});
    f.add_node({{"name", "body"}, {"mesh", mesh}, {"skin", 0}});
    const Scene scene = load(f);
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.objects[0].skin->influences, 8u);
    EXPECT_EQ(scene.objects[0].skin->joints[5], 2u);
    EXPECT_FLOAT_EQ(scene.objects[0].skin->weights[5], 0.6f);
    // p + 0.2 (1, 0, 0) + 0.2 (2, 0, 10) + 0.6 (3, 0, 20) = p + (2.4, 0, 14).
    const PosedScene posed = pose_at(scene, 0.0);
    EXPECT_EQ(posed.objects[0].motion_class, MotionClass::static_);
    expect_near(posed.objects[0].positions[0], {3.4, 0, 14});
    expect_near(posed.objects[0].positions[1], {2.4, 1, 14});
}

// ---- Morph targets ---------------------------------------------------------------------------

/// One mesh with two position targets (d0 moves vertex 2 by (0, 0, 1), d1 by (0, 2, 0); a
/// third target has only a NORMAL) and mesh weights (0.25, 0.5, 0); nodes: "by_mesh" uses the
/// mesh weights, "by_node" its own (1, 0, 0), "animated" has them animated (0,0,0) -> (1,1,0)
/// over [0, 1] s.
GltfTestFile morph_file() {
    GltfTestFile f;
    const int d0 = f.add_floats({0, 0, 0, 0, 0, 0, 0, 0, 1}, "VEC3");
    const int d1 = f.add_floats({0, 0, 0, 0, 0, 0, 0, 2, 0}, "VEC3");
    const int normal = f.add_floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int mesh = f.add_mesh(kTriangle, json::object(),
                                json::array({json{{"POSITION", d0}}, json{{"POSITION", d1}}, json{{"NORMAL", normal}}}));
    f.doc()["meshes"][mesh]["weights"] = {0.25, 0.5, 0.0};
    f.add_node({{"name", "by_mesh"}, {"mesh", mesh}});
    f.add_node({{"name", "by_node"}, {"mesh", mesh}, {"weights", {1.0, 0.0, 0.0}}});
    const int animated = f.add_node({{"name", "animated"}, {"mesh", mesh}});
    f.add_animation("Breathe", {{animated, "weights", {0, 1}, {0, 0, 0, 1, 1, 0}}});
    return f;
}

TEST(GltfMorphing, DefaultWeightsFromMeshOrNode) {
    const Scene scene = load(morph_file());
    ASSERT_EQ(scene.objects.size(), 3u);
    const Object& by_mesh = scene.objects[0];
    ASSERT_TRUE(by_mesh.morph.has_value());
    EXPECT_EQ(by_mesh.morph->position_deltas.size(), 3u);
    EXPECT_EQ(by_mesh.morph->position_deltas[2][2], glm::vec3(0.0f));  // NORMAL only: no displacement
    EXPECT_EQ(by_mesh.morph->default_weights, (std::vector<double>{0.25, 0.5, 0.0}));
    EXPECT_EQ(by_mesh.morph->base_positions[2], glm::vec3(0, 0, 1));
    // mesh.positions carries the default weights: (0, 0, 1) + 0.25 (0, 0, 1) + 0.5 (0, 2, 0).
    EXPECT_EQ(by_mesh.mesh.positions[2], glm::vec3(0, 1, 1.25f));
    EXPECT_EQ(scene.objects[1].morph->default_weights, (std::vector<double>{1.0, 0.0, 0.0}));
    EXPECT_EQ(scene.objects[1].mesh.positions[2], glm::vec3(0, 0, 2));

    const PosedScene posed = pose_at(scene, 0.0);
    EXPECT_EQ(posed.objects[0].positions[2], glm::vec3(0, 1, 1.25f));
    EXPECT_EQ(posed.objects[0].morph_weights, (std::vector<double>{0.25, 0.5, 0.0}));
    EXPECT_EQ(posed.objects[0].motion_class, MotionClass::static_);
    EXPECT_EQ(posed.objects[1].motion_class, MotionClass::static_);
}

TEST(GltfMorphing, AnimatedWeights) {
    const Scene scene = load(morph_file());
    const PosedScene posed = pose_at(scene, 0.5);
    EXPECT_EQ(posed.objects[2].motion_class, MotionClass::deformable);
    EXPECT_EQ(posed.objects[2].morph_weights, (std::vector<double>{0.5, 0.5, 0.0}));
    // (0, 0, 1) + 0.5 (0, 0, 1) + 0.5 (0, 2, 0).
    EXPECT_EQ(posed.objects[2].positions[2], glm::vec3(0, 1, 1.5f));
    expect_near(pose_at(scene, 7.0).objects[2].positions[2], {0, 2, 2}, "clamped at weights (1, 1, 0)");
}

TEST(GltfMorphing, TargetsWithoutPositionsAreNotMorphs) {
    GltfTestFile f;
    const int normal = f.add_floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    f.add_node({{"name", "n"}, {"mesh", f.add_mesh(kTriangle, json::object(), json::array({json{{"NORMAL", normal}}}))}});
    EXPECT_FALSE(load(f).objects[0].morph.has_value());
}

// ---- Cameras ---------------------------------------------------------------------------------

TEST(GltfCamera, FollowsItsAnimatedNode) {
    GltfTestFile f;
    f.add_node({{"name", "thing"}, {"mesh", f.add_mesh(kTriangle)}});
    f.doc()["cameras"] = json::array({json{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"zfar", 10}, {"znear", 0.1}}}},
                                      json{{"name", "eye"}, {"type", "perspective"},
                                           {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.5}, {"znear", 0.1}}}}});
    f.add_node({{"name", "flat"}, {"camera", 0}});
    // The camera turns 90 degrees about +Y (looking down -X instead of -Z) under a dolly
    // moving from z = 0 to z = 10 over [0, 1] s.
    const int camera = f.add_node({{"name", "cam_node"}, {"camera", 1}, {"rotation", {0.0, kHalfSqrt2, 0.0, kHalfSqrt2}}}, false);
    const int dolly = f.add_node({{"name", "dolly"}, {"children", json::array({camera})}});
    f.add_animation("Dolly", {{dolly, "translation", {0, 1}, {0, 0, 0, 0, 0, 10}}});
    const Scene scene = load(f);
    ASSERT_EQ(scene.cameras.size(), 1u);  // the orthographic one is skipped
    EXPECT_EQ(scene.cameras[0].name, "eye");
    EXPECT_EQ(scene.cameras[0].aspect_ratio, 1.5);

    const PosedScene posed = pose_at(scene, 0.5);
    ASSERT_TRUE(posed.camera.has_value());
    const anim::PosedCamera& c = *posed.camera;
    EXPECT_NEAR(c.eye.x, 0.0, 1e-12);
    EXPECT_NEAR(c.eye.z, 5.0, 1e-12);
    EXPECT_NEAR(c.forward.x, -1.0, 1e-6);
    EXPECT_NEAR(c.forward.z, 0.0, 1e-6);
    EXPECT_NEAR(c.up.y, 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(c.yfov_rad, 0.8);
    EXPECT_NEAR(pose_at(scene, 3.0).camera->eye.z, 10.0, 1e-12);

    EXPECT_FALSE(pose_at(load(hierarchy_file()), 0.0).camera.has_value());
}

// ---- Malformed files -------------------------------------------------------------------------

TEST(GltfAnimationErrors, Samplers) {
    // Each case starts from the valid hierarchy file; the "Walk" translation sampler is 0.
    const auto walk = [](const std::function<void(GltfTestFile&, json& sampler)>& edit) {
        GltfTestFile f = hierarchy_file();
        edit(f, f.doc()["animations"][0]["samplers"][0]);
        return f;
    };
    expect_error(walk([](GltfTestFile& f, json& s) { s["input"] = f.add_floats({0, 1, 1}, "SCALAR"); s["output"] = f.add_floats(std::vector<float>(9, 0), "VEC3"); }),
                 {"animation 'Walk' sampler 0: input key 2 (1.000000 s) is not after key 1 (1.000000 s)"});
    expect_error(walk([](GltfTestFile& f, json& s) { s["input"] = f.add_accessor(std::vector<std::uint8_t>{0, 1, 2, 3}, "SCALAR", test::kGltfUnsignedByte); }),
                 {"animation 'Walk' sampler 0: input: accessor", "must be FLOAT SCALAR, not UNSIGNED_BYTE SCALAR"});
    expect_error(walk([](GltfTestFile& f, json& s) { s["input"] = f.add_floats({0, std::numeric_limits<float>::infinity()}, "SCALAR"); }),
                 {"sampler 0: input: accessor", "element 1 is not finite"});
    expect_error(walk([](GltfTestFile& f, json& s) { s["output"] = f.add_floats({0, 0, 0, 1, 1, 1, 2, 2, 2}, "VEC3"); }),
                 {"animation 'Walk' sampler 0: output has 9 numbers, expected 6 (2 keys x 3)"});
    expect_error(walk([](GltfTestFile&, json& s) { s["interpolation"] = "CUBICSPLINE"; }),
                 {"sampler 0: output has 6 numbers, expected 18 (2 keys x 3 (in-tangent, value, out-tangent) x 3)"});
    expect_error(walk([](GltfTestFile&, json& s) { s["interpolation"] = "QUADRATIC"; }),
                 {"animation 'Walk' sampler 0: unknown interpolation 'QUADRATIC'"});
    expect_error(walk([](GltfTestFile& f, json& s) { s["output"] = f.add_floats({0, 0, 0, std::nanf(""), 0, 0}, "VEC3"); }),
                 {"sampler 0: output: accessor", "element 1 is not finite"});
    expect_error(walk([](GltfTestFile& f, json& s) { s["output"] = f.add_floats({0, 0, 0, 0, 0, 0, 0, 0}, "VEC4"); }),
                 {"sampler 0: output: accessor", "must be FLOAT VEC3, not FLOAT VEC4"});

    GltfTestFile rotation = hierarchy_file();
    rotation.doc()["animations"][0]["samplers"][1]["output"] = rotation.add_floats({0, 0, 0, 1, 0, 0, 0, 0}, "VEC4");
    expect_error(rotation, {"animation 'Walk' sampler 1: output key 1: rotation quaternion has zero length"});
    rotation = hierarchy_file();
    rotation.doc()["animations"][0]["samplers"][1]["output"] = rotation.add_floats({0, 0, 0, 0, 0, 0}, "VEC3");
    expect_error(rotation, {"sampler 1: output: accessor", "must be FLOAT or normalized (UNSIGNED_)BYTE/SHORT VEC4"});
    rotation = hierarchy_file();
    rotation.doc()["animations"][0]["samplers"][1]["output"] =
        rotation.add_accessor(std::vector<std::int16_t>{0, 0, 0, 32767, 0, 0, 32767, 0}, "VEC4", test::kGltfShort);
    expect_error(rotation, {"sampler 1: output: accessor", "SHORT components must be normalized"});
    // Normalized SHORT rotations are fine: (0, 0, 1, 0) is 180 degrees about Z, so at t = 1
    // (1.75, 0, 0) -> (-1.75, 0, 0) -> (0.25, 0, 0).
    rotation.doc()["accessors"].back()["normalized"] = true;
    expect_near(pose_at(load(rotation), 1.0).objects[0].positions[0], {0.25, 0, 0}, "normalized SHORT rotation");
}

TEST(GltfAnimationErrors, Channels) {
    GltfTestFile f = hierarchy_file();
    f.doc()["animations"][0]["channels"][0]["sampler"] = 3;
    expect_error(f, {"animation 'Walk' channel 0: sampler 3 does not exist (3 samplers)"});
    f = hierarchy_file();
    f.doc()["animations"][0]["channels"][2]["target"]["node"] = 42;
    expect_error(f, {"animation 'Walk' channel 2: target node 42 does not exist (2 nodes)"});
    f = hierarchy_file();
    f.doc()["animations"][0].erase("name");
    f.doc()["nodes"][1].erase("translation");
    f.doc()["nodes"][1]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    expect_error(f, {"animation 'animation0' channel 0: animates node 'parent', which has a matrix"});
    f = hierarchy_file();
    f.doc()["animations"][0]["channels"][1]["sampler"] = 0;  // translation values for a rotation
    expect_error(f, {"animation 'Walk' sampler 0: drives values of 3 and of 4 numbers"});
    f = hierarchy_file();
    f.doc()["animations"][0]["channels"][0]["target"]["path"] = "weights";
    expect_error(f, {"animation 'Walk' channel 0: animates the weights of node 'parent', which has no mesh"});
    f = hierarchy_file();
    f.doc()["animations"][0]["channels"][1]["target"]["path"] = "weights";
    expect_error(f, {"channel 1: animates the weights of node 'child', whose mesh has no morph targets"});

    GltfTestFile morph = morph_file();
    morph.doc()["animations"][0]["samplers"][0]["output"] = morph.add_floats({0, 0, 1, 1}, "SCALAR");
    expect_error(morph, {"animation 'Breathe' sampler 0: output has 4 numbers, expected 6 (2 keys x 3)"});

    // Unknown paths are skipped with a warning; channels on nodes outside the scene dropped.
    f = hierarchy_file();
    f.doc()["animations"][0]["channels"][0]["target"]["path"] = "pointer";
    const int outside = f.add_node({{"name", "outside"}}, false);
    f.doc()["animations"][0]["channels"][1]["target"]["node"] = outside;
    const Scene scene = load(f);
    EXPECT_EQ(scene.clips[0].channels.size(), 1u);
}

TEST(GltfAnimationErrors, Skins) {
    const auto chain = [](const std::function<void(GltfTestFile&, json& attributes)>& edit) {
        GltfTestFile f = chain_file();
        edit(f, f.doc()["meshes"][0]["primitives"][0]["attributes"]);
        return f;
    };
    expect_error(chain([](GltfTestFile& f, json& a) {
                     a["JOINTS_0"] = f.add_accessor(std::vector<std::uint8_t>{0, 0, 0, 0, 5, 0, 0, 0, 1, 2, 0, 0}, "VEC4",
                                                    test::kGltfUnsignedByte);
                 }),
                 {"object 'body/mesh': JOINTS_0 vertex 1: joint 5 out of range of the skin's 3 joints"});
    expect_error(chain([](GltfTestFile& f, json& a) { a["JOINTS_0"] = f.add_floats(std::vector<float>(12, 0), "VEC4"); }),
                 {"object 'body/mesh': JOINTS_0: accessor", "joint indices must be UNSIGNED_BYTE or UNSIGNED_SHORT VEC4"});
    expect_error(chain([](GltfTestFile& f, json& a) { a["WEIGHTS_0"] = f.add_floats({1, 0, 0, -0.5f, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4"); }),
                 {"object 'body/mesh': WEIGHTS_0 vertex 0: negative weight"});
    expect_error(chain([](GltfTestFile& f, json& a) { a["WEIGHTS_0"] = f.add_floats({1, 0, 0, 0, std::nanf(""), 0, 0, 0, 1, 0, 0, 0}, "VEC4"); }),
                 {"object 'body/mesh': WEIGHTS_0: accessor", "element 1 is not finite"});
    expect_error(chain([](GltfTestFile& f, json& a) { a["WEIGHTS_0"] = f.add_floats({1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0}, "VEC4"); }),
                 {"object 'body/mesh': skin weights of vertex 2 are all zero"});
    expect_error(chain([](GltfTestFile& f, json& a) {
                     a["WEIGHTS_0"] = f.add_accessor(std::vector<std::uint8_t>(12, 85), "VEC4", test::kGltfUnsignedByte);
                 }),
                 {"WEIGHTS_0: accessor", "UNSIGNED_BYTE components must be normalized here"});
    expect_error(chain([](GltfTestFile&, json& a) { a.erase("WEIGHTS_0"); }),
                 {"object 'body/mesh': skinned primitive needs both JOINTS_0 and WEIGHTS_0"});
    expect_error(chain([](GltfTestFile&, json& a) { a["JOINTS_1"] = a["JOINTS_0"]; }),
                 {"skinned primitive needs both JOINTS_1 and WEIGHTS_1"});
    expect_error(chain([](GltfTestFile& f, json& a) {
                     a["JOINTS_0"] = f.add_accessor(std::vector<std::uint8_t>(8, 0), "VEC4", test::kGltfUnsignedByte);
                 }),
                 {"JOINTS_0 has 2 and WEIGHTS_0 3 elements for 3 positions"});

    const auto skin = [](const std::function<void(GltfTestFile&, json& skin)>& edit) {
        GltfTestFile f = chain_file();
        edit(f, f.doc()["skins"][0]);
        return f;
    };
    expect_error(skin([](GltfTestFile& f, json& s) { s["inverseBindMatrices"] = f.add_floats(std::vector<float>(32, 0), "MAT4"); }),
                 {"node 'body': skin 'skin0': inverseBindMatrices has 2 matrices for 3 joints"});
    expect_error(skin([](GltfTestFile& f, json& s) { s["inverseBindMatrices"] = f.add_floats(std::vector<float>(12, 0), "VEC4"); }),
                 {"skin 'skin0': inverseBindMatrices: accessor", "must be FLOAT MAT4, not FLOAT VEC4"});
    expect_error(skin([](GltfTestFile& f, json& s) {
                     std::vector<float> m(48, 0.0f);
                     m[20] = std::numeric_limits<float>::infinity();
                     s["inverseBindMatrices"] = f.add_floats(m, "MAT4");
                 }),
                 {"skin 'skin0': inverseBindMatrices: accessor", "element 1 is not finite"});
    expect_error(skin([](GltfTestFile&, json& s) { s["joints"] = json::array(); }), {"skin 'skin0': has no joints"});
    expect_error(skin([](GltfTestFile&, json& s) { s["joints"] = {0, 1, 9}; }),
                 {"skin 'skin0': joint 2 is node 9, which does not exist (4 nodes)"});
    expect_error(skin([](GltfTestFile&, json& s) { s["joints"] = {0, 1, 1}; }),
                 {"skin 'skin0': joint 2 (node 'j1') is listed twice"});
    expect_error(skin([](GltfTestFile& f, json& s) {
                     s["name"] = "rig";
                     s["joints"][2] = f.add_node({{"name", "elsewhere"}}, false);
                 }),
                 {"skin 'rig': joint 2 is node 'elsewhere', which is not in the default scene"});

    GltfTestFile f = chain_file();
    f.doc()["nodes"][3]["skin"] = 4;
    expect_error(f, {"node 'body': skin 4 does not exist (1 skins)"});
    f = chain_file();
    f.doc()["nodes"][3].erase("mesh");
    expect_error(f, {"node 'body': has a skin but no mesh"});
}

TEST(GltfAnimationErrors, MorphTargetsAndCameras) {
    GltfTestFile f = morph_file();
    f.doc()["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = f.add_floats({0, 0, 0, 0, 0, 0}, "VEC3");
    expect_error(f, {"object 'by_mesh/mesh': morph target 1 POSITION has 2 elements for 3 positions"});
    f = morph_file();
    f.doc()["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = f.add_floats({0, 0, 0, 0, 0, 0}, "VEC2");
    expect_error(f, {"object 'by_mesh/mesh': morph target 0 POSITION: accessor", "POSITION must be FLOAT VEC3"});
    f = morph_file();
    f.doc()["meshes"][0]["weights"] = {1.0, 2.0};
    expect_error(f, {"object 'by_mesh/mesh': mesh weights has 2 numbers for 3 morph targets"});
    f = morph_file();
    f.doc()["nodes"][1]["weights"] = {1.0};
    expect_error(f, {"object 'by_node/mesh': node weights has 1 numbers for 3 morph targets"});
    f = morph_file();
    f.doc()["meshes"][0]["primitives"].push_back(f.doc()["meshes"][0]["primitives"][0]);
    f.doc()["meshes"][0]["primitives"][1].erase("targets");
    expect_error(f, {"object 'by_mesh/mesh#0': primitive 1 has 0 morph targets, primitive 0 has 3 (they must match)"});

    GltfTestFile camera = hierarchy_file();
    camera.doc()["cameras"] = json::array({json{{"name", "cam"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.0}, {"znear", 0.1}}}}});
    camera.add_node({{"name", "viewer"}, {"camera", 0}});
    expect_error(camera, {"camera 'cam': yfov must be in (0, pi) radians"});
    camera.doc()["nodes"].back()["camera"] = 3;
    expect_error(camera, {"node 'viewer': camera 3 does not exist (1 cameras)"});
}

}  // namespace
}  // namespace dynrt
