#pragma once
// Renders one frame: pose the scene, build the BVH, trace primary rays in 16x16 tiles, trace a
// shadow ray per hit and light, shade with Phong. Each stage is timed into FrameStats.
//
// Shading (reproduced by the reference renderer in tests/): at a hit with unit geometric normal
// n turned to face the eye, unit shading normal s (below), view vector v = -dir, material
// (kd, ks, shininess), ambient a, where kd is the material's diffuse colour times, when it maps
// a texture (Material::diffuse_map) that can be read and the object has texture coordinates,
// the texture's linear colour at the hit's interpolated coordinates over the footprint
// texture_footprint gives (dynrt/engine/texture_set.h, docs/rendering.md "Textures"):
//   color = a * kd + sum over lights L with n.l > 0, s.l > 0 and the light visible from the hit:
//           I_L * (kd * (s.l) + ks * max(0, r.v)^shininess),  r = 2 (s.l) s - l,
// plus the material's emission, l the unit vector to the light; a * kd is replaced by the
// material's own ambient colour times the texture's colour where it gives one
// (Material::ambient, BART's am times ka). A miss is the background colour, or the
// environment map's radiance along the ray (TraceSettings::environment). A hit on a cut-out
// material (glTF alphaMode MASK) where its alpha is below the cutoff is no hit: every ray goes
// on through it (dynrt/engine/alpha_mask.h; docs/rendering.md "Alpha").
//
// Lights (PointLight; glTF's KHR_lights_punctual): I_L = intensity * color * falloff, per
// channel. A point or area light's l points at it (an area light's sample), a spot's too, a
// directional light's is -direction everywhere. The falloff is 1 (dynrt's own lights by
// default: no distance falloff), times 1 / d^2 when inverse_square (glTF's point and spot
// lights), times clamp(1 - (d / range)^4, 0, 1) when range > 0, times a spot's
// clamp((-l . axis - cos outer) / max(0.001, cos inner - cos outer), 0, 1)^2 (glTF's cone),
// d the distance to the light. Shadow rays run from the light to the hit's offset origin over
// t in [0, 1], or for a directional light from the origin toward it over [0, +inf).
// A shadow ray is traced only where the light can add something: n.l > 0, s.l > 0, and a
// falloff and intensity other than 0 (the others add exactly nothing); shadow_rays counts
// them, shadow_rays_back_side, shadow_rays_shading_side and shadow_rays_dark_light (outside a
// spot's cone, past a range, intensity 0) the ones left out.
//
// Shading normals (Phong 1975, "Illumination for Computer Generated Pictures": the normal
// interpolated across the triangle), when TraceSettings::smooth_normals is on (the default)
// and the hit object has vertex normals (Mesh::normals: the file's, or area-weighted ones,
// dynrt/scene/vertex_normals.h; posed with the mesh, anim/posed_scene.h): with the hit's
// barycentrics (u, v) and the triangle's world-space vertex normals n0, n1, n2,
//   s = normalize((1 - u - v) n0 + u n1 + v n2), negated when s.n < 0,
// so s lies on the eye's side exactly when n does, whichever way the file's normals and the
// triangles' winding point. Where the interpolated vector's squared length is at most
// kMinShadingNormalLength2 (opposed vertex normals), or the object has none, or smooth normals
// are off, s = n (flat shading, the model as it was before vertex normals). s lights the
// Phong terms and takes the reflection and refraction directions below; n alone decides where
// shadow and secondary rays start (their offsets), so a smooth normal never lets a ray start
// inside its own surface. A light with n.l > 0 but s.l <= 0 adds nothing (the shading normal
// faces away from it), and casts no shadow ray.
// Shading runs per 16x16 tile in SIMD for both tracers (packet::shade, packet/), in float, with
// max(0, r.v)^shininess from packet/include/dynrt/packet/simd_pow.h (absolute error below
// 6 * 2^-24 per light): the reference renderer's double-precision colours are matched within
// tests/reference's colour tolerance, not bit for bit.
//
// Secondary rays (Whitted 1980, "An Improved Illumination Model for Shaded Display"), when
// TraceSettings::secondary.max_depth > 0 and a hit's material has reflectance kr or
// transmittance kt (dynrt::Material). At a hit of a ray with unit direction d, facing normal n
// as above, hit point P from the barycentrics and m = triangle_magnitude of the triangle:
//   the ray enters the surface when the winding normal (v1 - v0) x (v2 - v0) points against d
//   (then n is the winding normal) and leaves it otherwise; eta = 1 / ior entering, ior
//   leaving; cos_i = -d.n; sin2_t = eta^2 (1 - cos_i^2); cos_t = sqrt(1 - sin2_t).
//   kt = 0: reflected weight wr = kr, no refraction.
//   kt > 0 and sin2_t > 1 (total internal reflection): wr = kr + kt, no refraction.
//   kt > 0 otherwise: the exact Fresnel reflectance of unpolarised light at a dielectric,
//   F = (rs^2 + rp^2) / 2, rs = (eta cos_i - cos_t) / (eta cos_i + cos_t),
//   rp = (cos_i - eta cos_t) / (cos_i + eta cos_t) (0 when ior is 1: a matched interface
//   reflects nothing, which Schlick's approximation misses at grazing angles);
//   wr = kr + F kt, refracted weight wt = (1 - F) kt.
//   color(ray) = local(hit) + wr color(reflected ray) + wt color(refracted ray), where local
//   is the Phong formula above with v = -d, and a miss gives the background.
//   Shadows through glass: with max_depth > 0, a shadow ray blocked only by transmissive
//   surfaces (kt > 0) still reaches its light, I_L multiplied by the kt of each one it
//   crosses, unrefracted (tile_tracing.h, through_glass).
//   reflected ray: origin offset_along_normal(P, n, m), direction normalize(d - 2 (d.s) s);
//   refracted ray: origin offset_along_normal(P, -n, m), direction
//   normalize(eta d + (eta cos_i - cos_t) s); both with t in [0, +inf).
//   cos_i, Fresnel and the directions take the shading normal s (cos_i = -d.s); when that
//   split fails (d.s >= 0, or the reflected direction does not leave above the geometric
//   surface, reflected.n <= 0, or the refracted one does not go below it, refracted.n >= 0:
//   a smooth normal bent past the ray near a silhouette), the whole split, weights included,
//   is made with n instead. With flat shading s = n and this never differs.
// Camera rays have depth 0 and a ray spawned at a hit of a depth-k ray has depth k + 1; a ray
// is traced only when its depth is <= max_depth and the product of the weights along its path
// has a channel >= secondary.cutoff. Every hit at every depth casts shadow rays as above;
// they pass through transmissive surfaces, filtered by them (no caustics: "Shadows through
// glass" above).
//
// Two tracers give identical frames (hits, shadows, hence every output buffer, bit for bit):
// the packet tracer (the default), which traces each 16x16 tile as one 256-ray packet and its
// shadow rays toward each light as another (packet/), and the single-ray tracer
// (bvh::intersect_closest and bvh::intersect_any per pixel), kept as the reference and for
// comparison.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/binned_sah_builder.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/environment_map.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/pixel_cost.h"
#include "dynrt/engine/pixel_reuse.h"
#include "dynrt/engine/pixel_sampling.h"
#include "dynrt/engine/render_progress.h"
#include "dynrt/engine/secondary_ray_log.h"
#include "dynrt/engine/trace_backend.h"
#include "dynrt/engine/texture_figures.h"
#include "dynrt/engine/update_plan.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/packet/packet_config.h"
#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace dynrt {

