// glTF 2.0 section 3.11: a channel replaces one property of its node's rest TRS; section 3.5.2:
// world = parent world * T * R * S.

#include "node_animation.h"

#include "dynrt/anim/animation_sampler.h"

#include <array>

namespace dynrt::anim {

NodeAnimation::NodeAnimation(const Scene& scene, std::span<const std::size_t> clips)
    : scene_(scene),
      translation_(scene.nodes.size()),
      rotation_(scene.nodes.size()),
      scale_(scene.nodes.size()),
      weights_(scene.nodes.size()),
      weights_offset_(scene.nodes.size(), 0),
      transform_driven_(scene.nodes.size(), false),
      transform_varies_(scene.nodes.size(), false),
      rest_world_(scene.nodes.size()) {
    for (const std::size_t c : clips) {
        const AnimationClip& clip = scene.clips[c];
        for (const AnimationChannel& channel : clip.channels) {
            std::vector<Binding>* slots = nullptr;
            switch (channel.property) {
                case AnimatedProperty::translation: slots = &translation_; break;
                case AnimatedProperty::rotation: slots = &rotation_; break;
                case AnimatedProperty::scale: slots = &scale_; break;
                case AnimatedProperty::weights: slots = &weights_; break;
            }
            Binding& binding = (*slots)[channel.node];
            if (binding.sampler != nullptr) continue;  // an earlier clip drives it
            binding.sampler = &clip.samplers[channel.sampler];
            binding.varies = !is_constant(*binding.sampler);
        }
    }
    for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& node = scene.nodes[i];
        const bool own_driven = translation_[i].sampler || rotation_[i].sampler || scale_[i].sampler;
        const bool own_varies = translation_[i].varies || rotation_[i].varies || scale_[i].varies;
        const bool has_parent = node.parent >= 0;
        const auto parent = static_cast<std::size_t>(node.parent);
        transform_driven_[i] = own_driven || (has_parent && transform_driven_[parent]);
        transform_varies_[i] = own_varies || (has_parent && transform_varies_[parent]);
        rest_world_[i] = has_parent ? rest_world_[parent] * node.rest_local() : node.rest_local();
        if (weights_[i].sampler != nullptr) {
            weights_offset_[i] = weights_size_;
            weights_size_ += weights_[i].sampler->components;
        }
    }
}

void NodeAnimation::evaluate(double t, std::vector<glm::dmat4>& world, std::vector<double>& weights) const {
    const std::size_t count = scene_.nodes.size();
    world.resize(count);
    weights.resize(weights_size_);
    std::array<double, 4> value{};
    for (std::size_t i = 0; i < count; ++i) {
        if (!transform_driven_[i]) {
            world[i] = rest_world_[i];
            continue;
        }
        const Node& node = scene_.nodes[i];
        glm::dmat4 local;
        if (node.matrix) {
            local = *node.matrix;
        } else {
            glm::dvec3 translation = node.translation, scale = node.scale;
            glm::dvec4 rotation = node.rotation;
            if (translation_[i].sampler) {
                sample(*translation_[i].sampler, t, false, std::span(value).first(3));
                translation = glm::dvec3(value[0], value[1], value[2]);
            }
            if (rotation_[i].sampler) {
                sample(*rotation_[i].sampler, t, true, value);
                rotation = glm::dvec4(value[0], value[1], value[2], value[3]);
            }
            if (scale_[i].sampler) {
                sample(*scale_[i].sampler, t, false, std::span(value).first(3));
                scale = glm::dvec3(value[0], value[1], value[2]);
            }
            local = trs_matrix(translation, rotation, scale);
        }
        world[i] = node.parent >= 0 ? world[static_cast<std::size_t>(node.parent)] * local : local;
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (weights_[i].sampler != nullptr) {
            sample(*weights_[i].sampler, t, false,
                   std::span(weights).subspan(weights_offset_[i], weights_[i].sampler->components));
        }
    }
}

}  // namespace dynrt::anim
