#include "animation_data_check.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/scene/scene_error.h"

#include <cmath>
#include <numbers>
#include <string>

namespace dynrt::anim {

namespace {

class Checker {
public:
    explicit Checker(const Scene& scene) : scene_(scene) {}

    void check() const {
        for (std::size_t i = 0; i < scene_.nodes.size(); ++i) {
            const std::int32_t parent = scene_.nodes[i].parent;
            if (parent < -1 || parent >= static_cast<std::int64_t>(i)) {
                fail("node '" + scene_.nodes[i].name + "': parent " + std::to_string(parent) +
                     " does not come before it");
            }
        }
        for (const Skin& skin : scene_.skins) check_skin(skin);
        for (const Object& object : scene_.objects) check_object(object);
        for (const AnimationClip& clip : scene_.clips) check_clip(clip);
        for (const SceneCamera& camera : scene_.cameras) {
            if (camera.node >= scene_.nodes.size()) fail("camera '" + camera.name + "': node out of range");
            if (!(camera.yfov_rad > 0.0 && camera.yfov_rad < std::numbers::pi)) {
                fail("camera '" + camera.name + "': yfov is not in (0, pi)");
            }
        }
        for (const ProceduralMotion& motion : scene_.motions) {
            if (motion.object >= scene_.objects.size()) fail("procedural motion names a missing object");
            if (motion.kind == MotionKind::explode && !has_unshared_triangles(scene_.objects[motion.object])) {
                fail("object '" + scene_.objects[motion.object].name +
                     "': explodes but its triangles share vertices (use add_procedural_motions)");
            }
        }
    }

private:
    [[noreturn]] void fail(const std::string& what) const { throw SceneError(scene_.source + ": " + what); }

    void check_skin(const Skin& skin) const {
        const std::string name = "skin '" + skin.name + "': ";
        if (skin.joints.empty()) fail(name + "has no joints");
        if (skin.inverse_bind_matrices.size() != skin.joints.size()) {
            fail(name + "needs one inverse bind matrix per joint");
        }
        for (const std::uint32_t joint : skin.joints) {
            if (joint >= scene_.nodes.size()) fail(name + "joint node " + std::to_string(joint) + " out of range");
        }
    }

    void check_object(const Object& object) const {
        const std::string name = "object '" + object.name + "': ";
        const std::size_t vertices = object.mesh.positions.size();
        if (object.node < -1 || object.node >= static_cast<std::int64_t>(scene_.nodes.size())) {
            fail(name + "node " + std::to_string(object.node) + " out of range");
        }
        if (object.skin) {
            const SkinWeights& weights = *object.skin;
            if (weights.skin >= scene_.skins.size()) fail(name + "skin out of range");
            if (weights.influences != 4 && weights.influences != 8) fail(name + "influences must be 4 or 8");
            if (weights.joints.size() != vertices * weights.influences ||
                weights.weights.size() != vertices * weights.influences) {
                fail(name + "skin influences do not match the vertex count");
            }
            const std::size_t joints = scene_.skins[weights.skin].joints.size();
            for (const std::uint16_t joint : weights.joints) {
                if (joint >= joints) fail(name + "joint index " + std::to_string(joint) + " out of range");
            }
        }
        if (!object.mesh.texcoords.empty() && object.mesh.texcoords.size() != vertices) {
            fail(name + "has " + std::to_string(object.mesh.texcoords.size()) + " texture coordinates for " +
                 std::to_string(vertices) + " vertices");
        }
        if (!object.mesh.normals.empty() && object.mesh.normals.size() != vertices) {
            fail(name + "has " + std::to_string(object.mesh.normals.size()) + " normals for " +
                 std::to_string(vertices) + " vertices");
        }
        if (object.morph) {
            const MorphTargets& morph = *object.morph;
            bool sizes_match = morph.base_positions.size() == vertices &&
                               morph.default_weights.size() == morph.position_deltas.size();
            for (const std::vector<glm::vec3>& deltas : morph.position_deltas) {
                sizes_match = sizes_match && deltas.size() == vertices;
            }
            if (!morph.normal_deltas.empty()) {
                sizes_match = sizes_match && morph.base_normals.size() == vertices &&
                              object.mesh.normals.size() == vertices &&
                              morph.normal_deltas.size() == morph.position_deltas.size();
                for (const std::vector<glm::vec3>& deltas : morph.normal_deltas) {
                    sizes_match = sizes_match && deltas.size() == vertices;
                }
            }
            if (!sizes_match) fail(name + "morph target sizes do not match");
        }
    }

    void check_clip(const AnimationClip& clip) const {
        for (std::size_t s = 0; s < clip.samplers.size(); ++s) {
            const AnimationSampler& sampler = clip.samplers[s];
            const std::string name = "animation '" + clip.name + "' sampler " + std::to_string(s) + ": ";
            if (sampler.times.empty()) fail(name + "has no keys");
            for (std::size_t k = 0; k < sampler.times.size(); ++k) {
                if (!std::isfinite(sampler.times[k]) || (k > 0 && !(sampler.times[k] > sampler.times[k - 1]))) {
                    fail(name + "key times are not finite and strictly increasing");
                }
            }
            const bool three_per_key = sampler.interpolation == Interpolation::cubic_spline ||
                                       sampler.interpolation == Interpolation::squad;
            const std::size_t per_key = three_per_key ? 3 : 1;
            if (sampler.components == 0 ||
                sampler.values.size() != sampler.times.size() * per_key * sampler.components) {
                fail(name + "value count does not match its keys");
            }
        }
        for (std::size_t c = 0; c < clip.channels.size(); ++c) {
            const AnimationChannel& channel = clip.channels[c];
            const std::string name = "animation '" + clip.name + "' channel " + std::to_string(c) + ": ";
            if (channel.node >= scene_.nodes.size()) fail(name + "node out of range");
            if (channel.sampler >= clip.samplers.size()) fail(name + "sampler out of range");
            if (channel.property != AnimatedProperty::rotation &&
                clip.samplers[channel.sampler].interpolation == Interpolation::squad) {
                fail(name + "squad interpolation is for rotations only");
            }
            const std::uint32_t components = clip.samplers[channel.sampler].components;
            if (channel.property == AnimatedProperty::weights) {
                check_weights_channel(channel, components, name);
                continue;
            }
            if (scene_.nodes[channel.node].matrix) fail(name + "animates a node given by a matrix");
            const std::uint32_t expected = channel.property == AnimatedProperty::rotation ? 4 : 3;
            if (components != expected) fail(name + "value size does not match the property");
        }
    }

    void check_weights_channel(const AnimationChannel& channel, std::uint32_t components,
                               const std::string& name) const {
        for (const Object& object : scene_.objects) {
            if (object.node == static_cast<std::int64_t>(channel.node) && object.morph &&
                object.morph->position_deltas.size() != components) {
                fail(name + "has " + std::to_string(components) + " weights, object '" + object.name +
                     "' has " + std::to_string(object.morph->position_deltas.size()) + " morph targets");
            }
        }
    }

    const Scene& scene_;
};

}  // namespace

void check_animation_data(const Scene& scene) { Checker(scene).check(); }

}  // namespace dynrt::anim