/// An interpolated vertex normal whose squared length is at most this points nowhere in
/// particular (its vertex normals oppose each other): the geometric normal shades instead.
inline constexpr float kMinShadingNormalLength2 = 1e-6f;

/// Which tracer renders the primary and shadow rays; both give the same frame.
enum class Tracer {
    packet,  ///< 16x16 ray packets (packet/)
    single,  ///< one ray at a time (bvh::intersect_closest, bvh::intersect_any)
};

/// Whitted reflection and refraction rays (the model is at the top of this file).
struct SecondaryRays {
    /// Deepest ray traced: 0 traces camera and shadow rays only; 5 follows a camera ray
    /// through up to five mirror or glass bounces.
    int max_depth = 5;
    /// A ray is traced only when a channel of its path's weight is at least this (1/256: it
    /// could not change an 8-bit pixel by more than one step).
    float cutoff = 1.0f / 256.0f;
    /// A frame's secondary rays of one depth are sorted into packets of up to 256 by kind,
    /// direction octant and origin; those of a packet sharing an octant are traced as one
    /// packet when there are at least this many of them, otherwise one by one
    /// (bvh::intersect_*), which gives the same bits. 0 always uses packets; above 256 never.
    int min_packet_rays = 32;
};

/// How a frame is traced and shaded: the trace stage's settings (FramePipeline::trace, the
/// library API's render).
struct TraceSettings {
    int width = 1024;
    int height = 1024;
    Tracer tracer = Tracer::packet;
    /// Adaptive sampling (approximate; packet tracer only): 0, the default, traces every
    /// pixel. Above 0 each 16x16 tile is first traced at 9 samples (columns and rows 0, 8 and
    /// its last); the tile is filled by bilinear interpolation when in each of its 4 cells the
    /// samples agree (all miss, or all hit one object with the same shadows, normals within
    /// 1 - dot <= tolerance and colours within tolerance per channel) and no other object's
    /// box reaches into the cell's view frustum; otherwise the whole tile is traced exactly.
    /// Larger is faster and less exact. What can still go wrong is in docs/reuse.md "Approximate
    /// rendering".
    float adaptive_tolerance = 0.0f;
    /// Samples per pixel, their reconstruction filter and adaptive anti-aliasing
    /// (pixel_sampling.h): one sample at each pixel's centre by default. Above one, each sample
    /// is a pass of the whole pipeline and area lights are sampled once per pixel sample;
    /// pixel reuse then traces every pixel (the reason "samples per pixel"); interpolating
    /// adaptive sampling (adaptive_tolerance) is refused, and so is adaptive anti-aliasing
    /// over a tile share (it compares pixels with their neighbours).
    PixelSampling sampling;
    /// How the frame reuses the previous trace's pixels (pixel_reuse.h): exact by default,
    /// which re-traces only the rays that may meet what changed and gives the same bits as a
    /// full render. Exact reuse needs the same RenderedFrame as the previous trace, unchanged
    /// by the caller (RenderedFrame::reuse_stamp); adaptive sampling turns it off.
    ReuseSettings reuse;
    /// Reflection and refraction rays (the model is at the top of this file).
    SecondaryRays secondary;
    /// When set, every reflection and refraction packet traced is appended to it (for
    /// benchmarks that replay them; borrowed, must outlive the trace).
    SecondaryRayLog* secondary_log = nullptr;
    /// The packet tracer's culling stages and SIMD width (ignored by the single-ray tracer).
    packet::PacketConfig packet;
    /// Count the tracer's work into FrameStats (ray_triangle_tests, nodes_visited and, for the
    /// packet tracer, ray_triangle_culled); off by default, as counting costs a little time.
    bool count_packet_work = false;
    /// Test each packet of shadow rays first against the triangles that last blocked rays
    /// leaving its light in the same directions (an occluder cache per light, for one frame;
    /// packet tracer only; rendering/occluder_cache.h). The same image either way. Off by
    /// default: on BART kitchen it answered a quarter of the shadow rays before any traversal
    /// and still cost 5% more CPU time (those rays are the ones a traversal from the light
    /// settles in its first leaves); `--occluder-cache on` to measure it on other scenes.
    bool occluder_cache = false;
    /// Fill RenderedFrame's per-pixel hit buffers (depth, object, prim, normal) as well as its
    /// colour. Off, they are left empty and a frame writes 12 bytes per pixel instead of 36:
    /// on the bundled scene those writes were most of the shading stage's time.
    bool hit_buffers = true;
    /// Fill RenderedFrame::cost, each pixel's camera-ray work in the frame's trees
    /// (dynrt/engine/pixel_cost.h; `--aov cost`, the viewer's cost view): a pass of its own
    /// after the frame, outside the stage times. Off by default.
    bool pixel_cost = false;
    glm::vec3 background{0.05f, 0.06f, 0.08f};
    /// What rays that leave the scene see, by direction, camera and secondary rays alike
    /// (dynrt/engine/environment_map.h; `--environment`); null: the background colour.
    std::shared_ptr<const EnvironmentMap> environment;
    /// The environment as this many directional lights besides the frame's own
    /// (dynrt/engine/environment_lights.h, an image-based light by median cut;
    /// `--environment-lights`), at most kEnvironmentLightsMax; 0 (the default): the environment
    /// is seen but lights nothing. Needs `environment`. With it on, the default light is left
    /// out (effective_lights): the sky is the light.
    int environment_lights = 0;
    /// Ambient term, as a fraction of the diffuse colour.
    float ambient = 0.08f;
    /// Shade with the objects' interpolated vertex normals ("Shading normals" at the top of
    /// this file; `--normals smooth`, the default); false shades every hit with its triangle's
    /// geometric normal (`--normals flat`), and a Renderer then poses no normals at all.
    bool smooth_normals = true;
    /// Which of the frame's 16x16 tiles this trace renders: all of them by default, or one
    /// process's interleaved share when a frame is split across processes (`mpirun dynrt
    /// render --distribute tiles`, the library API's RenderSettings::tile_share). The pixels
    /// of other tiles are left as they were, and the caller may write them (a gather does)
    /// without disturbing exact reuse, which reads the share's alone; the stats count the
    /// share's rays and pixels. Exact reuse works per share (the same share frame after
    /// frame); the approximate reuse modes (render cache, frameless) need the whole image and
    /// refuse a share.
    packet::TileShare tiles;
};

