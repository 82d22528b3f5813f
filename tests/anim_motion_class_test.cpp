// Motion classes derived from the animation data, classes forced by the user, clip selection,
// the per-frame `changed` flags (a clamped clip stops changing) and posing rigid objects
// without their vertices, on one small glTF scene with an object of each kind.

#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include "gltf_test_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::anim {
namespace {

using nlohmann::json;
using test::GltfTestFile;

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

/// Objects, in scene order:
///   0 still/mesh      nothing animates it                         static
///   1 child/mesh      its parent's translation is animated        rigid
///   2 spinner/mesh    its rotation is animated (clip "Spin")      rigid
///   3 skinned/mesh    skinned, joint "bone" rotates               deformable
///   4 puppet/mesh     skinned, its joints never move              static
///   5 morph/morphing  morph weights animated                      deformable
///   6 held/mesh       a one-key translation channel (constant)    static
///   7 frozen/morphing morph weights held at 0.5 by a clip         static
Scene classes_scene() {
    GltfTestFile f;
    const int plain = f.add_mesh(kTriangle);
    f.add_node({{"name", "still"}, {"mesh", plain}});
    const int child = f.add_node({{"name", "child"}, {"mesh", plain}}, false);
    const int parent = f.add_node({{"name", "parent"}, {"children", json::array({child})}});
    const int spinner = f.add_node({{"name", "spinner"}, {"mesh", plain}});

    const int root = f.add_node({{"name", "root"}});
    const int bone = f.add_node({{"name", "bone"}, {"translation", {0.0, 1.0, 0.0}}}, false);
    f.add_child(root, bone);
    const int joints = f.add_accessor(std::vector<std::uint16_t>{0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0}, "VEC4",
                                      test::kGltfUnsignedShort);
    const int weights = f.add_floats({1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0}, "VEC4");
    const int skinned_mesh = f.add_mesh(kTriangle, {{"JOINTS_0", joints}, {"WEIGHTS_0", weights}});
    f.doc()["skins"] = json::array({json{{"joints", {root, bone}}}});
    f.add_node({{"name", "skinned"}, {"mesh", skinned_mesh}, {"skin", 0}});
    const int still_bone = f.add_node({{"name", "still_bone"}});
    f.doc()["skins"].push_back({{"name", "puppet_skin"}, {"joints", {still_bone, root}}});
    f.add_node({{"name", "puppet"}, {"mesh", skinned_mesh}, {"skin", 1}});

    const int target = f.add_floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int morph_mesh = f.add_mesh(kTriangle, json::object(), json::array({json{{"POSITION", target}}}), "morphing");
    const int morph = f.add_node({{"name", "morph"}, {"mesh", morph_mesh}});
    const int held = f.add_node({{"name", "held"}, {"mesh", plain}});
    const int frozen = f.add_node({{"name", "frozen"}, {"mesh", morph_mesh}});

    const double s = std::sqrt(0.5);
    f.add_animation("Move", {{parent, "translation", {0, 1}, {0, 0, 0, 2, 0, 0}},
                             {bone, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, float(s), float(s)}},
                             {morph, "weights", {0, 1}, {0, 1}},
                             {held, "translation", {0.5f}, {0, 0, 3}},
                             {frozen, "weights", {0, 2}, {0.5f, 0.5f}}});
    f.add_animation("Spin", {{spinner, "rotation", {0, 2}, {0, 0, 0, 1, 0, float(s), 0, float(s)}}});
    f.add_animation("Other", {{spinner, "rotation", {0, 1}, {0, 0, 1, 0, 0, 0, 1, 0}}});
    return load_gltf(f.write("classes.gltf"));
}

std::vector<MotionClass> classes_of(const ScenePoser& poser, std::size_t count) {
    std::vector<MotionClass> classes;
    for (std::size_t i = 0; i < count; ++i) classes.push_back(poser.motion_class(i));
    return classes;
}

constexpr MotionClass S = MotionClass::static_, R = MotionClass::rigid, D = MotionClass::deformable,
                      E = MotionClass::exploding;

TEST(MotionClass, NamesRoundTrip) {
    for (const MotionClass c : {S, R, D, E}) EXPECT_EQ(parse_motion_class(motion_class_name(c)), c);
    EXPECT_EQ(std::string(motion_class_name(S)), "static");
    EXPECT_FALSE(parse_motion_class("Static").has_value());
}

TEST(MotionClass, DerivedFromTheAnimationData) {
    const Scene scene = classes_scene();
    ASSERT_EQ(scene.objects.size(), 8u);
    EXPECT_EQ(scene.objects[3].name, "skinned/mesh");
    const ScenePoser poser(scene, {});
    EXPECT_EQ(classes_of(poser, 8), (std::vector<MotionClass>{S, R, R, D, S, D, S, S}));
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(poser.derived_class(i), poser.motion_class(i));
    EXPECT_DOUBLE_EQ(poser.end_time(), 2.0);
}

