#include "dynrt/engine/renderer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/resident_memory.h"
#include "dynrt/scene/scene_bytes.h"
#include "update/held_bytes.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/engine/stopwatch.h"
#include "rendering/level_of_detail.h"
#include "rendering/posed_lights.h"
#include "rendering/frame_pipeline.h"
#include "rendering/cpu_tracer.h"
#include "rendering/secondary_rays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>
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
    /// The lights as the scene or options give them, and as the frame uses them (posed with
    /// their nodes: posed_lights.h).
    std::vector<PointLight> sequence_lights, lights;
    anim::PosedScene posed;
    /// The posed frame as the planner reads it.
    std::vector<ObjectState> states;
    /// The levels of detail (RenderOptions::lod_pixels), and the scene the frame is traced in:
    /// `scene`, or the levels' copy of it.
    LevelOfDetail lod;
    std::vector<std::size_t> lod_changed;
    const Scene* traced = nullptr;
    /// Since the pose of the frame being updated began.
    Stopwatch frame_clock;
    FramePipeline pipeline;
};

namespace {

/// Whether every coordinate is finite: one pass over the exponent bits, in parallel blocks.
bool all_finite(std::span<const glm::vec3> points) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, points.size(), 16384), true,
        [&](const tbb::blocked_range<std::size_t>& range, bool finite) {
            if (!finite) return false;
            constexpr std::uint32_t kExponent = 0x7f800000u;
            const auto all_ones = [](float x) {
                return std::uint32_t((std::bit_cast<std::uint32_t>(x) & kExponent) == kExponent);
            };
            std::uint32_t bad = 0;
            for (std::size_t v = range.begin(); v < range.end(); ++v) {
                bad |= all_ones(points[v].x) | all_ones(points[v].y) | all_ones(points[v].z);
            }
            return bad == 0;
        },
        [](bool a, bool b) { return a && b; });
}

/// Static or rigid object `object`'s world-space positions at the frame `posed` holds (posed
/// with PoseSettings::skip_fixed_positions): a span into the poser's storage or into `scratch`.
std::span<const glm::vec3> fixed_world(const anim::ScenePoser& poser, const anim::PosedScene& posed,
                                       std::size_t object, std::vector<glm::vec3>& scratch) {
    const std::vector<glm::vec3>& made = posed.objects[object].positions;
    if (!made.empty()) return made;
    // The usual static object, at the identity: transform * p in double gives every finite p
    // back (as an equal value), so its own vertices serve, uncopied. Only a non-finite vertex
    // takes the poser's path, which names it in its error.
    // (A moving object is here only without vertices: it has no object space either.)
    const std::span<const glm::vec3> local = poser.object_space_positions(object);
    if (local.empty() || (posed.objects[object].transform == glm::dmat4(1.0) && all_finite(local))) return local;
    poser.fixed_world_positions(object, posed, scratch);
    return scratch;
}

/// A posed frame's static and rigid vertices, from the poser that evaluated it.
class PoserPositions final : public FixedPositions {
public:
    PoserPositions(const anim::ScenePoser& poser, const anim::PosedScene& posed)
        : poser_(poser), posed_(posed) {}
    std::span<const glm::vec3> object_space(std::size_t object) const override {
        return poser_.object_space_positions(object);
    }
    std::span<const glm::vec3> world(std::size_t object,
                                     std::vector<glm::vec3>& scratch) const override {
        return fixed_world(poser_, posed_, object, scratch);
    }
    std::span<const glm::vec3> object_space_normals(std::size_t object) const override {
        return poser_.object_space_normals(object);
    }
    std::span<const glm::vec3> world_normals(std::size_t object,
                                             std::vector<glm::vec3>& scratch) const override {
        const std::vector<glm::vec3>& posed = posed_.objects[object].normals;
        if (!posed.empty()) return posed;
        // At the identity the cofactor matrix is the identity too: the object's own normals.
        if (posed_.objects[object].transform == glm::dmat4(1.0)) return poser_.object_space_normals(object);
        poser_.fixed_world_normals(object, posed_, scratch);
        return scratch;
    }

private:
    const anim::ScenePoser& poser_;
    const anim::PosedScene& posed_;
};

