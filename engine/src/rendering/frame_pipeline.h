#pragma once
// The one path every frame takes once its objects are posed: plan and carry out the update of
// the trees (update_plan.h, SceneAccel), trace primary and shadow rays, shade (trace_frame),
// and the frame's figures. Two front ends feed it: Renderer, which poses a Scene's frames and
// resolves their camera (`dynrt render`, `dynrt bench`, the tests), and the library API
// (dynrt/dynrt.h), whose caller moves the meshes. Work that reuses pixels between frames or
// splits a frame across processes belongs here, so that every front end gets it.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/engine/texture_figures.h"
#include "dynrt/engine/texture_set.h"
#include "dynrt/engine/trace_backend.h"
#include "dynrt/engine/update_plan.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/scene/scene.h"
#include "rendering/approximate_reuse.h"
#include "rendering/exact_reuse.h"
#include "rendering/frame_tracer.h"
#include "rendering/object_versions.h"
#include "rendering/sampled_frame.h"
#include "rendering/scene_textures.h"
#include "update/scene_accel.h"

#include <tbb/task_group.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

namespace dynrt {

class FramePipeline {
public:
    /// Brings the trees of `scene`'s objects to `states` (one per object, scene order) under
    /// `policy`, and records the update's figures, which later traces report with theirs.
    /// `frame_clock` started when the caller began the frame (before posing), so that
    /// update_ms is everything the update did besides building trees: posing, checks,
    /// gathering triangles. `scene` and what `states` and `fixed` borrow must stay alive and
    /// unchanged until the next update. Returns the update's figures. On an exception the
    /// trees may be half updated: clear() before the next update.
    const FrameStats& update(const Scene& scene, std::span<const ObjectState> states,
                             const FixedPositions& fixed, const UpdatePolicy& policy, int frame,
                             const Stopwatch& frame_clock);

    /// Traces and shades the last update's trees as `camera` sees them under `options` (image
    /// size, tracer, shading) and `lights` (and the environment's suns when
    /// options.environment_lights asks for them), into `out` (buffers reused). out.stats holds the
    /// update's figures and the trace's; total_ms is the update's wall time plus the trace's.
    /// Materials are read from `scene` as it is now; its textures (TextureSet) are opened at
    /// the first trace of a scene and kept while the same scene's materials map the same
    /// textures the same way (opened again when one maps another, or a new material maps
    /// one: the library API's one scene gains textures and textured meshes over its life). A
    /// caller that replaces a Scene::textures entry in place must clear(). Throws std::logic_error
    /// before any update and std::invalid_argument for a degenerate camera.
    void trace(const Scene& scene, const Camera& camera, const TraceSettings& options,
               std::span<const PointLight> lights, RenderedFrame& out);

    /// Stops the trace running now, if one is, from any thread: its parallel loops start no
    /// more work (a oneTBB task group's cancellation), it returns with out.stats.cancelled and
    /// an incomplete image, and what pixel reuse remembered is forgotten (the next trace is a
    /// full one). Does nothing between traces. Thread-safe.
    void cancel();
    /// How far the trace running now has come (the last one's between traces). Thread-safe.
    RenderProgress progress() const { return progress_.now(); }

    /// Traces with `backend` (not null) instead of dynrt's own tracer, or with dynrt's again
    /// (null): each update then also loads its frame into the backend. Forgets the trees, as
    /// clear_trees().
    void use_backend(std::shared_ptr<FrameBackend> backend);

    /// Whether an update has completed since construction or clear().
    bool updated() const { return updated_; }
    /// The last update's figures.
    const FrameStats& update_stats() const { return update_stats_; }
    /// The trees of the last update (for ray queries and bounds).
    const SceneAccel& accel() const { return accel_; }

    /// Forgets every tree, the pixel memory and the opened textures: the next update builds
    /// from scratch and the next trace opens the scene's textures again.
    void clear();
    /// Forgets every tree and the pixel memory, and keeps the textures opened (with what
    /// OpenImageIO has read of them): for benchmarks that time a full build per frame, whose
    /// runs would otherwise each time the reading of every texture again.
    void clear_trees();
    /// Forgets one object's tree (its triangles were replaced, or it was removed).
    void invalidate(std::size_t object);
    /// Frees what is kept for an object the last update saw without triangles (a removed
    /// mesh's slot): SceneAccel::release, and its boxes for exact reuse.
    void release(std::size_t object);
    /// Object `object` is a new one in a freed slot: SceneAccel::renew, and its version moves
    /// at the next update (as invalidate), so that pixels showing the slot are traced again.
    void renew(std::size_t object);

    /// Heap bytes held for the objects: the trees (SceneAccel::memory_bytes), the per-object
    /// records of shading and exact reuse, and the opened textures (TextureSet::bytes, every
    /// MIP level). The image-sized buffers of traces are left out: they depend on the image
    /// size, not on the objects.
    std::size_t memory_bytes() const;

    /// The figures of the textures held (opened at the first trace that needed them, once per
    /// TextureSet: texture_figures.h); zeros when none are (no trace yet, a scene mapping no
    /// texture, or after clear()).
    TextureFigures texture_figures() const;

private:
    SceneAccel accel_;
    /// Another tracer behind the seam, or null for dynrt's CpuTracer.
    std::shared_ptr<FrameBackend> backend_;
    FrameStats update_stats_;
    double update_wall_ms_ = 0.0;
    bool updated_ = false;
    /// The scene's materials as the shading kernel reads them and each object's material index,
    /// refreshed per trace (kept to avoid reallocating), and the trace's own buffers.
    std::vector<packet::PhongMaterial> materials_;
    std::vector<std::int32_t> object_material_;
    TraceScratch scratch_;
    /// The shading kernel's view of `scene`'s materials and each object's material index,
    /// into materials_ and object_material_.
    void view_materials(const Scene& scene);
    /// trace() without its cancellation: what a trace does.
    void run_trace(const Scene& scene, const Camera& camera, const TraceSettings& options,
                   std::span<const PointLight> given_lights, RenderedFrame& out);
    /// The running trace's task group context (cancel()), or null between traces.
    std::mutex cancel_mutex_;
    tbb::task_group_context* running_ = nullptr;
    /// The tile passes of the trace running now (progress()).
    detail::FrameProgress progress_;
    /// `lights` and, when options ask for them, the environment's suns (environment_lights.h)
    /// after them: the lights a trace shades with. Refuses a count out of range, or suns
    /// without a map. The span borrows frame_lights_ until the next call.
    std::span<const PointLight> with_environment_lights(std::span<const PointLight> lights,
                                                        const TraceSettings& options);
    /// The environment's suns, for the map and count they were made from.
    std::vector<PointLight> environment_suns_;
    std::pair<std::shared_ptr<const EnvironmentMap>, int> environment_suns_key_{nullptr, 0};
    std::vector<PointLight> frame_lights_;
    /// The textures of the scene traced last, kept between traces.
    detail::SceneTextures textures_;
    /// What pixel reuse compares between traces: each object's geometry version, and its parts.
    ObjectVersions versions_;
    /// Exact reuse's memory of the last trace with it; with several samples per pixel, one
    /// per sample.
    detail::ReuseMemory reuse_;
    detail::SampledReuse sampled_reuse_;
    /// Exact reuse: the last trace was a full one because the camera had moved, and its
    /// camera (a camera that keeps moving is traced without recording reuse memory).
    bool camera_moving_ = false;
    Camera last_camera_;
    /// The render cache's and frameless mode's per-pixel samples.
    detail::PixelCache pixel_cache_;
};

}  // namespace dynrt
