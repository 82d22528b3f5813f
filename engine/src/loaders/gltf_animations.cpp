// glTF 2.0 section 3.11 "Animations": channels (target node and path) and samplers (key times,
// values, interpolation), each validated before the scene model holds it.

#include "gltf_animations.h"

#include "gltf_accessors.h"
#include "gltf_data_error.h"
#include "gltf_morph_targets.h"
#include "gltf_names.h"
#include "gltf_node_tree.h"
#include "message_text.h"

#include <cmath>
#include <optional>

namespace dynrt {

namespace {

std::optional<AnimatedProperty> parse_path(const std::string& path) {
    if (path == "translation") return AnimatedProperty::translation;
    if (path == "rotation") return AnimatedProperty::rotation;
    if (path == "scale") return AnimatedProperty::scale;
    if (path == "weights") return AnimatedProperty::weights;
    return std::nullopt;
}

std::optional<Interpolation> parse_interpolation(const std::string& name) {
    if (name == "STEP") return Interpolation::step;
    if (name == "LINEAR" || name.empty()) return Interpolation::linear;
    if (name == "CUBICSPLINE") return Interpolation::cubic_spline;
    return std::nullopt;
}

/// Converts the samplers and channels of one animation.
class ClipReader {
public:
    ClipReader(const tinygltf::Model& model, std::span<const int> scene_node_of, std::size_t index,
               std::vector<Warning>& warnings)
        : model_(model),
          scene_node_of_(scene_node_of),
          source_(model.animations[index]),
          warnings_(warnings),
          converted_(source_.samplers.size(), -1) {
        clip_.name = gltf_element_name(model.animations, static_cast<int>(index), "animation");
    }

    AnimationClip read() {
        for (std::size_t c = 0; c < source_.channels.size(); ++c) read_channel(c);
        return std::move(clip_);
    }

private:
    void read_channel(std::size_t c) {
        const tinygltf::AnimationChannel& channel = source_.channels[c];
        const auto fail = [&](const std::string& what) {
            throw GltfDataError(cat("animation '", clip_.name, "' channel ", c, ": ", what));
        };
        if (channel.target_node < 0) return;  // glTF 2.0: an extension may target something else
        if (static_cast<std::size_t>(channel.target_node) >= model_.nodes.size()) {
            fail(cat("target node ", channel.target_node, " does not exist (", model_.nodes.size(), " nodes)"));
        }
        const std::optional<AnimatedProperty> property = parse_path(channel.target_path);
        if (!property) {
            warnings_.push_back({.kind = cat("animation channel on path '", channel.target_path, "' skipped"),
                                 .kinds = cat("animation channels on path '", channel.target_path, "' skipped"),
                                 .item = cat("animation '", clip_.name, "' channel ", c),
                                 .effect = "only translation, rotation, scale and weights are played"});
            return;
        }
        if (channel.sampler < 0 || static_cast<std::size_t>(channel.sampler) >= source_.samplers.size()) {
            fail(cat("sampler ", channel.sampler, " does not exist (", source_.samplers.size(), " samplers)"));
        }
        const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(channel.target_node)];
        const std::string node_name = gltf_node_name(model_, channel.target_node);
        std::size_t components = *property == AnimatedProperty::rotation ? 4 : 3;
        if (*property == AnimatedProperty::weights) {
            if (node.mesh < 0 || static_cast<std::size_t>(node.mesh) >= model_.meshes.size()) {
                fail(cat("animates the weights of node '", node_name, "', which has no mesh"));
            }
            try {
                components = gltf_morph_target_count(model_.meshes[static_cast<std::size_t>(node.mesh)]);
            } catch (const GltfDataError& e) {
                fail(cat("node '", node_name, "': ", e.what()));
            }
            if (components == 0) fail(cat("animates the weights of node '", node_name, "', whose mesh has no morph targets"));
        } else if (!node.matrix.empty()) {
            fail(cat("animates node '", node_name, "', which has a matrix (animated nodes must use translation, rotation and scale)"));
        }
        const std::uint32_t sampler = read_sampler(channel.sampler, *property, components);
        const int scene_node = scene_node_of_[static_cast<std::size_t>(channel.target_node)];
        if (scene_node < 0) return;  // not in the default scene: moves nothing that is drawn
        clip_.channels.push_back(AnimationChannel{static_cast<std::uint32_t>(scene_node), *property, sampler});
    }