/// A Renderer's settings, stage by stage: how the trees are updated (UpdatePolicy: build
/// configuration, exploding objects' cost ratio, rebuild threshold), how frames are traced
/// (TraceSettings), how the scene is posed, and its lights.
struct RenderOptions : UpdatePolicy, TraceSettings {
    /// How the scene is animated: frame rate, clips, forced motion classes
    /// (skip_fixed_positions is ignored: the renderer never poses static or rigid vertices
    /// after their one build).
    anim::PoseSettings pose;
    /// Empty: one default light at c + 4 R normalize(-0.5, 1.0, 0.8) (scene box centre c,
    /// half-diagonal R) unless the scene defines its own.
    std::vector<PointLight> lights;
    /// Makes the tracer behind the trace seam for each Renderer made with these options
    /// (Renderer::use_backend; `--backend embree-...`); empty: dynrt's own.
    std::function<std::shared_ptr<FrameBackend>()> backend;
    /// Level of detail (`--lod PIXELS`), an approximation, off at 0: each frame, every static
    /// or rigid object that is neither skinned nor morphed, with a mesh of at least 256
    /// triangles that is not a soup, is traced with the coarsest of its simplified meshes
    /// (each a quarter of the one before, made once by meshoptimizer's simplifier) whose error
    /// is estimated to cover at most this many pixels where the object comes nearest the
    /// camera. Those objects are then traced as instances (rigid), never in the static group,
    /// and the frame's `prim` buffer numbers the triangles of the level traced. Chosen by
    /// render(), which knows the camera; update() alone keeps the levels it had.
    /// docs/reuse.md, "Level of detail".
    float lod_pixels = 0.0f;
};

