// Which clips play by default (anim::default_clips) and looping clips (PoseSettings::loop), on
// scenes built in code: one node moved by linear translation keys.

#include "dynrt/anim/clip_selection.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/scene/scene.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

namespace dynrt::anim {
namespace {

/// A clip named `name` moving node `node`'s `property` from 0 to `to` (on x) over [0, end] s.
AnimationClip clip_on(const std::string& name, std::uint32_t node, AnimatedProperty property,
                      double end = 2.0, double to = 4.0) {
    AnimationClip clip;
    clip.name = name;
    const bool scale = property == AnimatedProperty::scale;
    clip.samplers.push_back(AnimationSampler{Interpolation::linear, {0.0, end}, 3,
                                             {scale ? 1.0 : 0.0, scale ? 1.0 : 0.0, scale ? 1.0 : 0.0,
                                              to, scale ? 1.0 : 0.0, scale ? 1.0 : 0.0}});
    clip.channels.push_back(AnimationChannel{node, property, 0});
    return clip;
}

Scene scene_with_nodes(int count) {
    Scene scene;
    scene.source = "clips.test";
    for (int i = 0; i < count; ++i) scene.nodes.emplace_back().name = "node" + std::to_string(i);
    return scene;
}

TEST(DefaultClips, AllPlayWhenTheyDriveDifferentNodesOrProperties) {
    Scene scene = scene_with_nodes(2);
    EXPECT_TRUE(default_clips(scene).empty());
    scene.clips.push_back(clip_on("a", 0, AnimatedProperty::translation));
    scene.clips.push_back(clip_on("b", 1, AnimatedProperty::translation));
    scene.clips.push_back(clip_on("c", 0, AnimatedProperty::scale));
    EXPECT_EQ(default_clips(scene), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(DefaultClips, OnlyTheFirstPlaysWhenTwoDriveTheSameProperty) {
    Scene scene = scene_with_nodes(2);
    scene.clips.push_back(clip_on("Survey", 0, AnimatedProperty::translation));
    scene.clips.push_back(clip_on("Walk", 1, AnimatedProperty::translation));
    scene.clips.push_back(clip_on("Run", 1, AnimatedProperty::translation));
    EXPECT_EQ(default_clips(scene), (std::vector<std::size_t>{0}));
}

double node_x(const ScenePoser& poser, int frame) {
    PosedScene posed;
    poser.pose(frame, posed);
    return posed.node_world[0][3][0];
}

TEST(LoopingClips, RepeatFromTheStartInsteadOfHoldingTheLastPose) {
    Scene scene = scene_with_nodes(1);
    scene.clips.push_back(clip_on("move", 0, AnimatedProperty::translation, 2.0, 4.0));
    PoseSettings held;
    held.fps = 4.0;  // frame 8 is the last key (t = 2 s)
    PoseSettings looped = held;
    looped.loop = true;
    const ScenePoser hold(scene, held), loop(scene, looped);
    EXPECT_EQ(hold.end_time(), 2.0);
    for (int frame = 0; frame < 8; ++frame) {
        EXPECT_EQ(node_x(loop, frame), node_x(hold, frame)) << frame;
    }
    EXPECT_EQ(node_x(hold, 12), 4.0);  // held at the last key
    EXPECT_EQ(node_x(loop, 12), 2.0);  // t = 3 s plays t = 1 s again
    for (int frame = 0; frame < 8; ++frame) {
        EXPECT_EQ(node_x(loop, frame + 8), node_x(loop, frame)) << frame;
        EXPECT_EQ(node_x(loop, frame + 80), node_x(loop, frame)) << frame;
    }
}

}  // namespace
}  // namespace dynrt::anim
