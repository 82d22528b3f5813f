#pragma once
// A small scene whose objects move in every way the planner tells apart, over a floor: one
// sphere moves rigidly, one deforms (wave), a soup explodes. Tests of what must not change
// when things move (exact reuse, the occluder cache) render it.

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene.h"

#include <string>
#include <vector>

namespace dynrt::test {

inline const std::string kPlane = "plane:8@0,-1,0,4#808080";
inline const std::string kRigid = "sphere:600@-0.8,-0.4,0.3,0.6#e04020";
inline const std::string kWave = "sphere:300@1.2,-0.5,-0.6,0.5#2050e0";
inline const std::string kExplode = "soup:600@-0.6,-1,-2,1.4#40c060";

inline Scene moving_scene() {
    Scene scene = load_scene(kPlane + "+" + kRigid + "+" + kWave + "+" + kExplode);
    const std::vector<std::string> motions{"rigid:" + kRigid, "wave:" + kWave, "explode:" + kExplode};
    anim::add_procedural_motions(scene, motions);
    return scene;
}

}  // namespace dynrt::test