/// Per-pixel results, row-major with y = 0 the top row.
struct RenderedFrame {
    int width = 0;
    int height = 0;
    std::vector<glm::vec3> color;   ///< linear RGB
    // The hit buffers: empty when TraceSettings::hit_buffers is off.
    std::vector<float> depth;       ///< distance from the eye along the unit ray; +inf on a miss
    std::vector<std::int32_t> object;  ///< object index in scene order; -1 on a miss
    std::vector<std::int32_t> prim;    ///< triangle index within the object; -1 on a miss
    /// Unit geometric normal facing the eye (not the shading normal); 0 on a miss.
    std::vector<glm::vec3> normal;
    /// Each pixel's camera-ray work in the frame's trees (dynrt/engine/pixel_cost.h), when
    /// TraceSettings::pixel_cost is on; empty otherwise.
    std::vector<PixelCost> cost;
    FrameStats stats;
    /// Set by the trace that filled this frame: the next trace reuses its pixels only when it
    /// is the frame that trace wrote (TraceSettings::reuse). A caller that edits the buffers
    /// between frames sets it to 0, which makes the next trace a full one.
    std::uint64_t reuse_stamp = 0;
};

/// Where the frames of a sequence get their camera: one camera for every frame, or the scene's
/// own (its first camera, evaluated at each frame as the renderer poses it, so it costs no
/// posing of its own).
struct CameraSource {
    bool from_scene = false;
    /// The camera of every frame, when not from_scene.
    Camera camera;