/// The box of every vertex of the frame `posed` holds (posed with skip_fixed_positions): the
/// static and rigid objects' made one object at a time, as their trees' builds make them.
/// With `changed_only`, the objects that did not change since the pose before are left out
/// (their vertices are the ones that pose's bounds held).
bvh::Aabb bounds_of(const anim::ScenePoser& poser, const anim::PosedScene& posed, bool changed_only) {
    bvh::Aabb bounds;
    std::vector<glm::vec3> scratch;
    for (std::size_t i = 0; i < posed.objects.size(); ++i) {
        if (changed_only && !posed.objects[i].changed) continue;
        for (const glm::vec3& p : fixed_world(poser, posed, i, scratch)) bounds.extend(p);
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
    // Bounds need positions only, and never a posed copy of the fixed objects' (as large as
    // the scene's own vertices: once the peak of a big static scene's start).
    settings.skip_fixed_positions = true;
    settings.normals = false;
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
        // After the first sample, only what moved: a forest with a few moving copies is not
        // bounded vertex by vertex once per sample.
        bounds.extend(bounds_of(poser, posed, i > 0));
    }
    return bounds;
}

namespace {

/// Whether `pose` plays every clip of `scene` in file order, as PoseSettings' default does.
bool plays_every_clip(const Scene& scene, const anim::PoseSettings& pose) {
    if (!pose.clips) return true;
    if (pose.clips->size() != scene.clips.size()) return false;
    for (std::size_t i = 0; i < scene.clips.size(); ++i) {
        if ((*pose.clips)[i] != i) return false;
    }
    return true;
}

/// effective_lights, with the bounds of frame 0 (the default light's) from `frame0_bounds`,
/// called only when that light is the one.
template <class Bounds>
std::vector<PointLight> lights_with_default(const Scene& scene, const RenderOptions& options,
                                            const Bounds& frame0_bounds) {
    if (!options.lights.empty()) return options.lights;
    if (!scene.lights.empty()) return scene.lights;
    if (options.environment && options.environment_lights > 0) return {};
    return {default_light(frame0_bounds())};
}

}  // namespace

std::vector<PointLight> effective_lights(const Scene& scene, const RenderOptions& options) {
    return lights_with_default(scene, options, [&] { return scene_bounds(scene); });
}

std::vector<PointLight> lights_at(std::span<const PointLight> lights, const anim::PosedScene& posed) {
    if (!detail::any_on_node(lights)) return {lights.begin(), lights.end()};
    std::vector<PointLight> out;
    detail::pose_lights(lights, posed.node_world, out);
    return out;
}

namespace {

/// The options a Renderer refuses before it starts.
void check_options(const RenderOptions& options) {
    const float tol = options.adaptive_tolerance;
    if (!std::isfinite(tol) || tol < 0.0f) {
        throw std::invalid_argument("adaptive tolerance " + std::to_string(tol) +
                                    ": must be finite and >= 0 (0: exact)");
    }
    if (tol > 0.0f && options.tracer != Tracer::packet) {
        throw std::invalid_argument("adaptive sampling traces 16x16 packets: it needs the packet "
                                    "tracer, not the single-ray one");
    }
    if (!std::isfinite(options.lod_pixels) || options.lod_pixels < 0.0f) {
        throw std::invalid_argument("level of detail " + std::to_string(options.lod_pixels) +
                                    " pixels: must be finite and >= 0 (0: off)");
    }
}

}  // namespace

Renderer::Renderer(RenderOptions options)
    : options_(std::move(options)), state_(std::make_unique<State>()) {
    check_options(options_);
    if (options_.backend) use_backend(options_.backend());
}

void Renderer::set_options(RenderOptions options) {
    check_options(options);
    options.pose = options_.pose;  // the poser was made with these
    options.backend = options_.backend;
    // Trees built from levels of detail do not match the scene's own triangles, nor the
    // reverse: switching levels of detail on or off starts the trees afresh.
    if ((options.lod_pixels > 0.0f) != (options_.lod_pixels > 0.0f)) {
        state_->pipeline.clear_trees();
        state_->lod.reset();
    }
    options_ = std::move(options);
}

Renderer::~Renderer() = default;

void Renderer::reset() {
    State& s = *state_;
    s.pipeline.clear();
    s.poser.reset();
    s.lod.reset();
    s.scene = nullptr;
    s.traced = nullptr;
}

