#pragma once
// glTF skins (glTF 2.0 section 3.7.3) into the scene model: the skins themselves, converted on
// first use, and the per-vertex joint influences of skinned primitives.

#include "dynrt/scene/skin.h"

#include <tiny_gltf.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dynrt {

class GltfSkins {
public:
    /// `scene_node_of[i]`: the Scene::nodes index of glTF node i, -1 when outside the scene.
    /// Borrows both.
    GltfSkins(const tinygltf::Model& model, std::span<const int> scene_node_of);

    /// The Scene::skins index of glTF skin `skin`, appended to `skins` on first use. Checks:
    /// the skin exists; joints are non-empty, unique, existing nodes of the default scene;
    /// inverseBindMatrices (when given) is FLOAT MAT4 with at least one finite matrix per joint.
    /// Throws GltfDataError "skin 'name': ...".
    std::uint32_t use(int skin, std::vector<Skin>& skins);

    /// The joint influences of `primitive` (JOINTS_0/WEIGHTS_0, plus JOINTS_1/WEIGHTS_1 when
    /// present: 4 or 8 per vertex) for the skin at Scene::skins[scene_skin]. Checks: both
    /// attributes of a set present, JOINTS_n UNSIGNED_BYTE/SHORT VEC4 with every index below
    /// the joint count, WEIGHTS_n FLOAT or normalized UNSIGNED_BYTE/SHORT VEC4 with finite,
    /// non-negative weights, `vertex_count` elements each, a positive weight sum per vertex.
    /// Throws GltfDataError naming the attribute and vertex.
    SkinWeights read_weights(const tinygltf::Primitive& primitive, std::uint32_t scene_skin,
                             const std::vector<Skin>& skins, std::size_t vertex_count) const;

private:
    const tinygltf::Model& model_;
    std::span<const int> scene_node_of_;
    /// Scene::skins index of each glTF skin, -1 until used.
    std::vector<int> converted_;
};

}  // namespace dynrt
