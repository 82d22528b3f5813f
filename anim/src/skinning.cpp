#include "dynrt/anim/skinning.h"

namespace dynrt::anim {

void compute_joint_matrices(const Skin& skin, std::span<const glm::dmat4> node_world, std::vector<glm::dmat4>& out) {
    out.resize(skin.joints.size());
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
        out[j] = node_world[skin.joints[j]] * skin.inverse_bind_matrices[j];
    }
}

}  // namespace dynrt::anim