TEST(MotionClass, ProceduralMotionsRaiseTheClass) {
    Scene scene = classes_scene();
    add_procedural_motions(scene, std::vector<std::string>{"rigid:still", "rigid:skinned", "wave:child",
                                                           "explode:puppet", "rigid:puppet"});
    const ScenePoser poser(scene, {});
    // explode makes the puppet deformable (the same triangles, moved), whatever else moves it.
    EXPECT_EQ(classes_of(poser, 8), (std::vector<MotionClass>{R, D, R, D, D, D, S, S}));
}

TEST(MotionClass, ClipSelectionChangesWhatMoves) {
    const Scene scene = classes_scene();
    EXPECT_EQ(find_clip(scene, "Spin"), 1u);
    EXPECT_EQ(find_clip(scene, "2"), 2u);
    try {
        find_clip(scene, "Jump");
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("clip 'Jump': no clip of that name or index in "), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("(clips: 0 'Move', 1 'Spin', 2 'Other')"), std::string::npos) << e.what();
    }
    EXPECT_THROW(find_clip(scene, "3"), std::invalid_argument);

    PoseSettings only_spin;
    only_spin.clips = std::vector<std::size_t>{1};
    EXPECT_EQ(classes_of(ScenePoser(scene, only_spin), 8), (std::vector<MotionClass>{S, S, R, S, S, S, S, S}));

    // "Other" holds the spinner at a constant 180 degrees about Z: static, but turned. Listed
    // first it wins over "Spin".
    PoseSettings other_first;
    other_first.clips = std::vector<std::size_t>{2, 1};
    const ScenePoser poser(scene, other_first);
    EXPECT_EQ(poser.motion_class(2), S);
    PosedScene posed;
    poser.pose(10, posed);
    EXPECT_NEAR(posed.objects[2].positions[1].x, -1.0f, 1e-6f);
    EXPECT_NEAR(posed.objects[2].positions[1].y, 0.0f, 1e-6f);

    PoseSettings none;
    none.clips = std::vector<std::size_t>{};
    const ScenePoser rest(scene, none);
    EXPECT_EQ(classes_of(rest, 8), std::vector<MotionClass>(8, S));
    EXPECT_EQ(rest.end_time(), 0.0);

    PoseSettings bad;
    bad.clips = std::vector<std::size_t>{3};
    EXPECT_THROW(ScenePoser(scene, bad), std::invalid_argument);
}

