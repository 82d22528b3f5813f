#pragma once
// The chosen clips bound to the scene's nodes: which sampler drives each node property, and
// evaluating every node's world matrix and morph weights at a time t.

#include "dynrt/scene/scene.h"

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace dynrt::anim {

class NodeAnimation {
public:
    /// Binds the channels of scene.clips[clips[i]], earlier clips winning where two drive the
    /// same property of the same node. Borrows `scene`. Precondition: the animation data is
    /// consistent (check_animation_data) and every clip index is in range.
    NodeAnimation(const Scene& scene, std::span<const std::size_t> clips);

    /// Some translation, rotation or scale of the node or an ancestor is driven by a channel.
    bool transform_driven(std::size_t node) const { return transform_driven_[node]; }
    /// ... by a channel that changes over time.
    bool transform_varies(std::size_t node) const { return transform_varies_[node]; }
    /// The node's morph weights are driven by a channel.
    bool weights_driven(std::size_t node) const { return weights_[node].sampler != nullptr; }
    /// ... by a channel that changes over time.
    bool weights_vary(std::size_t node) const { return weights_[node].varies; }
    /// The node's weights within the buffer `evaluate` fills. Precondition: weights_driven.
    std::span<const double> weights(std::size_t node, std::span<const double> buffer) const {
        return buffer.subspan(weights_offset_[node], weights_[node].sampler->components);
    }

    /// Every node's world matrix at time t into `world`, and the driven nodes' morph weights
    /// into `weights` (both resized; storage reused).
    void evaluate(double t, std::vector<glm::dmat4>& world, std::vector<double>& weights) const;

private:
    struct Binding {
        const AnimationSampler* sampler = nullptr;
        bool varies = false;
    };

    const Scene& scene_;
    /// translation, rotation, scale bindings of each node.
    std::vector<Binding> translation_, rotation_, scale_, weights_;
    std::vector<std::size_t> weights_offset_;
    std::size_t weights_size_ = 0;
    std::vector<bool> transform_driven_, transform_varies_;
    /// World matrices of the nodes no channel reaches, computed once from the rest pose.
    std::vector<glm::dmat4> rest_world_;
};

}  // namespace dynrt::anim
