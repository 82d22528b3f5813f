// aiAnimation -> AnimationClip. assimp 5.2.5 keys carry no interpolation mode: its readers
// resample or keep keys so that linear interpolation (slerp for quaternions) between them is
// the animation, which is the scene model's Interpolation::linear.

#include "assimp_animations.h"

#include "message_text.h"

#include <cmath>

namespace dynrt {

namespace {

/// One sampler from `count` keys, `components` numbers each, read by `value_of(key, out)`.
template <class Key, class ValueOf>
AnimationSampler sampler_of(const Key* keys, unsigned count, std::uint32_t components, double ticks_per_second,
                            const char* what, ValueOf value_of) {
    AnimationSampler sampler;
    sampler.interpolation = Interpolation::linear;
    sampler.components = components;
    for (unsigned k = 0; k < count; ++k) {
        const double time = keys[k].mTime / ticks_per_second;
        if (!std::isfinite(time)) throw AssimpDataError(cat(what, " key ", k, ": time ", keys[k].mTime, " is not finite"));
        if (!sampler.times.empty() && !(time > sampler.times.back())) {
            throw AssimpDataError(cat(what, " key ", k, ": time ", keys[k].mTime, " ticks is not after key ", k - 1,
                                      "'s ", keys[k - 1].mTime));
        }
        sampler.times.push_back(time);
        const std::size_t first = sampler.values.size();
        sampler.values.resize(first + components);
        value_of(keys[k], &sampler.values[first]);
        for (std::uint32_t c = 0; c < components; ++c) {
            if (!std::isfinite(sampler.values[first + c])) {
                throw AssimpDataError(cat(what, " key ", k, ": value is not finite"));
            }
        }
    }
    return sampler;
}

void add_channel(AnimationClip& clip, std::uint32_t node, AnimatedProperty property, AnimationSampler sampler) {
    clip.channels.push_back({node, property, static_cast<std::uint32_t>(clip.samplers.size())});
    clip.samplers.push_back(std::move(sampler));
}

}  // namespace

std::vector<AnimationClip> read_assimp_animations(const aiScene& scene, const AssimpNodeNames& nodes,
                                                  std::vector<Warning>& warnings) {
    std::vector<AnimationClip> clips;
    for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
        const aiAnimation& animation = *scene.mAnimations[a];
        AnimationClip clip;
        clip.name = animation.mName.length > 0 ? to_string(animation.mName) : cat("animation", a);
        const double tps = animation.mTicksPerSecond > 0.0 && std::isfinite(animation.mTicksPerSecond)
                               ? animation.mTicksPerSecond
                               : kAssimpDefaultTicksPerSecond;
        for (unsigned c = 0; c < animation.mNumChannels; ++c) {
            const aiNodeAnim& channel = *animation.mChannels[c];
            const std::string node_name = to_string(channel.mNodeName);
            const std::string where = cat("animation '", clip.name, "' channel ", c, " (node '", node_name, "'): ");
            const auto node = nodes.find(node_name);
            if (node == nodes.end()) throw AssimpDataError(cat(where, "names no node of the scene"));
            const auto target = static_cast<std::uint32_t>(node->second);
            try {
                if (channel.mNumPositionKeys > 0) {
                    add_channel(clip, target, AnimatedProperty::translation,
                                sampler_of(channel.mPositionKeys, channel.mNumPositionKeys, 3, tps, "position",
                                           [](const aiVectorKey& key, double* out) {
                                               out[0] = key.mValue.x, out[1] = key.mValue.y, out[2] = key.mValue.z;
                                           }));
                }
                if (channel.mNumRotationKeys > 0) {
                    add_channel(clip, target, AnimatedProperty::rotation,
                                sampler_of(channel.mRotationKeys, channel.mNumRotationKeys, 4, tps, "rotation",
                                           [](const aiQuatKey& key, double* out) {
                                               // glTF's order (x, y, z, w), normalised.
                                               const aiQuaternion& q = key.mValue;
                                               const double n = std::sqrt(double(q.x) * q.x + double(q.y) * q.y +
                                                                          double(q.z) * q.z + double(q.w) * q.w);
                                               if (!(n > 0.0)) throw AssimpDataError("rotation key is zero");
                                               out[0] = q.x / n, out[1] = q.y / n, out[2] = q.z / n, out[3] = q.w / n;
                                           }));
                }
                if (channel.mNumScalingKeys > 0) {
                    add_channel(clip, target, AnimatedProperty::scale,
                                sampler_of(channel.mScalingKeys, channel.mNumScalingKeys, 3, tps, "scaling",
                                           [](const aiVectorKey& key, double* out) {
                                               out[0] = key.mValue.x, out[1] = key.mValue.y, out[2] = key.mValue.z;
                                           }));
                }
            } catch (const AssimpDataError& e) {
                throw AssimpDataError(cat(where, e.what()));
            }
        }
        const unsigned left_out = animation.mNumMeshChannels + animation.mNumMorphMeshChannels;
        if (left_out > 0) {
            warnings.push_back({.kind = "mesh or morph animation channels left out",
                                .item = cat("animation '", clip.name, "' (", left_out, ")"),
                                .effect = "only node animation is read"});
        }
        clips.push_back(std::move(clip));
    }
    return clips;
}

std::vector<std::string> assimp_animated_nodes(const aiScene& scene) {
    std::vector<std::string> names;
    for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
        for (unsigned c = 0; c < scene.mAnimations[a]->mNumChannels; ++c) {
            names.push_back(to_string(scene.mAnimations[a]->mChannels[c]->mNodeName));
        }
    }
    return names;
}

}  // namespace dynrt
