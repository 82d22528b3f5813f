#pragma once
// `dynrt bench --frames`: an animated sequence rendered frame after frame, as an application
// would, with per-frame figures summarised over the frames. Other tracers (Embree) can run the
// same frames side by side in the same loop, through the SequenceTracer interface, so every
// tracer sees the same poses, rays and cache conditions.

#include "dynrt/bench/bench.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/bench/hit_agreement.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/sequence.h"
#include "dynrt/scene/scene.h"

#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dynrt {

/// What one frame cost a tracer, in its own terms mapped onto dynrt's stages.
struct SequenceFrameTimes {
    double update_ms = 0;   ///< evaluating the animation (posing)
    double build_ms = 0;    ///< bringing the acceleration structure up to date
    double primary_ms = 0;  ///< camera rays
    double shadow_ms = 0;   ///< shadow rays
    double shade_ms = 0;    ///< hits to colours; 0 for a tracer that does not shade (Embree's)
    /// Its hits against dynrt's for this frame.
    HitAgreement vs_dynrt;
    /// Reflection and refraction rays with their shadow rays and shading (0 without them, and
    /// for a tracer that does not shade).
    double secondary_ms = 0;
};

/// Another tracer stepping through the same sequence (see the Embree backend).
class SequenceTracer {
public:
    virtual ~SequenceTracer() = default;
    /// Its name in the table, e.g. "embree refit".
    virtual std::string name() const = 0;
    /// Renders frame `frame` (the frames come in order) with the same camera rays and lights
    /// as `dynrt_frame`, dynrt's render of that frame, and compares its hits with it.
    virtual SequenceFrameTimes frame(int frame, const Camera& camera,
                                     const RenderedFrame& dynrt_frame) = 0;
};

/// One tracer's figures over the frames (median, min, max over every frame of every run).
struct SequenceRow {
    std::string tracer;
    Spread update_ms;
    Spread build_ms;
    Spread trace_ms;  ///< primary + shadow
    Spread primary_ms;
    Spread shadow_ms;
    /// update + build + trace: what a frame costs before shading, the figure compared.
    Spread frame_ms;
    Spread shade_ms;
    Spread secondary_ms;
    /// frame + shade + secondary: the whole frame (as frame_ms for a tracer that does not
    /// shade).
    Spread total_ms;
    /// Summed over the frames (other tracers only).
    HitAgreement vs_dynrt;
};

struct SequenceBench {
    /// dynrt first, then one row per SequenceTracer.
    std::vector<SequenceRow> rows;
    /// dynrt's per-frame report of the last run (for the timeline plot and --json).
    std::vector<FrameStats> frames;
    /// The untimed start-up frame before the warm-up (the first frame, its textures read and
    /// its trees built): what a render pays once, outside every run.
    double first_ms = 0.0;
    /// The textures that start-up frame read (Renderer::texture_figures), once.
    TextureFigures textures{};
};

/// Renders frames `range` of `scene` with `options`, `runs` times (each run starts from empty
/// trees, as a new sequence would, but with the textures read: SequenceBench::first_ms), after
/// one untimed start-up render of the first frame and `warmup` more. Each
/// frame of each run is one sample. `others` step through the same frames in the same loop,
/// each right after dynrt, with the same camera, the one `view` gives at each frame.
/// Throws std::invalid_argument when `view` asks for the scene's own camera and it has none.
SequenceBench bench_sequence(const Scene& scene, const CameraSource& view,
                             const RenderOptions& options, FrameRange range, int runs, int warmup,
                             const std::vector<std::unique_ptr<SequenceTracer>>& others);

/// The table: one row per tracer, then the ratios of dynrt's frame ms to each other's.
void print_sequence_table(std::ostream& out, const SequenceBench& bench);

/// {"sequence": [rows], "frames": [dynrt's per-frame report]} as JSON text.
std::string sequence_json(const SequenceBench& bench);

}  // namespace dynrt
