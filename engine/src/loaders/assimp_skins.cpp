// assimp bones -> scene model skins. assimp's offset matrix is glTF's inverse bind matrix
// (mesh space to the bone's space in the bind pose), so a posed vertex is
// sum_k w_k * world(bone_k) * offset_k * p, the mesh node's own transform not applied: the
// formula of dynrt/scene/skin.h. assimp's own post-processing step LimitBoneWeights is not
// used (it keeps 4); the 8 largest are kept here, as glTF's JOINTS_0/JOINTS_1 allow, scaled
// to the sum of all of them.

#include "assimp_skins.h"

#include "message_text.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace dynrt {

namespace {

constexpr std::size_t kMaxInfluences = 8;

struct Influence {
    std::uint16_t joint = 0;
    float weight = 0.0f;
};

bool is_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

}  // namespace

SkinWeights read_assimp_skin(const aiMesh& mesh, const std::string& object, std::int32_t mesh_node,
                             const AssimpNodeNames& nodes, std::vector<Skin>& skins,
                             std::size_t& vertices_truncated) {
    Skin skin;
    skin.name = cat(object, " skin");
    const std::size_t vertex_count = mesh.mNumVertices;
    std::vector<std::vector<Influence>> influences(vertex_count);
    // One joint per bone, plus the mesh's node when some vertex needs it; at most 65535.
    if (mesh.mNumBones >= 0xffffu) throw AssimpDataError(cat("has ", mesh.mNumBones, " bones (at most 65534)"));
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
        const aiBone& bone = *mesh.mBones[b];
        const std::string bone_name = to_string(bone.mName);
        const auto fail = [&](const std::string& what) { throw AssimpDataError(cat("bone '", bone_name, "': ", what)); };
        const auto node = nodes.find(bone_name);
        if (node == nodes.end()) fail("names no node of the scene");
        const auto joint = static_cast<std::uint32_t>(node->second);
        if (std::find(skin.joints.begin(), skin.joints.end(), joint) != skin.joints.end()) {
            fail("its node is another bone's too");
        }
        const glm::dmat4 offset = to_dmat4(bone.mOffsetMatrix);
        if (!is_finite(offset)) fail("offset matrix is not finite");
        skin.joints.push_back(joint);
        skin.inverse_bind_matrices.push_back(offset);
        for (unsigned w = 0; w < bone.mNumWeights; ++w) {
            const aiVertexWeight& weight = bone.mWeights[w];
            if (weight.mVertexId >= vertex_count) {
                fail(cat("weight ", w, " names vertex ", weight.mVertexId, " (", vertex_count, " vertices)"));
            }
            if (!std::isfinite(weight.mWeight) || weight.mWeight < 0.0f) {
                fail(cat("weight ", w, " of vertex ", weight.mVertexId, " is ", weight.mWeight,
                         " (must be finite and not negative)"));
            }
            if (weight.mWeight > 0.0f) influences[weight.mVertexId].push_back({std::uint16_t(b), weight.mWeight});
        }
    }

    // Vertices no bone moves stay with the mesh's node.
    std::uint16_t own_node_joint = 0;
    bool own_node_added = false;
    std::size_t most = 0;
    vertices_truncated = 0;
    for (std::vector<Influence>& list : influences) {
        if (list.empty()) {
            if (!own_node_added) {
                own_node_joint = std::uint16_t(skin.joints.size());
                skin.joints.push_back(static_cast<std::uint32_t>(mesh_node));
                skin.inverse_bind_matrices.push_back(glm::dmat4(1.0));
                own_node_added = true;
            }
            list.push_back({own_node_joint, 1.0f});
        }
        if (list.size() > kMaxInfluences) {
            std::partial_sort(list.begin(), list.begin() + kMaxInfluences, list.end(),
                              [](const Influence& a, const Influence& b) { return a.weight > b.weight; });
            // The kept weights sum to what all of them did, as assimp's LimitBoneWeights does.
            float all = 0.0f, kept = 0.0f;
            for (std::size_t k = 0; k < list.size(); ++k) (k < kMaxInfluences ? kept : all) += list[k].weight;
            all += kept;
            list.resize(kMaxInfluences);
            for (Influence& influence : list) influence.weight *= all / kept;
            ++vertices_truncated;
        }
        most = std::max(most, list.size());
    }
    if (own_node_added && std::count(skin.joints.begin(), skin.joints.end(), skin.joints.back()) > 1) {
        // The mesh's node is also a bone: its influence is the bone's, with the bone's offset.
        throw AssimpDataError(cat("some vertices have no bone weights and the mesh's own node is a bone"));
    }

    SkinWeights weights;
    weights.skin = static_cast<std::uint32_t>(skins.size());
    weights.influences = most <= 4 ? 4 : 8;
    weights.joints.assign(vertex_count * weights.influences, 0);
    weights.weights.assign(vertex_count * weights.influences, 0.0f);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        for (std::size_t k = 0; k < influences[v].size(); ++k) {
            weights.joints[v * weights.influences + k] = influences[v][k].joint;
            weights.weights[v * weights.influences + k] = influences[v][k].weight;
        }
    }
    skins.push_back(std::move(skin));
    return weights;
}

}  // namespace dynrt