    static CameraSource fixed(const Camera& camera) { return CameraSource{false, camera}; }
    static CameraSource scene() { return CameraSource{true, Camera{}}; }
};

/// Renders the frames of a scene: the engine's frame loop for scenes (`dynrt render`,
/// `dynrt bench`, the tests). Each frame is posed once, its camera resolved from the pose, its
/// trees updated as the update planner decides (dynrt/engine/update_plan.h), then traced and
/// shaded; the library API runs the same path from its update on (ARCHITECTURE.md). Keeps each object's tree from frame to frame and gives it the
/// cheapest correct update its motion class allows (static: never touched again; rigid: only
/// its instance moves; deformable: refit, rebuilt when the refit's SAH cost has degraded past
/// UpdatePolicy::rebuild_threshold; exploding: rebuilt), then traces primary and shadow rays
/// through the two-level structure. The trees belong to one scene: rendering another Scene
/// object starts afresh, and a caller that edits a scene in place between frames must call
/// reset(). Not thread-safe: one call at a time; each runs in parallel on the caller's oneTBB
/// arena.
class Renderer {
public:
    explicit Renderer(RenderOptions options);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    const RenderOptions& options() const { return options_; }

    /// Replaces the options of later frames, keeping the trees, the pose state and the opened
    /// textures (the viewer's settings panel): the next update plans with the new policy, the
    /// next trace traces with the new settings (exact reuse re-traces what they change). The
    /// pose settings stay those the renderer was made with, and so does the backend (change it
    /// with use_backend). Throws std::invalid_argument as the constructor does, changing nothing.
    void set_options(RenderOptions options);

    /// Renders `scene` at `frame` seen by `camera` into `out` (its buffers are reused):
    /// update(scene, frame), then trace(camera, out).
    /// Throws SceneError for non-finite posed geometry (naming object and frame) and
    /// std::invalid_argument for a degenerate camera or bad pose settings.
    void render(const Scene& scene, const Camera& camera, int frame, RenderedFrame& out);

    /// The same with the camera `view` gives at `frame` (the scene's own camera is read from
    /// the pose this update makes). Returns the camera the frame was traced with. Throws as
    /// render above, and std::logic_error when `view` asks for the scene's camera and the scene
    /// has none.
    Camera render(const Scene& scene, int frame, const CameraSource& view, RenderedFrame& out);

    /// Evaluates `scene` at `frame` and brings the trees up to date. `scene` must stay alive
    /// and unchanged until the next update, reset or destruction. With lod_pixels, each
    /// object keeps the level of detail the last render() chose (there is no camera to choose).
    void update(const Scene& scene, int frame);

    /// Traces and shades the frame of the last update as seen by `camera`. Its stats hold the
    /// update's figures too. Throws std::logic_error before any update.
    void trace(const Camera& camera, RenderedFrame& out);

