#pragma once
// The approximate pixel reuse modes (pixel_reuse.h): a cache of the last traced sample of
// every pixel (colour, hit point, normal, object, triangle, age), refreshed each frame under a
// budget of traced pixels.
//
//   render cache  Walter, Drettakis and Parker 1999, "Interactive Rendering using the Render
//                 Cache": when the camera moves, the cached hit points are reprojected into the
//                 new view (nearest depth wins per pixel); pixels nothing landed on are holes.
//   frameless     Bishop, Fuchs, McMillan and Scher Zagier 1994, "Frameless Rendering: Double
//                 Buffering Considered Harmful", with the priorities of Dayal et al. 2005: the
//                 samples stay where they were traced, and the budget refreshes them.
//
// Each frame ranks 8x8 blocks of pixels: those whose ray may meet what changed since the last
// frame (changed_space.h) or that show an object that changed, then blocks with many holes,
// then the oldest. Ties are broken by a hash of block and frame, so the refresh order is
// randomised but reproducible. The render cache traces the larger of the budget and the first
// class (moving objects are never shown stale); frameless traces the budget in rank order.
// The render cache culls reprojected samples seen through cracks by depth (Walter et al.,
// section 4.3). What is still a hole after the trace is filled from its traced or reprojected
// neighbours (3x3 mean, a few passes), else the background; the render cache keeps filled
// cracks as samples. A budget in ms becomes a pixel count from the measured cost of a traced
// pixel in the previous frames.

#include "dynrt/bvh/aabb.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "rendering/frame_tracer.h"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace dynrt::detail {

/// The approximate modes' memory, one sample per pixel.
struct PixelCache {
    bool valid = false;
    Camera camera;
    TraceSettings settings;
    std::vector<PointLight> lights;
    std::vector<glm::vec3> color, point, normal;
    std::vector<std::int32_t> object, prim;
    /// Frames since the pixel was traced (saturating), kEmpty for no sample.
    std::vector<std::uint8_t> age;
    /// Per pixel depth for depth culling after reprojection (scratch, kept to reuse).
    std::vector<float> depth_scratch;
    /// Per-frame working arrays, kept so that a frame writes memory already faulted in.
    std::vector<std::uint64_t> nearest_scratch;
    std::vector<std::uint8_t> known_scratch, next_scratch;
    std::vector<bvh::Aabb> object_boxes;
    std::vector<std::uint64_t> object_versions;
    /// Measured cost of one traced pixel (ns of wall clock), for budgets in ms; 0 unknown.
    double ns_per_pixel = 0.0;
    std::uint64_t frames = 0;

    /// A second set of sample arrays for reprojection to gather into (then swapped in).
    std::unique_ptr<PixelCache> back;
    PixelCache& spare() {
        if (!back) back = std::make_unique<PixelCache>();
        return *back;
    }
    void swap_samples() {
        color.swap(back->color);
        point.swap(back->point);
        normal.swap(back->normal);
        object.swap(back->object);
        prim.swap(back->prim);
        age.swap(back->age);
    }

    static constexpr std::uint8_t kEmpty = 255;
    static constexpr std::uint8_t kOldest = 254;
};

/// Renders with options.reuse's approximate mode into `out`, refreshing `cache`. `boxes` and
/// `versions` are the objects' world boxes and geometry versions now (FramePipeline).
void trace_frame_approximate(const TraceInputs& in, const Camera& camera,
                             const TraceSettings& options, std::span<const bvh::Aabb> boxes,
                             std::span<const std::uint64_t> versions, PixelCache& cache,
                             TraceScratch& scratch, RenderedFrame& out);

}  // namespace dynrt::detail
