#pragma once
// The Embree 3 adapter of `dynrt bench --vs embree`: the same posed world-space triangles and
// the same camera and shadow rays as dynrt's renderer, traced by Embree and timed. The bench
// drivers and tables are in embree_bench.h. Embree's types stay in the .cpp; this header needs
// no Embree include.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/secondary_ray_log.h"
#include "dynrt/engine/trace_backend.h"
#include "dynrt/packet/ray_packet.h"
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

/// Embree here holds every object's triangles in world space, copies of a shared mesh each in
/// full (it has no instancing in dynrt's use of it), besides the posed frame it reads them
/// from. Throws std::runtime_error naming the scene when that would need more memory than the
/// machine has available (available_memory; no check where that is unknown): a forest of a
/// billion instanced triangles is traced by dynrt alone, not run out of memory.
void check_embree_fits(const Scene& scene);

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

    /// Primary rays of `camera` at width x height (packet::PinholeRays), one rtcIntersect1 per pixel.
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

    /// Closest hits of logged reflection and refraction rays (SecondaryRayLog, a frame's
    /// packets as the renderer traced them), parallel over the packets: each 256-lane packet
    /// as sixteen blocks of 16 lanes (rays next to each other in the renderer's sorted order:
    /// one kind and octant, nearby origins), one rtcIntersect16 per block holding a ray, the
    /// other lanes masked off, with a coherent context or Embree's default (incoherent) one. `hits`
    /// gets one entry per ray in log order (object, prim; -1 on a miss). Returns ms.
    double intersect16_logged(const SecondaryRayLog& log, bool coherent, PixelHits& hits);
    /// The same rays one at a time with rtcIntersect1. Same results as intersect16_logged.
    double intersect1_logged(const SecondaryRayLog& log, PixelHits& hits);
    /// The same shadow rays one at a time with rtcOccluded1. Same results as occluded16.
    double occluded1(const Camera& camera, int width, int height,
                     const std::vector<PointLight>& lights, const PixelHits& hits,
                     std::size_t& rays, std::vector<std::uint32_t>* occluded = nullptr);

    /// One frame given object by object (FrameGeometry, the trace seam's view of an update):
    /// as load_frame, creating the geometries at the first call, with another quality or
    /// object count, and otherwise copying the changed objects' positions.
    FrameLoad load_geometry(const Scene& scene, const FrameGeometry& geometry, BuildQuality quality);
    /// Releases the scene: the next load creates it afresh.
    void forget();

    /// The trace seam's calls (EmbreeBackend): closest hits of `rays`' active lanes into
    /// hits[lane] (object = geomID, prim = primID, Embree's t, u, v; a miss a default hit),
    /// and which active lanes are occluded, with rtcIntersect16 / rtcOccluded16 over blocks of
    /// 16 lanes: a tile's 4x4-pixel blocks with a coherent context when `tile`, else 16
    /// consecutive lanes with the default one. Thread-safe after a load.
    void closest_lanes(const packet::RayPacket& rays, bool tile, HitTarget hits) const;
    packet::LaneMask occluded_lanes(const packet::RayPacket& rays, bool tile) const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace dynrt::embree