TEST(MotionClass, UsersMayRaiseButNotLowerAClass) {
    const Scene scene = classes_scene();
    PoseSettings settings;
    settings.class_overrides =
        parse_class_overrides(scene, std::vector<std::string>{"still=rigid", "spinner=exploding", "morph=deformable"});
    ASSERT_EQ(settings.class_overrides.size(), 3u);
    EXPECT_EQ(settings.class_overrides[1].object, 2u);
    const ScenePoser poser(scene, settings);
    EXPECT_EQ(classes_of(poser, 8), (std::vector<MotionClass>{R, R, E, D, S, D, S, S}));
    EXPECT_EQ(poser.derived_class(0), S);

    // Treated as exploding, the spinner's positions are world positions and its transform the
    // identity; treated as rigid, the still object's transform is its node's.
    PosedScene posed;
    poser.pose(12, posed);
    EXPECT_EQ(posed.objects[2].motion_class, E);
    EXPECT_EQ(posed.objects[2].transform, glm::dmat4(1.0));
    EXPECT_EQ(posed.objects[0].motion_class, R);

    settings.class_overrides = parse_class_overrides(scene, std::vector<std::string>{"spinner=static"});
    try {
        ScenePoser refused(scene, settings);
        ADD_FAILURE() << "lowering accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("class override 'spinner=static': object 'spinner/mesh' is rigid"),
                  std::string::npos)
            << e.what();
    }

    const auto expect_invalid = [&](const std::string& spec, const std::string& fragment) {
        try {
            parse_class_overrides(scene, std::vector<std::string>{spec});
            ADD_FAILURE() << "no error for " << spec;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    expect_invalid("spinner", "class override 'spinner': expected NAME=CLASS");
    expect_invalid("=rigid", "expected NAME=CLASS");
    expect_invalid("spinner=wobbly", "unknown class 'wobbly' (expected static, rigid, deformable or exploding)");
    expect_invalid("ghost=rigid", "class override 'ghost=rigid': no object named 'ghost'");
}

TEST(MotionClass, ChangedFlagsFollowTheClipAndStopWhenItIsClamped) {
    const Scene scene = classes_scene();
    const ScenePoser poser(scene, {});  // 24 fps: "Move" ends at frame 24, "Spin" at 48
    PosedScene posed;
    const auto changed = [&](int frame) {
        poser.pose(frame, posed);
        std::vector<bool> flags;
        for (const PosedObject& o : posed.objects) flags.push_back(o.changed);
        return flags;
    };
    EXPECT_EQ(changed(0), std::vector<bool>(8, true));  // first evaluation
    EXPECT_EQ(changed(0), std::vector<bool>(8, false));
    EXPECT_EQ(changed(1), (std::vector<bool>{false, true, true, true, false, true, false, false}));
    EXPECT_EQ(changed(24), (std::vector<bool>{false, true, true, true, false, true, false, false}));
    // Past the end of "Move" its objects stay put; the spinner turns until frame 48.
    EXPECT_EQ(changed(25), (std::vector<bool>{false, false, true, false, false, false, false, false}));
    EXPECT_EQ(changed(30), (std::vector<bool>{false, false, true, false, false, false, false, false}));
    EXPECT_EQ(changed(48), (std::vector<bool>{false, false, true, false, false, false, false, false}));
    EXPECT_EQ(changed(60), std::vector<bool>(8, false));
    // Going back changes them again.
    EXPECT_EQ(changed(12), (std::vector<bool>{false, true, true, true, false, true, false, false}));
}

TEST(MotionClass, RaisedObjectsStillReportTheirNodesMotion) {
    const Scene scene = classes_scene();
    PoseSettings settings;
    settings.class_overrides = parse_class_overrides(scene, std::vector<std::string>{"child=deformable"});
    const ScenePoser poser(scene, settings);
    PosedScene posed;
    poser.pose(0, posed);
    poser.pose(12, posed);  // t = 0.5: the parent has moved by (1, 0, 0)
    EXPECT_TRUE(posed.objects[1].changed);
    EXPECT_EQ(posed.objects[1].transform, glm::dmat4(1.0));
    EXPECT_NEAR(posed.objects[1].node_transform[3][0], 1.0, 1e-12);
    EXPECT_NEAR(posed.objects[1].positions[1].x, 2.0f, 1e-6f);
    poser.pose(25, posed);
    poser.pose(26, posed);
    EXPECT_FALSE(posed.objects[1].changed);
}

TEST(MotionClass, RigidAndStaticObjectsPoseWithoutTheirVertices) {
    const Scene scene = classes_scene();
    PoseSettings settings;
    settings.skip_fixed_positions = true;
    const ScenePoser skipping(scene, settings);
    const ScenePoser full(scene, {});
    PosedScene skipped, all;
    for (const int frame : {0, 7, 30}) {
        skipping.pose(frame, skipped);
        full.pose(frame, all);
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            SCOPED_TRACE(scene.objects[i].name + " frame " + std::to_string(frame));
            const bool fixed = full.motion_class(i) <= MotionClass::rigid;
            EXPECT_EQ(skipped.objects[i].positions.empty(), fixed);
            EXPECT_EQ(skipped.objects[i].transform, all.objects[i].transform);
            EXPECT_EQ(full.object_space_positions(i).empty(), !fixed);
            if (!fixed) {
                std::vector<glm::vec3> world;
                EXPECT_THROW(skipping.fixed_world_positions(i, skipped, world), std::invalid_argument);
                continue;
            }
            // What a skipping caller computes on demand is exactly what pose() would have.
            std::vector<glm::vec3> world;
            skipping.fixed_world_positions(i, skipped, world);
            EXPECT_EQ(world, all.objects[i].positions);
            const std::span<const glm::vec3> local = full.object_space_positions(i);
            for (std::size_t v = 0; v < local.size(); ++v) {
                const glm::dvec4 p = all.objects[i].transform * glm::dvec4(glm::dvec3(local[v]), 1.0);
                EXPECT_EQ(all.objects[i].positions[v], glm::vec3(glm::dvec3(p) / p.w)) << v;
            }
        }
    }
    // The skinned static object's object space is its skinned pose in world space (its joints
    // sit at the origin and never move; vertex 1 is half on each, with identity bind matrices).
    EXPECT_EQ(full.object_space_positions(4)[1], glm::vec3(1, 0, 0));
    // The frozen object's object space is its shape under the clip-held weight 0.5.
    EXPECT_EQ(full.object_space_positions(7)[2], glm::vec3(0, 1, 0.5f));
    // A plain static object uses its mesh as it is.
    EXPECT_EQ(full.object_space_positions(0).data(), scene.objects[0].mesh.positions.data());
}

TEST(MotionClass, SettingsAreChecked) {
    const Scene scene = classes_scene();
    PoseSettings settings;
    settings.fps = 0.0;
    EXPECT_THROW(ScenePoser(scene, settings), std::invalid_argument);
    settings.fps = std::nan("");
    EXPECT_THROW(ScenePoser(scene, settings), std::invalid_argument);
    settings.fps = 30.0;
    const ScenePoser poser(scene, settings);
    EXPECT_DOUBLE_EQ(poser.time_of(45), 1.5);
    PosedScene posed;
    poser.pose(45, posed);
    EXPECT_EQ(posed.time_s, 1.5);
    EXPECT_EQ(posed.frame, 45);

    // A hand-built scene with inconsistent animation data is refused, not read out of range.
    Scene broken = scene;
    broken.objects[1].node = 99;
    EXPECT_THROW(ScenePoser(broken, {}), SceneError);
    broken = scene;
    broken.clips[0].samplers[0].times = {1.0, 0.5};
    EXPECT_THROW(ScenePoser(broken, {}), SceneError);
}

}  // namespace
}  // namespace dynrt::anim