    std::uint32_t read_sampler(int index, AnimatedProperty property, std::size_t components) {
        const auto fail = [&](const std::string& what) {
            throw GltfDataError(cat("animation '", clip_.name, "' sampler ", index, ": ", what));
        };
        int& converted = converted_[static_cast<std::size_t>(index)];
        if (converted >= 0) {
            const AnimationSampler& existing = clip_.samplers[static_cast<std::size_t>(converted)];
            if (existing.components != components) {
                fail(cat("drives values of ", existing.components, " and of ", components, " numbers"));
            }
            return static_cast<std::uint32_t>(converted);
        }
        const tinygltf::AnimationSampler& source = source_.samplers[static_cast<std::size_t>(index)];
        AnimationSampler sampler;
        sampler.components = static_cast<std::uint32_t>(components);
        const std::optional<Interpolation> interpolation = parse_interpolation(source.interpolation);
        if (!interpolation) fail(cat("unknown interpolation '", source.interpolation, "'"));
        sampler.interpolation = *interpolation;

        try {
            sampler.times = read_numbers(model_, source.input, TINYGLTF_TYPE_SCALAR, NormalizedIntegers::none);
        } catch (const GltfDataError& e) {
            fail(cat("input: ", e.what()));
        }
        if (sampler.times.empty()) fail("input has no keys");
        for (std::size_t k = 1; k < sampler.times.size(); ++k) {
            if (!(sampler.times[k] > sampler.times[k - 1])) {
                fail(cat("input key ", k, " (", std::to_string(sampler.times[k]), " s) is not after key ", k - 1,
                         " (", std::to_string(sampler.times[k - 1]), " s); key times must strictly increase"));
            }
        }

        const int type = property == AnimatedProperty::weights    ? TINYGLTF_TYPE_SCALAR
                         : property == AnimatedProperty::rotation ? TINYGLTF_TYPE_VEC4
                                                                  : TINYGLTF_TYPE_VEC3;
        const NormalizedIntegers integers = property == AnimatedProperty::rotation || property == AnimatedProperty::weights
                                                ? NormalizedIntegers::any
                                                : NormalizedIntegers::none;
        try {
            sampler.values = read_numbers(model_, source.output, type, integers);
        } catch (const GltfDataError& e) {
            fail(cat("output: ", e.what()));
        }
        const bool cubic = sampler.interpolation == Interpolation::cubic_spline;
        const std::size_t per_key = (cubic ? 3 : 1) * components;
        if (sampler.values.size() != sampler.times.size() * per_key) {
            fail(cat("output has ", sampler.values.size(), " numbers, expected ", sampler.times.size() * per_key, " (",
                     sampler.times.size(), " keys x ", cubic ? "3 (in-tangent, value, out-tangent) x " : "",
                     components, ")"));
        }
        if (property == AnimatedProperty::rotation) check_rotations(sampler, fail);
        converted = static_cast<int>(clip_.samplers.size());
        clip_.samplers.push_back(std::move(sampler));
        return static_cast<std::uint32_t>(converted);
    }

    template <class Fail>
    static void check_rotations(AnimationSampler& sampler, const Fail& fail) {
        const bool cubic = sampler.interpolation == Interpolation::cubic_spline;
        for (std::size_t k = 0; k < sampler.times.size(); ++k) {
            double* q = sampler.values.data() + (cubic ? 3 * k + 1 : k) * 4;
            const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
            if (!(length > 0.0)) fail(cat("output key ", k, ": rotation quaternion has zero length"));
            // Slerp expects unit quaternions; files round them. Cubic values stay as they are:
            // their tangents are relative to them, and the result is normalised anyway.
            if (!cubic) {
                for (int c = 0; c < 4; ++c) q[c] /= length;
            }
        }
    }

    const tinygltf::Model& model_;
    std::span<const int> scene_node_of_;
    const tinygltf::Animation& source_;
    std::vector<Warning>& warnings_;
    /// Clip sampler index of each glTF sampler, -1 until used.
    std::vector<int> converted_;
    AnimationClip clip_;
};

}  // namespace

std::vector<AnimationClip> read_animations(const tinygltf::Model& model, std::span<const int> scene_node_of,
                                           std::vector<Warning>& warnings) {
    std::vector<AnimationClip> clips;
    for (std::size_t a = 0; a < model.animations.size(); ++a) {
        clips.push_back(ClipReader(model, scene_node_of, a, warnings).read());
    }
    return clips;
}

}  // namespace dynrt