    /// Stops the trace running now, from any other thread: it returns soon with
    /// out.stats.cancelled set and an incomplete image (not to be shown); the trees are whole
    /// (an update is never stopped) and the next frame traces in full. Does nothing between
    /// frames. Thread-safe.
    void cancel();
    /// How far the frame being traced has come: its tile passes done and in all
    /// (dynrt/engine/render_progress.h); the last frame's between frames. Thread-safe: another
    /// thread may poll it while render() runs.
    RenderProgress progress() const;

    /// The scene as evaluated by the last update (its camera, transforms, motion classes).
    /// Static and rigid objects' positions are left empty. Throws std::logic_error before any
    /// update.
    const anim::PosedScene& posed() const;

    /// Traces the rays of `log` (a frame's secondary rays, TraceSettings::secondary_log)
    /// through the last update's trees the way the renderer traced them (each logged packet's
    /// rays of a direction octant as a packet when there are at least
    /// secondary.min_packet_rays of them, the rest one by one, in parallel over the packets) and returns the wall time in ms. With `hits`, fills one
    /// closest hit per ray in log order. For benchmarks; throws std::logic_error before any
    /// update.
    double trace_logged_rays(const SecondaryRayLog& log, std::vector<bvh::InstanceHit>* hits = nullptr) const;

    /// The figures of the scene's textures as the renderer holds them (count, bytes, load ms:
    /// texture_figures.h): read at the first trace of the scene and kept until reset(), so a
    /// sequence reports them once. Zeros before that trace and for a scene mapping no texture.
    TextureFigures texture_figures() const;

    /// Forgets the trees and the scene's opened textures: the next update builds every object
    /// afresh and the next trace reads the textures again. Needed after editing a scene in
    /// place.
    void reset();

    /// Forgets the trees and the previous frame's pixels (as reset()), but keeps the same
    /// scene's pose state and opened textures, with what has been read of them: benchmarks use
    /// it to time a full build and trace per run without timing the textures' first reading,
    /// a start-up cost a render pays once.
    void forget_trees();

    /// Traces every later frame with `backend` (behind the trace seam: Embree, say) instead
    /// of dynrt's own tracer, or with dynrt's again for null: the same frames, rays and
    /// shading, another tracer's hits. Each update then also loads its frame into the backend
    /// (FrameStats::backend_load_ms). Forgets the trees, as forget_trees().
    void use_backend(std::shared_ptr<FrameBackend> backend);

private:
    /// update() in two steps, so that render() can read the scene's camera from the pose
    /// before the trees are updated with the levels of detail it sees.
    void pose(const Scene& scene, int frame);
    void update_trees(int frame, const Camera* camera);

    struct State;
    RenderOptions options_;
    std::unique_ptr<State> state_;
};

/// The light a scene without lights gets: c + 4 R normalize(-0.5, 1.0, 0.8) for the box's
/// centre c and half-diagonal R.
PointLight default_light(const bvh::Aabb& scene_bounds);

/// World-space bounds of `scene` at frame 0 (for the default camera and light).
bvh::Aabb scene_bounds(const Scene& scene);

/// World-space bounds of `scene` over frames first..last as `pose` plays them, from at most
/// `samples` frames spread evenly over the range (first and last included), so that a default
/// camera framing them keeps moving parts in the picture. A single frame, or a scene without
/// animation or motions, is posed once.
bvh::Aabb sequence_bounds(const Scene& scene, const anim::PoseSettings& pose, int first, int last,
                          int samples = 16);

/// `lights` as they are at `posed`'s frame: those on a node (glTF's, assimp's) moved with its
/// world matrix there, as Renderer::update poses them every frame; the others as they are.
std::vector<PointLight> lights_at(std::span<const PointLight> lights, const anim::PosedScene& posed);

/// The lights a render of `scene` uses under `options` (see RenderOptions::lights); with
/// environment lights on, no default light (FramePipeline adds the environment's suns to these).
std::vector<PointLight> effective_lights(const Scene& scene, const RenderOptions& options);

}  // namespace dynrt
