#pragma once
// Tracing and shading one frame through a SceneAccel: primary rays in 16x16 tiles, a shadow
// ray per hit and light, Phong shading (renderer.h describes the model). The renderer calls it
// after posing a scene's frame; the library API (dynrt/dynrt.h) after its caller's update.

#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/packet_shading.h"
#include "rendering/frame_progress.h"
#include "rendering/pixel_samples.h"
#include "rendering/secondary_rays.h"
#include "dynrt/engine/trace_backend.h"
#include "update/scene_accel.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dynrt {

/// What a frame's trace reads besides the camera and options; borrowed for the call.
struct TraceInputs {
    /// The trees, and the shading geometry of their objects.
    const SceneAccel& accel;
    /// What traces the frame's rays (trace_backend.h): dynrt's CpuTracer over `accel`, or
    /// another backend over the same posed scene.
    const TraceBackend& tracer;
    /// Materials as the shading kernel reads them, and each object's index into them.
    std::span<const packet::PhongMaterial> materials;
    const std::vector<std::int32_t>& object_material;
    std::span<const PointLight> lights;
    /// The scene's materials, for their reflection and refraction terms; empty, or none of
    /// them reflecting or transmitting, or TraceSettings::secondary.max_depth 0: no secondary
    /// rays.
    std::span<const Material> scene_materials = {};
    /// The frame's textures, or null when no material maps one.
    const detail::SurfaceTextures* textures = nullptr;
    /// Counts each tile pass done (Renderer::progress), or null.
    detail::FrameProgress* progress = nullptr;
};

/// Buffers a trace fills and the next one reuses (one per concurrent trace).
struct TraceScratch {
    std::vector<bvh::InstanceHit> hits;
    std::vector<packet::ShadingLight> shading_lights;
    /// Per object, the transmittance shadow rays pass through (TileShading::glass).
    std::vector<glm::vec3> glass;
    detail::SecondaryBuffers secondary;
    /// Frames of several samples per pixel (sampled_frame.h): one sample pass's image, the
    /// pixels' sums, and the pixels that take every sample.
    RenderedFrame sample_pass;
    std::vector<glm::vec3> sample_sum;
    std::vector<std::uint8_t> refined;
    /// Adaptive anti-aliasing's pass: the refined pixels' other samples, and its frame's mask.
    std::vector<detail::PixelSample> refined_samples;
    std::vector<std::uint8_t> listed;
};

/// Sizes `out` for options.width x options.height: the colour, and the hit buffers (depth,
/// object, prim, normal) when options.hit_buffers, else none.
void size_image(const TraceSettings& options, RenderedFrame& out);

/// size_image, and scratch.hits alike.
void size_frame(const TraceSettings& options, TraceScratch& scratch, RenderedFrame& out);

/// The shading kernel's view of a trace: `in`'s materials, lights (made into
/// scratch.shading_lights, which it borrows) and textures, options' ambient and background.
detail::TileShading frame_shading(const TraceInputs& in, const TraceSettings& options,
                                  TraceScratch& scratch);

/// A trace's secondary stage (secondary_rays.h) when its materials and options spawn
/// reflection or refraction rays, else none; the frame it reads is kept beside it.
class FrameSecondary {
public:
    /// `sample`: the pixel samples the frame's rays belong to.
    FrameSecondary(const TraceInputs& in, const TraceSettings& options,
                   const detail::TileShading& shading, TraceScratch& scratch, const detail::SamplePass& sample = {});
    FrameSecondary(const FrameSecondary&) = delete;
    FrameSecondary& operator=(const FrameSecondary&) = delete;

    /// The stage, or null for a frame without secondary rays.
    detail::SecondaryStage* stage() { return stage_ ? &*stage_ : nullptr; }

private:
    std::optional<detail::SecondaryFrame> frame_;
    std::optional<detail::SecondaryStage> stage_;
};

/// Renders `camera`'s view at options.width x options.height into `out` (its buffers reused),
/// with options' tracer, culling, adaptive tolerance, secondary rays, background and ambient,
/// lit by `in.lights`. Adaptive sampling ignores the secondary rays: callers turn it off when
/// a frame has some (FramePipeline::trace does). Sets the trace's fields of
/// out.stats (primary, shadow and shade ms and rays, rays/s, interpolated pixels, packet work)
/// and leaves the others as they are. Throws std::invalid_argument for a degenerate camera.
/// `sample` says which sample of its pixels the frame traces (pixel_samples.h; by default each
/// pixel's centre, options.sampling aside: sampled_frame.h makes frames of several): with
/// sample.pixels, only those pixels' rays are traced, the others are written as misses.
void trace_frame(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                 TraceScratch& scratch, RenderedFrame& out, const detail::SamplePass& sample = {});

}  // namespace dynrt
