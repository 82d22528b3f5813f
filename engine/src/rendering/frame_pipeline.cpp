#include "rendering/frame_pipeline.h"

#include <algorithm>
#include <stdexcept>

namespace dynrt {

void FramePipeline::clear() {
    accel_.clear();
    updated_ = false;
}

const FrameStats& FramePipeline::update(const Scene& scene, std::span<const ObjectState> states,
                                        const FixedPositions& fixed, const UpdatePolicy& policy,
                                        int frame, const Stopwatch& frame_clock) {
    updated_ = false;
    FrameStats& stats = update_stats_;
    stats = FrameStats{};
    stats.frame = frame;
    accel_.update(scene, states, fixed, policy, stats, stats);
    // Measuring new trees for the report (their SAH cost and shape) is not frame work.
    update_wall_ms_ = frame_clock.elapsed_ms() - accel_.reporting_ms();
    // Everything the update did besides building trees (posing, checks, gathering triangles),
    // so that the stages shown add up to total_ms.
    stats.update_ms = std::max(0.0, update_wall_ms_ - stats.build_ms);
    stats.total_ms = update_wall_ms_;
    updated_ = true;
    return stats;
}

void FramePipeline::trace(const Scene& scene, const Camera& camera, const TraceSettings& options,
                          std::span<const PointLight> lights, RenderedFrame& out) {
    if (!updated_) throw std::logic_error("FramePipeline::trace before any update");
    const Stopwatch trace_clock;
    // The shading kernel's view of the materials (bookkeeping, outside the stage clocks).
    materials_.clear();
    for (const Material& m : scene.materials) {
        materials_.push_back(packet::PhongMaterial{m.diffuse, m.specular, m.shininess});
    }
    object_material_.clear();
    for (const Object& object : scene.objects) {
        object_material_.push_back(std::int32_t(object.material));
    }
    out.stats = update_stats_;
    trace_frame(TraceInputs{accel_, materials_, object_material_, lights}, camera, options,
                scratch_, out);
    out.stats.total_ms = update_wall_ms_ + trace_clock.elapsed_ms();
}

}  // namespace dynrt
