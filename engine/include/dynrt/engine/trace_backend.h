#pragma once
// The one seam between a frame and the tracer that answers its rays (issue 36; the shape
// follows pbrt-v4's wavefront aggregate, whose IntersectClosest and IntersectShadow over a ray
// queue are implemented once per device). Every ray a frame traces, camera, shadow, reflection
// or refraction, in every mode (full frames, exact reuse, the approximate modes, adaptive
// sampling), goes through a TraceBackend as a batch of at most 256 rays: the active lanes of a
// RayPacket. Hits come back resolved to the scene object and its triangle, so nothing above the
// seam knows how a tracer groups its objects. dynrt's own tracer (cpu_tracer.h) is one
// backend; another (Embree, a GPU) implements the same two calls.
//
// A backend that is not bit-identical to dynrt's can still be checked: hit_agreement.h counts
// pixels whose object or triangle differ, and the frame tests compare such a backend's frames
// against dynrt's within a documented count of edge pixels.

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/packet/packet_config.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace dynrt {

/// How a batch's rays were made, which is all a tracer is told of their coherence.
enum class RayCoherence {
    /// One tile's rays: its camera rays through one eye, or its hit points' shadow rays toward
    /// one light (which, run from the light, share an origin).
    tile,
    /// Rays that may go anywhere: reflection and refraction rays, and the shadow rays of their
    /// hits.
    scattered,
    /// A caller's rays, of which nothing is known: the library API's batches (a camera's, a
    /// lidar sweep's, or rays in any order).
    unknown,
};

/// Closest hits of a batch, by lane.
using LaneHits = bvh::InstanceHit[packet::kPacketRays];

/// Where a batch's closest hits go: lane l's to base[(l / 16) * row_stride + l % 16]. Either
/// a LaneHits array (row_stride 16), or a tile of a frame's per-pixel hits (base at the tile's
/// top-left pixel, row_stride the image width), so that a tile's camera rays' hits land in
/// place, without a copy.
struct HitTarget {
    bvh::InstanceHit* base;
    std::size_t row_stride = std::size_t(packet::kTileSize);

    HitTarget(LaneHits& hits) : base(hits) {}  // NOLINT: a LaneHits array is a target
    HitTarget(bvh::InstanceHit* first, std::size_t stride) : base(first), row_stride(stride) {}

    bvh::InstanceHit& operator[](int lane) const {
        return base[std::size_t(lane / packet::kTileSize) * row_stride + std::size_t(lane % packet::kTileSize)];
    }
};

/// The work a thread's traces did, when a trace counts it (TraceSettings::count_packet_work):
/// packet traversals' counters and single rays' counters.
struct TraceWork {
    packet::PacketStats packet;
    bvh::TraversalStats single;

    TraceWork& operator+=(const TraceWork& other) {
        packet += other.packet;
        single.nodes_visited += other.single.nodes_visited;
        single.triangles_tested += other.single.triangles_tested;
        return *this;
    }

    /// Sets the report's ray/triangle tests, culled pairs and node visits from both tracers'
    /// counters (a trace may use both: packets for full tiles, single rays for a few).
    void report(TraceStats& stats) const {
        stats.ray_triangle_tests = packet.ray_triangle_tests + single.triangles_tested;
        stats.ray_triangle_culled = packet.culled_active_bounds + packet.culled_beam_planes +
                                    packet.culled_triangle_edges + packet.culled_near_far;
        stats.nodes_visited = packet.nodes_visited + single.nodes_visited;
    }
};

class TraceBackend {
public:
    virtual ~TraceBackend() = default;

    /// Closest hits of `rays`' active lanes within [tmin, tmax] into hits[lane], resolved to
    /// scene object and triangle (a miss: a default InstanceHit); other lanes' entries are left
    /// alone.
    /// Returns how many of the rays were traced as packets (the rest one by one), for the
    /// report. `work`, if not null, receives the traversal counters. Thread-safe on a shared
    /// backend; `work` is the calling thread's.
    virtual int closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                        TraceWork* work) const = 0;

    /// Which of `rays`' active lanes hit anything within [tmin, tmax] (shadow rays).
    virtual packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence,
                                      TraceWork* work) const = 0;
};

/// One frame's world-space geometry, object by object (scene order), as a backend other than
/// dynrt's loads it: the same posed frame dynrt's update received.
class FrameGeometry {
public:
    virtual ~FrameGeometry() = default;
    /// Object `object`'s world-space positions at the frame, indexed as its mesh's: a span
    /// into storage of its own or into `scratch`, which it may fill; valid until the next call.
    virtual std::span<const glm::vec3> world_positions(std::size_t object,
                                                       std::vector<glm::vec3>& scratch) const = 0;
    /// False when the object is known not to have moved since the previous frame.
    virtual bool changed(std::size_t object) const = 0;
};

/// A tracer other than dynrt's own behind the seam (Renderer::use_backend): Embree, later a
/// GPU. Each frame, after dynrt's update (whose trees' shading geometry the frame is still
/// shaded with), it loads the frame's geometry; then it answers the frame's rays. Its hits
/// must name the scene's objects and their mesh triangles (triangle i of object o:
/// scene.objects[o].mesh.triangles[i]), with barycentrics as dynrt's.
class FrameBackend : public TraceBackend {
public:
    /// The backend's name in reports, e.g. "embree-low".
    virtual std::string name() const = 0;
    /// Brings the backend's own acceleration structures to `scene`'s frame as `geometry` gives
    /// it. Returns the milliseconds it took (the backend's update stage).
    virtual double load(const Scene& scene, const FrameGeometry& geometry) = 0;
    /// Forgets what was loaded: the next load builds from nothing (Renderer::forget_trees).
    virtual void forget() = 0;
};

}  // namespace dynrt
