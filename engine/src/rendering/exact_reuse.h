#pragma once
// Exact reuse of the previous trace's pixels (TraceSettings::reuse, PixelReuse::exact): when
// the camera, lights, image settings and object set are those of the last trace, only the
// rays that may meet the space that changed (changed_space.h: the old and new boxes of the
// objects that moved or changed material) are traced again, tile by tile:
//
//   1. a tile whose primary pyramid (or, when every pixel hit, the hull of the eye and its hit
//      points) misses the changed space keeps its hits; otherwise each primary ray is tested
//      up to its previous hit, and the rays that may meet it are traced again;
//   2. each light's shadow rays of the tile are tested as the hull of the light and their end
//      points, then one by one; those that may meet the changed space, and those of re-traced
//      pixels, are traced again, and the others keep their previous verdict;
//   3. a tile where anything was traced again is shaded again (the same kernel on the same
//      inputs gives the same bits for the pixels that kept theirs);
//   4. with secondary rays (renderer.h), a reflection or refraction may show any change from
//      anywhere: when anything changed, every pixel whose hit spawns them is traced again
//      from its hit on (its reflection and refraction rays, their shadows), and its tile
//      shaded again.
//
// Every other pixel keeps the RenderedFrame's values, so the frame is bit-identical to a full
// render; tests/exact_reuse_test.cpp renders sequences both ways. Anything else that changed
// (the first frame, the camera, a light, the image settings, another frame object, objects
// removed from the end of the scene) makes a full trace, which fills the memory for the next.

#include "dynrt/bvh/aabb.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/ray_packet.h"
#include "rendering/frame_tracer.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dynrt::detail {

/// What the last trace with exact reuse left for the next one.
struct ReuseMemory {
    bool valid = false;
    /// RenderedFrame::reuse_stamp of the frame it wrote.
    std::uint64_t stamp = 0;
    Camera camera;
    TraceSettings settings;
    std::vector<PointLight> lights;
    std::vector<packet::PhongMaterial> materials;
    /// The scene's materials, for their reflection and refraction terms and diffuse maps.
    std::vector<Material> scene_materials;
    std::vector<std::int32_t> object_material;
    /// Per object: its world box and its geometry version (FramePipeline) at that trace.
    std::vector<bvh::Aabb> object_boxes;
    std::vector<std::uint64_t> object_versions;
    /// Per object: the world boxes of a cut through its tree at that trace (the boxes a
    /// change is tested against, tighter than object_boxes; SceneAccel::object_world_parts).
    std::vector<std::vector<bvh::Aabb>> object_parts;
    /// Per tile: the box of its hit points and whether every pixel hit; per tile and light
    /// (tile * lights + l): the lanes the light reached, and the box of its shadow rays' ends.
    std::vector<bvh::Aabb> hit_points;
    std::vector<std::uint8_t> all_hit;
    std::vector<packet::LaneMask> visible;
    std::vector<bvh::Aabb> shadow_ends;
};

/// This trace's inputs besides the trees, as the reuse decision compares them.
struct ReuseInputs {
    const Camera& camera;
    const TraceSettings& settings;
    std::span<const PointLight> lights;
    std::span<const packet::PhongMaterial> materials;
    std::span<const Material> scene_materials;
    std::span<const std::int32_t> object_material;
    std::span<const bvh::Aabb> object_boxes;
    std::span<const std::uint64_t> object_versions;
    std::uint64_t frame_stamp;  ///< the RenderedFrame's reuse_stamp
    /// Per object, its parts now (ReuseMemory::object_parts); objects past its end are
    /// tested as their box.
    std::span<const std::vector<bvh::Aabb>> object_parts;
};

/// What the trace does: all of it, or the rays meeting `changed` (none when it is empty).
struct ReusePlan {
    bool full = true;
    /// Why, for the report: "first frame", "camera moved", "2 objects changed", ...
    std::string reason;
    std::vector<bvh::Aabb> changed;
};

/// ReusePlan::reason of a full trace because the camera moved.
inline constexpr const char* kCameraMoved = "camera moved";

ReusePlan plan_exact_reuse(const ReuseMemory& memory, const ReuseInputs& now);

/// Traces the frame as `plan` says into `out` (its pixels kept where nothing changed), sets
/// out.stats' trace fields and the reuse fields, and records `memory`'s per-tile part
/// (the caller records the rest with remember_inputs). `sample`: which sample of its pixels
/// the frame is (a pass of several samples per pixel keeps a memory of its own; sampled_frame.h).
void trace_frame_reusing(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                         const ReusePlan& plan, ReuseMemory& memory, TraceScratch& scratch,
                         RenderedFrame& out, const SamplePass& sample = {});

/// Records `now` in `memory` after a trace with exact reuse and stamps `out` and it.
void remember_inputs(const ReuseInputs& now, ReuseMemory& memory, RenderedFrame& out);

}  // namespace dynrt::detail
