// The animated Khronos sample models in ../shared/scenes: each loads, classifies sensibly,
// poses to finite positions at several frames (before, inside and after its clips), stops
// changing once its clips are clamped, and, where the motion is simple enough to work out by
// hand, reaches known positions.

#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/scene_loading.h"
#include "shared_scene_files.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace dynrt::anim {
namespace {

namespace fs = std::filesystem;

struct Model {
    std::string path;
    /// The most general class any object must have: static (no animation), rigid (TRS only)
    /// or deformable (skins or morphs).
    MotionClass most_general;
    /// The number of clips the file has.
    std::size_t clips;
};

class SampleModel : public ::testing::TestWithParam<Model> {};

TEST_P(SampleModel, LoadsClassifiesAndPosesFinitePositions) {
    const Model& model = GetParam();
    LOAD_SHARED_OR_SKIP(scene, model.path);
    EXPECT_EQ(scene.clips.size(), model.clips);
    const ScenePoser poser(scene, {});
    MotionClass most_general = MotionClass::static_;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) most_general = std::max(most_general, poser.motion_class(i));
    EXPECT_EQ(most_general, model.most_general);

    PosedScene posed;
    const int last = static_cast<int>(std::ceil(poser.end_time() * kDefaultFps));
    for (const int frame : {-3, 0, 7, last / 2, last, last + 1, last + 50}) {
        SCOPED_TRACE(frame);
        poser.pose(frame, posed);  // throws on a non-finite position
        ASSERT_EQ(posed.objects.size(), scene.objects.size());
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            ASSERT_EQ(posed.objects[i].positions.size(), scene.objects[i].mesh.positions.size());
        }
    }
    // Past the end every clip is clamped: nothing changes from one frame to the next.
    for (const PosedObject& object : posed.objects) EXPECT_FALSE(object.changed);
}

INSTANTIATE_TEST_SUITE_P(
    Shared, SampleModel,
    ::testing::Values(Model{"boxanimated/BoxAnimated.glb", MotionClass::rigid, 1},
                      Model{"animatedcube/AnimatedCube.gltf", MotionClass::rigid, 1},
                      Model{"interpolationtest/InterpolationTest.glb", MotionClass::rigid, 9},
                      Model{"animatedtriangle/AnimatedTriangle.gltf", MotionClass::rigid, 1},
                      Model{"cesiummilktruck/CesiumMilkTruck.glb", MotionClass::rigid, 1},
                      Model{"simpleskin/SimpleSkin.gltf", MotionClass::deformable, 1},
                      Model{"riggedsimple/RiggedSimple.glb", MotionClass::deformable, 1},
                      Model{"riggedfigure/RiggedFigure.glb", MotionClass::deformable, 1},
                      Model{"cesiumman/CesiumMan.glb", MotionClass::deformable, 1},
                      Model{"fox/Fox.glb", MotionClass::deformable, 3},
                      Model{"recursiveskeletons/RecursiveSkeletons.glb", MotionClass::deformable, 1},
                      Model{"robot/robot.glb", MotionClass::deformable, 14},
                      Model{"simplemorph/SimpleMorph.gltf", MotionClass::deformable, 1},
                      Model{"animatedmorphcube/AnimatedMorphCube.glb", MotionClass::deformable, 1},
                      Model{"animatedmorphsphere/AnimatedMorphSphere.glb", MotionClass::deformable, 1},
                      Model{"morphprimitivestest/MorphPrimitivesTest.glb", MotionClass::static_, 0},
                      Model{"morphstresstest/MorphStressTest.glb", MotionClass::deformable, 3}),
    [](const ::testing::TestParamInfo<Model>& info) {
        return fs::path(info.param.path).parent_path().string();
    });

void expect_near(const glm::vec3& actual, const glm::dvec3& expected, double tolerance = 1e-5) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], tolerance) << "component " << c;
}

TEST(SampleModels, AnimatedTriangleTurnsAboutZIncludingTheWrapAround) {
    LOAD_SHARED_OR_SKIP(scene, "animatedtriangle/AnimatedTriangle.gltf");
    // Keys every 0.25 s: 0, 90, 180, 270, 360 degrees about Z; vertex 1 is (1, 0, 0). The last
    // pair, 270 -> 360, has a negative dot product: the short path turns through 315.
    const ScenePoser poser(scene, {});
    PosedScene posed;
    const double h = std::sqrt(0.5);
    const std::vector<std::pair<int, glm::dvec3>> expected = {
        {0, {1, 0, 0}}, {3, {h, h, 0}}, {6, {0, 1, 0}}, {12, {-1, 0, 0}}, {18, {0, -1, 0}}, {21, {h, -h, 0}}, {24, {1, 0, 0}}};
    for (const auto& [frame, position] : expected) {
        SCOPED_TRACE(frame);
        poser.pose(frame, posed);
        // The file's keys are 0.707 rather than sqrt(1/2); normalised they are exact.
        expect_near(posed.objects[0].positions[1], position, 1e-6);
    }
}