void Renderer::forget_trees() { state_->pipeline.clear_trees(); }

void Renderer::use_backend(std::shared_ptr<FrameBackend> backend) {
    state_->pipeline.use_backend(std::move(backend));
}

TextureFigures Renderer::texture_figures() const { return state_->pipeline.texture_figures(); }

double Renderer::trace_logged_rays(const SecondaryRayLog& log,
                                   std::vector<bvh::InstanceHit>* hits) const {
    const State& s = *state_;
    if (!s.pipeline.updated()) throw std::logic_error("Renderer::trace_logged_rays before any update");
    // Where each packet's hits go in log order.
    std::vector<std::size_t> first(log.packets.size() + 1, 0);
    for (std::size_t i = 0; i < log.packets.size(); ++i) first[i + 1] = first[i] + log.packets[i].rays.size();
    if (hits) hits->assign(first.back(), bvh::InstanceHit{});
    const detail::CpuTracer tracer(s.pipeline.accel(), options_);
    const Stopwatch clock;
    tbb::parallel_for(std::size_t(0), log.packets.size(), [&](std::size_t i) {
        const SecondaryRayPacket& logged = log.packets[i];
        packet::RayPacket rays;
        rays.clear();
        std::size_t k = 0;
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            if (logged.lanes.test(lane)) rays.set_ray(lane, logged.rays[k++]);
        }
        LaneHits lane_hits;
        tracer.closest(rays, RayCoherence::scattered, lane_hits, nullptr);
        if (!hits) return;
        k = first[i];
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            if (logged.lanes.test(lane)) (*hits)[k++] = lane_hits[lane];
        }
    });
    return clock.elapsed_ms();
}

const anim::PosedScene& Renderer::posed() const {
    if (!state_->pipeline.updated()) throw std::logic_error("Renderer::posed before any update");
    return state_->posed;
}

void Renderer::render(const Scene& scene, const Camera& camera, int frame, RenderedFrame& out) {
    pose(scene, frame);
    update_trees(frame, &camera);
    trace(camera, out);
}

Camera Renderer::render(const Scene& scene, int frame, const CameraSource& view,
                        RenderedFrame& out) {
    pose(scene, frame);
    if (view.from_scene && !state_->posed.camera) {
        throw std::logic_error("Renderer::render: " + scene.source + " has no camera of its own");
    }
    const Camera camera = view.from_scene ? camera_from_scene(*state_->posed.camera) : view.camera;
    update_trees(frame, &camera);
    trace(camera, out);
    return camera;
}

void Renderer::update(const Scene& scene, int frame) {
    pose(scene, frame);
    update_trees(frame, nullptr);
}

void Renderer::pose(const Scene& scene, int frame) {
    State& s = *state_;
    if (s.scene != &scene || !s.poser) {
        // A new scene: a poser for it (settings checked here), set up once per sequence.
        reset();
        anim::PoseSettings settings = options_.pose;
        settings.skip_fixed_positions = true;
        // Flat shading needs no normals: none are posed.
        settings.normals = options_.smooth_normals;
        s.poser.emplace(scene, std::move(settings));
        s.sequence_lights.clear();
        s.lights.clear();
        s.scene = &scene;
    }
    s.frame_clock = Stopwatch{};

    // ---- Pose: evaluate the animation at the frame ----
    s.poser->pose(frame, s.posed);
    s.states.resize(s.posed.objects.size());
    for (std::size_t i = 0; i < s.states.size(); ++i) {
        const anim::PosedObject& pose = s.posed.objects[i];
        s.states[i] = ObjectState{pose.motion_class, pose.changed, pose.transform, pose.positions,
                                  pose.normals};
    }
}

