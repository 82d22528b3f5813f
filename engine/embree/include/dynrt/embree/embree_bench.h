#pragma once
// Embree beside dynrt in `dynrt bench --vs embree`: every build quality on one frame (with hit
// agreement against a dynrt frame), Embree stepping through a sequence beside dynrt's frame
// loop, and the rows as a table and JSON. The adapter itself is embree_tracer.h.

#include "dynrt/bench/bench.h"
#include "dynrt/bench/bench_sequence.h"
#include "dynrt/bench/hit_agreement.h"
#include "dynrt/embree/embree_tracer.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/spread.h"
#include "dynrt/scene/scene.h"

#include <cstddef>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::embree {

/// One Embree build quality's figures over `repeat` runs after `warmup`.
struct EmbreeRow {
    BuildQuality quality = BuildQuality::low;
    Spread build_ms;        ///< rtcCommitScene only; buffer creation and upload excluded
    Spread intersect1_ms;   ///< primary rays, one at a time
    Spread intersect16_ms;  ///< primary rays, 16-ray packets of 4x4 pixels
    Spread occluded1_ms;    ///< shadow rays, one at a time
    Spread occluded16_ms;   ///< shadow rays, 16-ray packets of 4x4 pixels
    Spread mrays_per_s;     ///< (primary + shadow rays) / (intersect16 + occluded16 time)
    std::size_t shadow_rays = 0;
    /// Embree's intersect1 hits against the dynrt frame given to bench_embree.
    HitAgreement vs_dynrt;
    /// Pixels where intersect16 and intersect1 disagree on object or primitive, plus pixels
    /// where occluded16 and occluded1 disagree on the number of occluded lights (expected 0).
    std::size_t packet_vs_single_differs = 0;
};

/// Benches every build quality on frame 0 of `scene` with `options`' resolution and lights,
/// and compares each quality's hits with `dynrt_frame` (a dynrt render of the same frame).
/// If `disagreement` is not null, it receives per pixel the worst disagreement between
/// `dynrt_frame` and any quality's intersect1 hits (for `--diff-image`).
/// The same reflection and refraction rays traced by dynrt and by Embree (`bench --vs embree`
/// on a frame with secondary rays): the rays one render of frame 0 traced
/// (TraceSettings::secondary_log), replayed as dynrt traced them (Renderer::trace_logged_rays)
/// and through Embree's high-quality tree in 16-lane blocks of each packet with
/// rtcIntersect16 (coherent and default contexts) and one by one with rtcIntersect1,
/// interleaved run by run.
struct SecondaryComparison {
    std::size_t reflection_rays = 0;
    std::size_t refraction_rays = 0;
    std::size_t packets = 0;  ///< packets as traced (one kind, one depth, up to 256 sorted rays)
    /// The render's camera rays' rate (FrameStats::primary_mrays_per_s), for scale.
    double primary_mrays_per_s = 0;
    Spread dynrt_ms, embree16_coherent_ms, embree16_ms, embree1_ms;
    /// dynrt's hits against Embree's rtcIntersect1 hits, ray by ray.
    HitAgreement vs_dynrt;
};

/// Runs the comparison above over `warmup` + `repeat` runs. Nothing to compare (no secondary
/// rays) gives all counts 0.
SecondaryComparison bench_secondary_embree(const Scene& scene, const Camera& camera,
                                           const RenderOptions& options, int repeat, int warmup);

/// The comparison as a table, and as JSON.
void print_secondary_table(std::ostream& out, const SecondaryComparison& c);
std::string secondary_json(const SecondaryComparison& c);

std::vector<EmbreeRow> bench_embree(const Scene& scene, const Camera& camera,
                                    const RenderOptions& options, int repeat, int warmup,
                                    const RenderedFrame& dynrt_frame,
                                    std::vector<PixelAgreement>* disagreement = nullptr);

/// The Embree block: one row per quality with the ratios dynrt/Embree taken from `dynrt_row`
/// (medians: build ms over build ms, primary ms over intersect1 and intersect16 ms, shadow ms
/// over occluded1 and occluded16 ms), then a "hit agreement" line per quality.
void print_embree_table(std::ostream& out, const std::vector<EmbreeRow>& rows,
                        const BenchRow& dynrt_row);

/// Embree stepping through an animated sequence beside dynrt (`bench --frames --vs embree`):
/// per frame it poses the scene in full (every object's world positions), loads the frame
/// (load_frame with `quality`: refit or low, Embree's two per-frame options), traces the
/// camera rays with rtcIntersect16 and the shadow rays with rtcOccluded16 (4x4-pixel packets,
/// as EmbreeTracer::intersect16 and occluded16 trace them), and compares its
/// hits with dynrt's. Borrows `scene`.
std::unique_ptr<SequenceTracer> make_sequence_tracer(const Scene& scene, const RenderOptions& options,
                                                     BuildQuality quality);

/// The rows as a JSON array (Spreads as {"median", "min", "max"} objects).
std::string embree_json(const std::vector<EmbreeRow>& rows);

}  // namespace dynrt::embree
