#pragma once
// assimp's node animations (aiAnimation's aiNodeAnim channels: position, rotation and scaling
// keys of one node, in ticks) as the scene model's clips, the same model glTF animations load
// into (dynrt/scene/animation_clip.h).

#include "assimp_convert.h"

#include "dynrt/scene/animation_clip.h"
#include "dynrt/scene/warnings.h"

#include <assimp/scene.h>

#include <string>
#include <vector>

namespace dynrt {

/// The ticks per second assumed when a file gives none (aiAnimation::mTicksPerSecond 0), as
/// assimp's own viewer does.
inline constexpr double kAssimpDefaultTicksPerSecond = 25.0;

/// Every animation of `scene` as a clip, in file order, named after it or "animation<i>".
/// Each node channel becomes up to three channels (translation, rotation, scale; a property
/// without keys is left alone), each with its own sampler: linear (spherical linear for
/// rotations, assimp's interpolation), times in seconds (key time / ticks per second).
/// Rotations are normalised. Mesh and morph channels are left out, with a warning in `warnings`.
/// Checks: the channel's node exists (`nodes`), key times are finite and strictly increasing,
/// values are finite, rotations are not zero. Throws AssimpDataError
/// "animation 'Walk' channel 3 (node 'arm'): ...".
std::vector<AnimationClip> read_assimp_animations(const aiScene& scene, const AssimpNodeNames& nodes,
                                                  std::vector<Warning>& warnings);

/// The names of the nodes `scene`'s animations drive (their rest transform is then kept as
/// translation, rotation and scale, which the channels replace).
std::vector<std::string> assimp_animated_nodes(const aiScene& scene);

}  // namespace dynrt
