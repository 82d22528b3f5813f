#include "rendering/frame_pipeline.h"

#include "dynrt/engine/alpha_mask.h"
#include "dynrt/engine/environment_lights.h"
#include "rendering/alpha_cutouts.h"
#include "rendering/cpu_tracer.h"
#include "rendering/pixel_cost_pass.h"
#include "rendering/same_view.h"
#include "rendering/sampled_frame.h"
#include "update/held_bytes.h"

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace dynrt {

namespace {

/// Throws std::invalid_argument naming the first light that cannot be traced: a position or
/// intensity not finite, a negative intensity, a colour not finite or negative, a sphere
/// light's radius not finite and positive, a quad light's edges not finite or parallel (no
/// area), a spot's or directional light's direction not finite or zero, a spot's cone outside
/// 0 <= inner < outer <= pi / 2, a range negative or not finite, a directional light with an
/// area (it has no position).
void check_lights(std::span<const PointLight> lights) {
    const auto finite = [](const glm::vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const PointLight& light = lights[i];
        const auto bad = [&](const std::string& why) {
            const std::string name = light.name.empty() ? std::to_string(i) : "'" + light.name + "'";
            throw std::invalid_argument("light " + name + ": " + why);
        };
        const bool directional = light.kind == PointLight::Kind::directional;
        if (!directional && !finite(light.position)) bad("its position is not finite");
        if (!(light.intensity >= 0.0f) || !std::isfinite(light.intensity)) bad("its intensity must be finite and >= 0");
        if (!finite(light.color) || !(std::min({light.color.x, light.color.y, light.color.z}) >= 0.0f)) {
            bad("its colour must be finite and >= 0");
        }
        if (light.shape == PointLight::Shape::sphere && !(light.radius > 0.0f && std::isfinite(light.radius))) {
            bad("a sphere light's radius must be finite and > 0 (a point light has none)");
        }
        if (light.shape == PointLight::Shape::quad) {
            const glm::vec3 normal = glm::cross(light.edge_u, light.edge_v);
            if (!finite(light.edge_u) || !finite(light.edge_v) || !finite(normal) || !(glm::dot(normal, normal) > 0.0f)) {
                bad("a quad light's edges must be finite and not parallel (it has no area)");
            }
        }
        if (light.kind != PointLight::Kind::point) {
            const float length = glm::length(light.direction);
            if (!finite(light.direction) || !(std::abs(length - 1.0f) < 1e-3f)) {
                bad("its direction must be a finite unit vector");
            }
        }
        if (directional && light.shape != PointLight::Shape::point) {
            bad("a directional light has no position, so no area (sphere or quad) around one");
        }
        if (light.kind == PointLight::Kind::spot &&
            !(light.inner_cone >= 0.0f && light.inner_cone < light.outer_cone && light.outer_cone <= 1.5707964f)) {
            bad("a spot's cone angles must satisfy 0 <= inner < outer <= pi/2 (radians; inner " +
                std::to_string(light.inner_cone) + ", outer " + std::to_string(light.outer_cone) + ")");
        }
        if (!(light.range >= 0.0f) || !std::isfinite(light.range)) bad("its range must be finite and >= 0 (0: none)");
    }
}

/// Throws std::invalid_argument for settings whose modes cannot go together: a tile share out
/// of range; the render cache or frameless rendering over a tile share (they reproject and rank
/// pixels over the whole image); bad sampling; interpolating adaptive sampling with several
/// samples per pixel; adaptive anti-aliasing over a tile share (it compares neighbours).
void check_trace_modes(const TraceSettings& options) {
    if (!options.tiles.valid()) {
        throw std::invalid_argument("tile share " + std::to_string(options.tiles.index) + " of " +
                                    std::to_string(options.tiles.count) +
                                    ": needs 0 <= index < count");
    }
    if (options.reuse.approximate() && !options.tiles.whole()) {
        throw std::invalid_argument(std::string("pixel reuse '") + pixel_reuse_name(options.reuse.mode) +
                                    "' needs the whole image: a frame split into tile shares "
                                    "can use exact reuse or none");
    }
    check_sampling(options.sampling);
    const bool sampled = options.sampling.spp > 1;
    if (sampled && options.adaptive_tolerance > 0.0f) {
        throw std::invalid_argument("adaptive sampling (interpolation) takes one sample per pixel: with " +
                                    std::to_string(options.sampling.spp) +
                                    " samples per pixel use adaptive anti-aliasing instead");
    }
    if (sampled && options.sampling.adaptive_contrast > 0.0f && !options.tiles.whole()) {
        throw std::invalid_argument("adaptive anti-aliasing compares neighbouring pixels and needs the whole "
                                    "image: a frame split into tile shares can take every sample in every pixel");
    }
}

/// The frame an update received, as another backend loads it: world positions per object.
class PipelineGeometry final : public FrameGeometry {
public:
    PipelineGeometry(std::span<const ObjectState> states, const FixedPositions& fixed)
        : states_(states), fixed_(fixed) {}

    std::span<const glm::vec3> world_positions(std::size_t object,
                                               std::vector<glm::vec3>& scratch) const override {
        const ObjectState& state = states_[object];
        switch (state.motion_class) {
            case anim::MotionClass::static_: return fixed_.world(object, scratch);
            case anim::MotionClass::rigid: {
                const std::span<const glm::vec3> local = fixed_.object_space(object);
                scratch.resize(local.size());
                for (std::size_t v = 0; v < local.size(); ++v) {
                    scratch[v] = glm::vec3(state.transform * glm::dvec4(glm::dvec3(local[v]), 1.0));
                }
                return scratch;
            }
            default: return state.world_positions;
        }
    }
    bool changed(std::size_t object) const override { return states_[object].changed; }

private:
    std::span<const ObjectState> states_;
    const FixedPositions& fixed_;
};

}  // namespace

void FramePipeline::use_backend(std::shared_ptr<FrameBackend> backend) {
    backend_ = std::move(backend);
    clear_trees();
}

void FramePipeline::clear() {
    clear_trees();
    textures_.clear();
}

void FramePipeline::clear_trees() {
    accel_.clear();
    if (backend_) backend_->forget();
    updated_ = false;
    reuse_.valid = false;
    sampled_reuse_.clear();
    pixel_cache_.valid = false;
    camera_moving_ = false;
    versions_.clear();
}

void FramePipeline::invalidate(std::size_t object) {
    accel_.invalidate(object);
    versions_.invalidate(object);
}

void FramePipeline::release(std::size_t object) {
    accel_.release(object);
    versions_.release(object);
}

void FramePipeline::renew(std::size_t object) {
    accel_.renew(object);
    versions_.invalidate(object);
}

std::size_t FramePipeline::memory_bytes() const {
    return accel_.memory_bytes() + held_bytes(materials_) + held_bytes(object_material_) +
           textures_.memory_bytes() + versions_.memory_bytes();
}

TextureFigures FramePipeline::texture_figures() const { return textures_.figures(); }

const FrameStats& FramePipeline::update(const Scene& scene, std::span<const ObjectState> states,
                                        const FixedPositions& fixed, const UpdatePolicy& policy,
                                        int frame, const Stopwatch& frame_clock) {
    updated_ = false;
    FrameStats& stats = update_stats_;
    stats = FrameStats{};
    stats.frame = frame;
    // Versions first: an update that throws half way has still changed what it touched.
    versions_.advance(states);
    accel_.update(scene, states, fixed, policy, stats, stats);
    if (backend_) {
        stats.backend = backend_->name();
        stats.backend_load_ms = backend_->load(scene, PipelineGeometry(states, fixed));
    }
    update_wall_ms_ = frame_clock.elapsed_ms();
    // Everything the update did besides building trees (posing, checks, gathering triangles),
    // so that the stages shown add up to total_ms.
    stats.update_ms = std::max(0.0, update_wall_ms_ - stats.build_ms - stats.backend_load_ms);
    stats.total_ms = update_wall_ms_;
    updated_ = true;
    return stats;
}

std::span<const PointLight> FramePipeline::with_environment_lights(std::span<const PointLight> lights,
                                                                  const TraceSettings& options) {
    if (options.environment_lights == 0) return lights;
    if (options.environment_lights < 0 || options.environment_lights > kEnvironmentLightsMax) {
        throw std::invalid_argument("environment lights " + std::to_string(options.environment_lights) +
                                    ": must be in [0, " + std::to_string(kEnvironmentLightsMax) + "]");
    }
    if (!options.environment) {
        throw std::invalid_argument("environment lights need an environment map to make them from");
    }
    // The suns are made once per map and count (the map is held, so the key stays its own).
    if (environment_suns_key_.first != options.environment ||
        environment_suns_key_.second != options.environment_lights) {
        environment_suns_ = environment_lights(*options.environment, options.environment_lights);
        environment_suns_key_ = {options.environment, options.environment_lights};
    }
    frame_lights_.assign(lights.begin(), lights.end());
    frame_lights_.insert(frame_lights_.end(), environment_suns_.begin(), environment_suns_.end());
    return frame_lights_;
}

void FramePipeline::trace(const Scene& scene, const Camera& camera, const TraceSettings& options,
                          std::span<const PointLight> lights, RenderedFrame& out) {
    // The whole trace runs as one task of a group of its own, so that cancel() reaches every
    // parallel loop inside it (nested loops' contexts are bound to the group's).
    tbb::task_group_context context;
    {
        const std::lock_guard<std::mutex> lock(cancel_mutex_);
        running_ = &context;
    }
    // The trace is over, whole, stopped or failed: nothing left to cancel or to count.
    const auto done = [&] {
        progress_.finish();
        const std::lock_guard<std::mutex> lock(cancel_mutex_);
        running_ = nullptr;
    };
    tbb::task_group_status status = tbb::task_group_status::complete;
    try {
        tbb::task_group group(context);
        // (The group resets its context when its wait ends: its status says whether it was
        // cancelled.)
        status = group.run_and_wait([&] { run_trace(scene, camera, options, lights, out); });
    } catch (...) {
        done();
        throw;
    }
    done();
    if (status == tbb::task_group_status::canceled) {
        // Stopped before or while it ran: the image sized but incomplete (a trace stopped
        // before it started has not even sized it), the update's figures alone.
        if (options.width > 0 && options.height > 0) size_image(options, out);
        out.stats = update_stats_;
        out.stats.cancelled = true;
        // The image is incomplete: nothing of it may be reused.
        reuse_.valid = false;
        sampled_reuse_.clear();
        pixel_cache_.valid = false;
        camera_moving_ = false;
        out.reuse_stamp = 0;
    }
}

void FramePipeline::cancel() {
    const std::lock_guard<std::mutex> lock(cancel_mutex_);
    if (running_ != nullptr) running_->cancel_group_execution();
}

void FramePipeline::view_materials(const Scene& scene) {
    materials_.clear();
    for (const Material& m : scene.materials) {
        materials_.push_back(packet::PhongMaterial{m.diffuse, m.specular, m.shininess, m.emission,
                                                   m.ambient.value_or(glm::vec3(0.0f)), m.ambient.has_value()});
    }
    object_material_.clear();
    for (const Object& object : scene.objects) {
        object_material_.push_back(std::int32_t(object.material));
    }
}

void FramePipeline::run_trace(const Scene& scene, const Camera& camera, const TraceSettings& options,
                              std::span<const PointLight> given_lights, RenderedFrame& out) {
    if (!updated_) throw std::logic_error("FramePipeline::trace before any update");
    // Refused before anything changes (the API's render passes these on as its own errors).
    check_trace_modes(options);
    const bool sampled = options.sampling.spp > 1;
    const std::span<const PointLight> lights = with_environment_lights(given_lights, options);
    check_lights(lights);
    // Every tile, once per sample pass (render_progress.h); adaptive anti-aliasing adds its
    // refinement pass's tiles once it knows them.
    const bool refines_later = sampled && options.sampling.adaptive_contrast > 0.0f;
    progress_.start(std::size_t(packet::Tiling(options.width, options.height, options.tiles).count()) *
                    std::size_t(refines_later ? 1 : options.sampling.spp));
    const Stopwatch trace_clock;
    view_materials(scene);  // bookkeeping, outside the stage clocks
    out.stats = update_stats_;
    accel_.use_vertex_normals(options.smooth_normals);
    // Textures: read, decoded and MIP-mapped once per scene (and again when its materials map
    // other textures).
    const std::optional<detail::SurfaceTextures> surface_textures =
        textures_.for_trace(scene, accel_.shading(), camera, options.height);
    const detail::CpuTracer cpu(accel_, options);
    const TraceBackend& backend = backend_ ? static_cast<const TraceBackend&>(*backend_) : cpu;
    // Cut-out materials: every ray through the wrapper that skips their cut hits; without
    // them, straight to the backend.
    const detail::AlphaCutouts cutouts(scene.materials, object_material_,
                                       surface_textures ? &*surface_textures : nullptr);
    const detail::CutoutTracer cutout_tracer(backend, cutouts);
    const TraceBackend& tracer = any_cutout(scene.materials) ? cutout_tracer : backend;
    const TraceInputs inputs{accel_, tracer, materials_, object_material_, lights, scene.materials,
                             surface_textures ? &*surface_textures : nullptr, &progress_};
    // A reflection or refraction can show any object from any pixel whose hit spawns one:
    // exact reuse traces such pixels again whenever anything changed (exact_reuse.h), while the
    // approximate modes' ranking and adaptive sampling's interpolation cannot account for it,
    // so a frame with secondary rays traces every pixel instead of them.
    const bool secondary = detail::any_secondary(scene.materials, options.secondary);
    // Several samples per pixel: every pixel traced (the reuse modes keep one sample's record).
    const bool approximate = options.reuse.approximate() && options.adaptive_tolerance == 0.0f &&
                             !secondary && !sampled;
    // Exact reuse takes several samples per pixel too (a memory per sample), unless adaptive
    // anti-aliasing picks other pixels for them from frame to frame.
    const bool adaptive_aa = sampled && options.sampling.adaptive_contrast > 0.0f;
    const bool exact = options.reuse.mode == PixelReuse::exact && options.adaptive_tolerance == 0.0f && !adaptive_aa;
    // The camera moved at the last trace and moves again: a full trace either way, and
    // recording what exact reuse needs per tile cost 9% of it over BART kitchen's path. Traced
    // plainly; once the camera holds still for a frame, that frame records again.
    const bool camera_moving = exact && camera_moving_ && !detail::same_camera(camera, last_camera_);
    if (approximate) {
        reuse_.valid = false;
        sampled_reuse_.clear();
        out.reuse_stamp = 0;
        detail::trace_frame_approximate(inputs, camera, options, accel_.object_world_boxes(),
                                        versions_.versions(), pixel_cache_, scratch_, out);
    } else if (exact && !camera_moving) {
        pixel_cache_.valid = false;
        const detail::ReuseInputs now{camera,           options,
                                      lights,           materials_,
                                      scene.materials,  object_material_,
                                      accel_.object_world_boxes(),
                                      versions_.versions(), out.reuse_stamp,
                                      versions_.parts(accel_)};
        if (sampled) {
            reuse_.valid = false;
            const detail::ReusePlan plan = sampled_reuse_.trace(inputs, now, options, out);
            camera_moving_ = plan.full && plan.reason == detail::kCameraMoved;
        } else {
            sampled_reuse_.clear();
            const detail::ReusePlan plan = detail::plan_exact_reuse(reuse_, now);
            detail::trace_frame_reusing(inputs, camera, options, plan, reuse_, scratch_, out);
            detail::remember_inputs(now, reuse_, out);
            camera_moving_ = plan.full && plan.reason == detail::kCameraMoved;
        }
    } else {
        // Every pixel traced (or sampled, adaptively): nothing is kept for the next frame.
        reuse_.valid = false;
        sampled_reuse_.clear();
        pixel_cache_.valid = false;
        out.reuse_stamp = 0;
        if (sampled) {
            detail::trace_sampled_frame(inputs, camera, options, scratch_, out);
        } else if (secondary && options.adaptive_tolerance > 0.0f) {
            TraceSettings every_pixel = options;
            every_pixel.adaptive_tolerance = 0.0f;
            trace_frame(inputs, camera, every_pixel, scratch_, out);
        } else {
            trace_frame(inputs, camera, options, scratch_, out);
        }
        const bool reuse_asked = options.reuse.mode != PixelReuse::off || options.adaptive_tolerance > 0.0f;
        out.stats.reuse_mode = pixel_reuse_name(camera_moving ? PixelReuse::exact : PixelReuse::off);
        out.stats.reuse_reason = camera_moving                       ? "camera moving"
                                 : adaptive_aa && reuse_asked         ? "adaptive anti-aliasing"
                                 : sampled && reuse_asked             ? "samples per pixel"
                                 : secondary && reuse_asked           ? "secondary rays"
                                 : options.adaptive_tolerance > 0.0f ? "adaptive sampling"
                                                                     : "reuse off";
        out.stats.pixels_traced = sampled ? packet::Tiling(options.width, options.height, options.tiles).pixel_count()
                                          : out.stats.primary_rays;
        out.stats.pixels_shadows_retraced = 0;
        out.stats.pixels_reused = 0;
        out.stats.pixels_filled = 0;
    }
    if (backend_ == nullptr) {
        out.stats.shadow_rays_cache_tested = cpu.cached_shadow_rays();
        out.stats.shadow_rays_cache_answered = cpu.cache_answered_shadow_rays();
    }
    if (!exact) camera_moving_ = false;
    last_camera_ = camera;
    out.stats.total_ms = update_wall_ms_ + trace_clock.elapsed_ms();
    // What the automatic update method predicts the next frames' trace times from.
    accel_.note_trace_ms(out.stats.primary_ms + out.stats.shadow_ms);
    // The cost view: a pass of its own, after the clocks.
    if (options.pixel_cost) {
        detail::trace_pixel_costs(accel_.top_level(), camera, options.width, options.height, options.tiles, out.cost);
    } else {
        out.cost.clear();
    }
}

}  // namespace dynrt
