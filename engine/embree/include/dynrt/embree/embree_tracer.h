#pragma once
// Embree 3 side of `dynrt bench --vs embree`: the same posed world-space triangles and the same
// camera and shadow rays as dynrt's renderer, traced by Embree, timed, and compared hit by hit
// with a dynrt frame. Embree's types stay in the .cpp; this header needs no Embree include.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bench/bench.h"
#include "dynrt/bench/bench_sequence.h"
#include "dynrt/engine/camera.h"
#include "dynrt/bench/hit_agreement.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::embree {

/// Embree's BVH build qualities; `low` also sets RTC_SCENE_FLAG_DYNAMIC (its refit-friendly
/// builder, the one meant for animated scenes). `refit` (RTC_BUILD_QUALITY_REFIT, dynamic
/// flag) builds like `low` at the first commit and refits the geometries at later ones: only
/// meaningful for load_frame sequences.
enum class BuildQuality { low, medium, high, refit };

/// What one load_frame cost.
struct FrameLoad {
    /// Copying the new positions into Embree's vertex buffers and marking them updated.
    double upload_ms = 0;
    /// rtcCommitScene: Embree's rebuild or refit.
    double commit_ms = 0;
};

/// "low", "medium", "high", "refit".
const char* quality_name(BuildQuality quality);

/// Per-pixel closest hits, row-major like RenderedFrame: object index in scene order and
/// triangle index within the object, both -1 on a miss; Embree's barycentrics of the hit
/// (p = (1-u-v) v0 + u v1 + v v2, dynrt's convention too), 0 on a miss.
struct PixelHits {
    std::vector<std::int32_t> object;
    std::vector<std::int32_t> prim;
    std::vector<float> u;
    std::vector<float> v;
};

/// One Embree device and scene holding frame 0 of a dynrt scene, one triangle geometry per
/// object (geomID = object index, primID = triangle index in the object). Owns its Embree
/// handles. Not thread-safe to rebuild; the trace calls run in parallel over 16x16 tiles on
/// the caller's oneTBB arena and may be called repeatedly after a build.
class EmbreeTracer {
public:
    /// Throws std::runtime_error if Embree cannot create a device.
    EmbreeTracer();
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    /// Poses `scene` at frame 0 and copies its triangles into fresh Embree geometry buffers
    /// (untimed), then commits the scene with `quality`. Returns the rtcCommitScene time in
    /// ms: the BVH build alone, comparable to dynrt's build_ms. Throws std::runtime_error on
    /// an Embree error.
    double build(const Scene& scene, BuildQuality quality);

    /// One frame of a sequence: `posed` (a full pose of `scene`: every object's world
    /// positions; borrowed until the next load or build) goes into the scene, then the scene
    /// is committed. The first call, or one with another quality, creates the geometries;
    /// later calls copy the positions of changed objects into the existing vertex buffers,
    /// which Embree answers at the commit by refitting (refit) or rebuilding (the others).
    FrameLoad load_frame(const Scene& scene, const anim::PosedScene& posed, BuildQuality quality);

    /// Primary rays of `camera` at width x height (CameraRays), one rtcIntersect1 per pixel.
    /// Fills `out` and returns the time in ms. Requires a build.
    double intersect1(const Camera& camera, int width, int height, PixelHits& out);

    /// The same rays as packets of 16, the way Embree's own tutorials cast them: each 16x16
    /// tile as sixteen 4x4-pixel blocks, one rtcIntersect16 per block (lanes past the image
    /// edge masked off), with the context flagged RTC_INTERSECT_CONTEXT_FLAG_COHERENT (camera
    /// rays are coherent, and the flag selects Embree's frustum-culling packet traversal).
    /// Same results as intersect1.
    double intersect16(const Camera& camera, int width, int height, PixelHits& out);

    /// dynrt's shadow rays for the hits `hits` (from intersect1/16 with the same camera, so
    /// with Embree's barycentrics, not dynrt's): per hit and light on the lit side, from the
    /// light to the barycentric hit point offset along the facing normal
    /// (offset_along_normal), t in [0, 1], traced with rtcOccluded16 in the same 4x4 blocks
    /// with a coherent context (all rays of a packet start at one light). Counts the rays in
    /// `rays` and returns ms. If `occluded` is not null, it receives per pixel the number of
    /// lights whose shadow ray is occluded.
    double occluded16(const Camera& camera, int width, int height,
                      const std::vector<PointLight>& lights, const PixelHits& hits,
                      std::size_t& rays, std::vector<std::uint32_t>* occluded = nullptr);

    /// The same shadow rays one at a time with rtcOccluded1. Same results as occluded16.
    double occluded1(const Camera& camera, int width, int height,
                     const std::vector<PointLight>& lights, const PixelHits& hits,
                     std::size_t& rays, std::vector<std::uint32_t>* occluded = nullptr);

private:
    struct State;
    std::unique_ptr<State> state_;
};

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