TEST(SampleModels, SimpleSkinBendsByHand) {
    LOAD_SHARED_OR_SKIP(scene, "simpleskin/SimpleSkin.gltf");
    // At t = 1 s the upper joint (at y = 1, inverse bind T(0, -1, 0)) has turned 90 degrees
    // about Z. Vertex 9 (0.5, 2, 0) follows it alone: (0.5, 1) -> (-1, 0.5) -> (-1, 1.5).
    // Vertex 4 (-0.5, 1, 0) is half on each joint: 0.5 (-0.5, 1) + 0.5 (0, 0.5).
    const ScenePoser poser(scene, {});
    EXPECT_EQ(poser.motion_class(0), MotionClass::deformable);
    PosedScene posed;
    poser.pose(24, posed);
    expect_near(posed.objects[0].positions[9], {-1, 1.5, 0});
    expect_near(posed.objects[0].positions[4], {-0.25, 0.75, 0});
    expect_near(posed.objects[0].positions[0], {-0.5, 0, 0});
}

TEST(SampleModels, SimpleMorphWeightsByHand) {
    LOAD_SHARED_OR_SKIP(scene, "simplemorph/SimpleMorph.gltf");
    // Vertex 2 is (0.5, 0.5, 0), moved by (-1, 1, 0) and (1, 1, 0); mesh weights (0.5, 0.5);
    // the clip's weights are (0, 0), (0, 1), (1, 1), (1, 0), (0, 0) at t = 0..4 s.
    EXPECT_EQ(scene.objects[0].mesh.positions[2], glm::vec3(0.5f, 1.5f, 0.0f));  // default weights
    const ScenePoser poser(scene, {});
    PosedScene posed;
    poser.pose(0, posed);
    EXPECT_EQ(posed.objects[0].positions[2], glm::vec3(0.5f, 0.5f, 0.0f));
    poser.pose(24, posed);
    EXPECT_EQ(posed.objects[0].positions[2], glm::vec3(1.5f, 1.5f, 0.0f));
    poser.pose(36, posed);  // t = 1.5: weights (0.5, 1)
    EXPECT_EQ(posed.objects[0].positions[2], glm::vec3(1.0f, 2.0f, 0.0f));
}

TEST(SampleModels, StaticMorphUsesTheMeshWeights) {
    LOAD_SHARED_OR_SKIP(scene, "morphprimitivestest/MorphPrimitivesTest.glb");
    bool moved = false;
    for (const Object& object : scene.objects) {
        ASSERT_TRUE(object.morph.has_value()) << object.name;
        EXPECT_EQ(object.morph->default_weights, std::vector<double>{0.5});
        moved = moved || object.mesh.positions != object.morph->base_positions;
    }
    EXPECT_TRUE(moved);
}

TEST(SampleModels, CesiumManWalksAndBoxAnimatedMovesRigidly) {
    LOAD_SHARED_OR_SKIP(man, "cesiumman/CesiumMan.glb");
    const ScenePoser walking(man, {});
    ASSERT_EQ(man.objects.size(), 1u);
    EXPECT_EQ(walking.motion_class(0), MotionClass::deformable);
    PosedScene a, b;
    walking.pose(5, a);
    walking.pose(20, b);
    EXPECT_NE(a.objects[0].positions, b.objects[0].positions);

    LOAD_SHARED_OR_SKIP(box, "boxanimated/BoxAnimated.glb");
    const ScenePoser boxes(box, {});
    std::vector<MotionClass> classes;
    for (std::size_t i = 0; i < box.objects.size(); ++i) classes.push_back(boxes.motion_class(i));
    EXPECT_NE(std::find(classes.begin(), classes.end(), MotionClass::rigid), classes.end());
    EXPECT_EQ(std::find(classes.begin(), classes.end(), MotionClass::deformable), classes.end());
}

TEST(SampleModels, FoxClipsCanBeChosen) {
    LOAD_SHARED_OR_SKIP(fox, "fox/Fox.glb");
    EXPECT_EQ(find_clip(fox, "Walk"), 1u);
    PoseSettings walk, run;
    walk.clips = std::vector<std::size_t>{find_clip(fox, "Walk")};
    run.clips = std::vector<std::size_t>{find_clip(fox, "Run")};
    const ScenePoser walking(fox, walk), running(fox, run);
    EXPECT_NEAR(walking.end_time(), 0.7083333, 1e-6);
    EXPECT_NEAR(running.end_time(), 1.1583333, 1e-6);
    PosedScene a, b;
    walking.pose(10, a);
    running.pose(10, b);
    EXPECT_NE(a.objects[0].positions, b.objects[0].positions);
}

TEST(SampleModels, MilkTruckWheelsTurnTheBodyStays) {
    LOAD_SHARED_OR_SKIP(truck, "cesiummilktruck/CesiumMilkTruck.glb");
    const ScenePoser poser(truck, {});
    int rigid = 0, still = 0;
    for (std::size_t i = 0; i < truck.objects.size(); ++i) {
        (poser.motion_class(i) == MotionClass::rigid ? rigid : still) += 1;
        if (poser.motion_class(i) == MotionClass::rigid) {
            EXPECT_NE(truck.objects[i].name.find("Wheel"), std::string::npos) << truck.objects[i].name;
        }
    }
    EXPECT_GE(rigid, 2);
    EXPECT_GE(still, 1);
}

TEST(SampleModels, SceneCameraIsFound) {
    LOAD_SHARED_OR_SKIP(scene, "transmissiontest/TransmissionTest.glb");
    ASSERT_FALSE(scene.cameras.empty());
    PosedScene posed;
    pose_scene(scene, 0, posed);
    ASSERT_TRUE(posed.camera.has_value());
    EXPECT_GT(posed.camera->yfov_rad, 0.0);
    EXPECT_NEAR(glm::length(posed.camera->forward), 1.0, 1e-12);
}

}  // namespace
}  // namespace dynrt::anim
