#pragma once
// A frame of several samples per pixel (TraceSettings::sampling, dynrt/engine/pixel_sampling.h):
// one pass of the frame's tile pipeline (trace_frame) per sample, each pixel the mean of its
// samples. A pass traces one sample of every pixel it covers as 16x16 coherent packets (each
// lane its pixel's own jittered ray), so packets stay as coherent as at one sample per pixel,
// and every pass is the full pipeline: shadow rays toward each area light's sampled point,
// shading, secondary rays. With adaptive anti-aliasing the first pass decides which pixels
// take the others (refine_pixels).

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "rendering/exact_reuse.h"
#include "rendering/frame_tracer.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynrt::detail {

/// The pixels adaptive anti-aliasing refines, from the first pass's image `first` and hits
/// (`hits`, per pixel): those whose colour, clamped to [0, 1], differs from a 4-neighbour's by
/// more than `contrast` in some channel, or whose neighbour shows another object (or nothing
/// where it shows one). refined[p] = 1 for them, 0 for the others; returns their number.
std::size_t refine_pixels(const RenderedFrame& first, const std::vector<bvh::InstanceHit>& hits, float contrast,
                          std::vector<std::uint8_t>& refined);

/// Renders options.sampling.spp samples per pixel (at least 2) into `out`, as trace_frame
/// renders one: out.color the mean of each pixel's samples, its hit buffers from sample 0,
/// out.stats the passes' figures added up (samples_per_pixel, pixels_refined). The caller
/// has refused the modes that cannot take several samples (interpolating adaptive sampling,
/// adaptive anti-aliasing over a tile share). Texture footprints shrink with the samples:
/// each sample's is a pixel's over sqrt(spp) (the first pass's stays a pixel's under adaptive
/// anti-aliasing, whose unrefined pixels keep that one sample).
void trace_sampled_frame(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                         TraceScratch& scratch, RenderedFrame& out);

/// Exact reuse (exact_reuse.h) of frames whose every pixel takes options.sampling.spp samples
/// (no adaptive anti-aliasing): each sample's pass keeps a memory, hits and image of its own
/// from frame to frame, and re-traces only its rays that may meet what changed, as a frame of
/// one sample does; each pixel is then the mean of the passes' images, so the frame is
/// bit-identical to trace_sampled_frame's. It holds spp images and hit buffers.
class SampledReuse {
public:
    /// Traces the frame into `out` (colour, sample 0's hit buffers, the passes' figures added
    /// up, the pixel counts the mean over the samples) and returns sample 0's plan (why it
    /// traced in full, or what changed). `now` as FramePipeline makes it for one sample.
    ReusePlan trace(const TraceInputs& in, const ReuseInputs& now, const TraceSettings& options,
                    RenderedFrame& out);

    /// Forgets what the passes kept (the next trace is a full one) and frees it.
    void clear() { samples_.clear(); }

private:
    struct Sample {
        ReuseMemory memory;
        TraceScratch scratch;
        RenderedFrame frame;
    };
    std::vector<Sample> samples_;
};

}  // namespace dynrt::detail
