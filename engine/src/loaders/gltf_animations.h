#pragma once
// glTF animations (glTF 2.0 section 3.11) into the scene model's clips.

#include "dynrt/scene/animation_clip.h"
#include "dynrt/scene/warnings.h"

#include <tiny_gltf.h>

#include <span>
#include <string>
#include <vector>

namespace dynrt {

/// Every glTF animation as a clip, in file order, named after it or "animation<i>".
/// `scene_node_of[i]` is the Scene::nodes index of glTF node i, -1 outside the default scene:
/// channels aimed there are checked, then dropped. Channels without a target node are ignored;
/// paths other than translation, rotation, scale and weights are skipped with a line in
/// `warnings`. Checks, per channel: the sampler and node exist, the node has no matrix, a
/// weights channel's node has a mesh with morph targets. Per sampler: interpolation is STEP,
/// LINEAR or CUBICSPLINE; input is FLOAT SCALAR, finite, at least one key, strictly increasing;
/// output is FLOAT VEC3 (translation, scale), FLOAT or normalized-integer VEC4 (rotation) or
/// SCALAR (weights), finite, with keys x components values (x 3 for CUBICSPLINE: in-tangent,
/// value, out-tangent); rotation values are not zero (and are normalised for STEP and LINEAR);
/// one sampler is not shared by properties of different sizes. Throws GltfDataError
/// "animation 'Walk' channel 3: ..." or "animation 'Walk' sampler 1: ...".
std::vector<AnimationClip> read_animations(const tinygltf::Model& model, std::span<const int> scene_node_of,
                                           std::vector<Warning>& warnings);

}  // namespace dynrt