void Renderer::update_trees(int frame, const Camera* camera) {
    State& s = *state_;
    const Scene& scene = *s.scene;
    // ---- Levels of detail: the triangles each object is traced with ----
    s.traced = &scene;
    if (options_.lod_pixels > 0.0f) {
        s.traced = &s.lod.choose(scene, s.states, camera, options_.height, options_.lod_pixels, s.lod_changed);
        for (const std::size_t object : s.lod_changed) s.pipeline.invalidate(object);
    }
    // ---- Plan and update the trees ----
    s.pipeline.update(*s.traced, s.states, PoserPositions(*s.poser, s.posed), options_, frame,
                      s.frame_clock);
    // The lights, once per sequence and untimed. After the update, so that bad geometry is
    // reported at the frame asked for (the default light is placed from frame 0's bounds).
    if (s.sequence_lights.empty()) {
        // Frame 0 posed with every clip is the very pose scene_bounds makes: its bounds are
        // taken from it, not from a second poser and posed copy (for a 20M-triangle exploding
        // soup, 48 bytes a triangle on top of the first build's peak).
        const bool posed_frame0 = frame == 0 && plays_every_clip(scene, options_.pose);
        s.sequence_lights = lights_with_default(scene, options_, [&] {
            return posed_frame0 ? bounds_of(*s.poser, s.posed, false) : scene_bounds(scene);
        });
        s.lights = s.sequence_lights;
    }
    if (detail::any_on_node(s.sequence_lights)) {
        detail::pose_lights(s.sequence_lights, s.posed.node_world, s.lights);
        for (std::size_t i = 0; i < s.lights.size(); ++i) {
            const PointLight& light = s.lights[i];
            const auto finite = [](const glm::vec3& v) {
                return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
            };
            if (!finite(light.position) || !finite(light.direction) || !finite(light.edge_u) || !finite(light.edge_v)) {
                const std::string name = light.name.empty() ? std::to_string(i) : "'" + light.name + "'";
                throw SceneError(scene.source + ": light " + name + ", frame " + std::to_string(frame) +
                                 ": its node's world transform is not finite or collapses its direction");
            }
        }
    }
}

void Renderer::cancel() { state_->pipeline.cancel(); }

RenderProgress Renderer::progress() const { return state_->pipeline.progress(); }

namespace {

/// `holders` (SceneAccel::memory_by_object) named and given their scene bytes, the largest
/// MemoryStats::kLargestHolders of them, largest first.
std::vector<ObjectMemory> largest_holders(const Scene& scene, std::span<const ObjectState> states,
                                          std::vector<ObjectMemory> holders) {
    std::size_t statics = 0;
    ObjectBytes static_bytes;
    for (std::size_t i = 0; i < states.size() && i < scene.objects.size(); ++i) {
        if (states[i].motion_class != anim::MotionClass::static_) continue;
        ++statics;
        static_bytes.add(scene.objects[i]);
    }
    for (ObjectMemory& h : holders) {
        if (h.object < 0) {
            h.name = "static objects (" + std::to_string(statics) + ")";
            h.scene_bytes = static_bytes.total();
        } else {
            h.name = scene.objects[std::size_t(h.object)].name;
            h.scene_bytes = object_bytes(scene.objects[std::size_t(h.object)]);
        }
    }
    const std::size_t kept = std::min(holders.size(), MemoryStats::kLargestHolders);
    std::partial_sort(holders.begin(), holders.begin() + std::ptrdiff_t(kept), holders.end(),
                      [](const ObjectMemory& a, const ObjectMemory& b) { return a.bytes() > b.bytes(); });
    holders.resize(kept);
    return holders;
}

}  // namespace

void Renderer::trace(const Camera& camera, RenderedFrame& out) {
    State& s = *state_;
    if (!s.pipeline.updated()) throw std::logic_error("Renderer::trace before any update");
    s.pipeline.trace(*s.traced, camera, options_, s.lights, out);
    // What the frame holds in memory, after its clocks (a walk over the objects' containers).
    s.pipeline.accel().memory_figures(out.stats);
    out.stats.scene_bytes = scene_bytes(*s.scene);
    std::size_t posed = held_bytes(s.posed.objects) + held_bytes(s.posed.node_world) + held_bytes(s.posed.node_weights) +
                        held_bytes(s.states);
    for (const anim::PosedObject& o : s.posed.objects) posed += held_bytes(o.positions) + held_bytes(o.normals);
    out.stats.renderer_bytes = s.pipeline.memory_bytes() + posed + s.lod.memory_bytes();
    const ResidentMemory resident = resident_memory();
    out.stats.rss_bytes = resident.current;
    out.stats.peak_rss_bytes = resident.peak;
    out.stats.largest = largest_holders(*s.scene, s.states, s.pipeline.accel().memory_by_object());
}

}  // namespace dynrt
