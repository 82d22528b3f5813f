#include "dynrt/engine/renderer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/packet/packet_shading.h"
#include "frame_tracer.h"
#include "update/scene_accel.h"
#include "dynrt/engine/stopwatch.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

namespace dynrt {

struct Renderer::State {
    /// The scene the trees belong to, its poser (one per sequence: it precomputes what never
    /// changes) and the lights the frames use.
    const Scene* scene = nullptr;
    std::optional<anim::ScenePoser> poser;
    std::vector<PointLight> lights;
    anim::PosedScene posed;
    SceneAccel accel;
    /// The last update's figures, and its wall time (part of the frame's total).
    FrameStats update_stats;
    double update_wall_ms = 0.0;
    bool updated = false;
    /// The scene's materials as the shading kernel reads them and each object's material
    /// index, refreshed per trace (kept to avoid reallocating), and the trace's own buffers.
    std::vector<packet::PhongMaterial> materials;
    std::vector<std::int32_t> object_material;
    TraceScratch scratch;
};

namespace {

bvh::Aabb bounds_of(const anim::PosedScene& posed) {
    bvh::Aabb bounds;
    for (const anim::PosedObject& object : posed.objects) {
        for (const glm::vec3& p : object.positions) bounds.extend(p);
    }
    return bounds;
}

}  // namespace

PointLight default_light(const bvh::Aabb& bounds) {
    const auto [c, r] = framing_of(bounds);
    return PointLight{c + 4.0f * r * glm::normalize(glm::vec3(-0.5f, 1.0f, 0.8f)), 1.0f};
}

bvh::Aabb scene_bounds(const Scene& scene) { return sequence_bounds(scene, {}, 0, 0); }

bvh::Aabb sequence_bounds(const Scene& scene, const anim::PoseSettings& pose, int first, int last,
                          int samples) {
    anim::PoseSettings settings = pose;
    settings.skip_fixed_positions = false;
    const anim::ScenePoser poser(scene, settings);
    const bool moves = !scene.clips.empty() || !scene.motions.empty();
    const int count = moves && last > first ? std::max(2, std::min(samples, last - first + 1)) : 1;
    anim::PosedScene posed;
    bvh::Aabb bounds;
    for (int i = 0; i < count; ++i) {
        // Evenly spread, in 64 bits: (last - first) * i can pass INT_MAX.
        const int frame =
            count == 1 ? first : first + int(std::int64_t(last - first) * i / (count - 1));
        poser.pose(frame, posed);
        bounds.extend(bounds_of(posed));
    }
    return bounds;
}

std::vector<PointLight> effective_lights(const Scene& scene, const RenderOptions& options) {
    if (!options.lights.empty()) return options.lights;
    if (!scene.lights.empty()) return scene.lights;
    return {default_light(scene_bounds(scene))};
}

Renderer::Renderer(RenderOptions options)
    : options_(std::move(options)), state_(std::make_unique<State>()) {
    const float tol = options_.adaptive_tolerance;
    if (!std::isfinite(tol) || tol < 0.0f) {
        throw std::invalid_argument("adaptive tolerance " + std::to_string(tol) +
                                    ": must be finite and >= 0 (0: exact)");
    }
    if (tol > 0.0f && options_.tracer != Tracer::packet) {
        throw std::invalid_argument("adaptive sampling traces 16x16 packets: it needs the packet "
                                    "tracer, not the single-ray one");
    }
}

Renderer::~Renderer() = default;

void Renderer::reset() {
    State& s = *state_;
    s.accel.clear();
    s.poser.reset();
    s.scene = nullptr;
    s.updated = false;
}

const anim::PosedScene& Renderer::posed() const {
    if (!state_->updated) throw std::logic_error("Renderer::posed before any update");
    return state_->posed;
}

void Renderer::render(const Scene& scene, const Camera& camera, int frame, RenderedFrame& out) {
    update(scene, frame);
    trace(camera, out);
}

void Renderer::update(const Scene& scene, int frame) {
    State& s = *state_;
    if (s.scene != &scene || !s.poser) {
        // A new scene: a poser for it (settings checked here), set up once per sequence.
        reset();
        anim::PoseSettings settings = options_.pose;
        settings.skip_fixed_positions = true;
        s.poser.emplace(scene, std::move(settings));
        s.lights.clear();
        s.scene = &scene;
    }
    s.updated = false;
    const Stopwatch update_clock;
    FrameStats& stats = s.update_stats;
    stats = FrameStats{};
    stats.frame = frame;

    // ---- Update: evaluate the animation, then bring every object's tree to this frame ----
    s.poser->pose(frame, s.posed);
    UpdatePolicy policy;
    policy.build = options_.build;
    policy.exploding_cost_ratio = options_.cost_ratio_exploding;
    policy.rebuild_threshold = options_.rebuild_threshold;
    s.accel.update(scene, *s.poser, s.posed, policy, stats);
    s.update_wall_ms = update_clock.elapsed_ms();
    // Everything the update did besides building trees (posing, gathering triangles), so that
    // the stages shown add up to total_ms.
    stats.update_ms = std::max(0.0, s.update_wall_ms - stats.build_ms);
    // The lights, once per sequence and untimed. After the update, so that bad geometry is
    // reported at the frame asked for (the default light is placed from frame 0's bounds).
    if (s.lights.empty()) s.lights = effective_lights(scene, options_);
    s.updated = true;
}

void Renderer::trace(const Camera& camera, RenderedFrame& out) {
    State& s = *state_;
    if (!s.updated) throw std::logic_error("Renderer::trace before any update");
    const Stopwatch trace_clock;
    const Scene& scene = *s.scene;
    // The shading kernel's view of the materials (bookkeeping, outside the stage clocks).
    s.materials.clear();
    for (const Material& m : scene.materials) {
        s.materials.push_back(packet::PhongMaterial{m.diffuse, m.specular, m.shininess});
    }
    s.object_material.clear();
    for (const Object& object : scene.objects) {
        s.object_material.push_back(std::int32_t(object.material));
    }
    out.stats = s.update_stats;
    trace_frame(TraceInputs{s.accel, s.materials, s.object_material, s.lights}, camera, options_,
                s.scratch, out);
    out.stats.total_ms = s.update_wall_ms + trace_clock.elapsed_ms();
}

}  // namespace dynrt
