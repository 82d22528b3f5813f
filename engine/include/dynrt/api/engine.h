#pragma once
// dynrt::Engine, the library API for programs that move geometry themselves: a physics or
// robotics simulation adds its meshes once, changes vertices or transforms every step, calls
// update(), then renders a view or traces a batch of rays. docs/library-api.md "Library API" has a complete
// example; engine/examples/ has two more (a cloth and a lidar).
//
// One step:
//
//   engine.set_positions(cloth, positions);   // deformable: vertices moved
//   engine.set_transform(robot_arm, pose);    // rigid: only its transform moved
//   dynrt::FrameStats stats = engine.update(); // trees brought up to date (refit, rebuild...)
//   engine.render(view, image);                // and/or
//   engine.intersect(rays, hits);              // closest hits, or occluded(rays, flags)
//
// Per mesh, update() picks the cheapest correct action for its motion class, as the renderer
// does for animated scenes (docs/animation.md "Animation"): static meshes are built once, rigid ones only
// move their instance, deformable ones are refitted (rebuilt when the refit's SAH cost has
// degraded past EngineOptions::rebuild_threshold), exploding ones are rebuilt. A mesh added
// with Motion::automatic starts static and is raised to the class its changes show (never
// lowered).
//
// Thread safety. Between two update() calls the engine is read-only: intersect(), occluded()
// and render() may run concurrently from any number of threads (renders are serialized with
// each other; queries never wait). Every other call changes the engine and must not overlap
// any call on the same engine; the engine detects a change made while a query or render is
// running and throws Error::Code::invalid_state rather than race. Queries see the geometry of
// the last update(), never changes made since. Different engines are independent.
//
// Errors: every failing call throws dynrt::Error (api/error.h) and leaves the engine as it was
// (update() keeps the last good trees, with one exception described at
// Error::Code::invalid_geometry). std::bad_alloc passes through.

#include "dynrt/api/error.h"
#include "dynrt/api/export.h"
#include "dynrt/api/types.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/render_progress.h"
#include "dynrt/engine/texture_figures.h"

#include <oneapi/tbb/task_arena.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>


namespace dynrt {

/// How a mesh moves from step to step (docs/animation.md "Animation" explains the classes).
enum class Motion : std::uint8_t {
    /// Inferred from the calls: static until set_transform (then rigid) or set_positions (then
    /// deformable); a deformable mesh whose refits degrade past the threshold on 3 steps in a
    /// row is treated as exploding from then on.
    automatic,
    /// Never changes: set_positions and set_transform are refused.
    static_,
    /// Only its transform changes: set_positions is refused.
    rigid,
    /// Same triangles, vertices move: refitted.
    deformable,
    /// Anything goes: rebuilt at every step it changed.
    exploding,
};

/// "automatic", "static", "rigid", "deformable" or "exploding".
DYNRT_API const char* motion_name(Motion motion);

/// Who owns a mesh's vertex positions.
enum class Ownership : std::uint8_t {
    /// add_mesh and set_positions copy them: the caller's buffer may go away right after.
    copy,
    /// The engine keeps a pointer to the caller's buffer and reads it in add_mesh, in every
    /// update() that follows a set_positions call for the mesh, and in any update() that builds
    /// the mesh's tree: the first, and for a static mesh every one that rebuilds the static
    /// group (a static mesh added or removed, an automatic mesh raised from static). So the
    /// buffer must stay alive and hold the mesh's current positions until the mesh is removed
    /// or the engine destroyed, or until set_positions points the mesh at another buffer, and
    /// must not be written during a call on the engine. After writing new positions into the
    /// same buffer, call set_positions(mesh, buffer) to say so. Saves a copy per step.
    borrow,
};

/// A mesh as add_mesh takes it: its vertices and triangles, how it moves, who owns its
/// positions, where it is and what it is made of.
struct MeshDesc {
    /// For errors and the report; "mesh <id>" when empty.
    std::string name;
    /// x, y, z per vertex, in object space. Finite.
    std::span<const float> positions;
    /// Three vertex indices per triangle, each less than the vertex count. Always copied.
    std::span<const std::uint32_t> indices;
    /// Optional shading normals, x, y, z per vertex in object space (finite; normalised on
    /// use; docs/rendering.md "Shading normals"). Always copied. Empty: the engine computes area-weighted
    /// vertex normals from the positions, and again whenever they change.
    std::span<const float> normals;
    /// Optional texture coordinates, s, t per vertex (finite; s runs right and t down the image
    /// from its top-left corner, one unit across, glTF's TEXCOORD_0 convention). Always
    /// copied, and fixed for the mesh's life. Needed for a textured Surface.
    std::span<const float> texcoords;
    /// How the mesh moves, which decides how its tree is updated; automatic: inferred.
    Motion motion = Motion::automatic;
    /// Whether the engine copies the positions or borrows the caller's buffer.
    Ownership ownership = Ownership::copy;
    /// Object to world; finite and affine.
    Transform transform;
    /// Its material: Phong terms, reflectance, transmittance and ior (see Surface).
    Surface surface;
};

/// An image that surfaces may map (Surface::diffuse_texture): a file, a file's bytes, or the
/// caller's array of texels. Exactly one of `path`, `encoded` and the texels is given.
struct TextureDesc {
    /// For errors and warnings; the path, or "texture <id>", when empty.
    std::string name{};
    /// An image file (PNG, JPEG, BMP, TGA, EXR... whatever OpenImageIO reads), opened at the
    /// first render that shows it; a relative path is taken from the working folder at
    /// add_texture. A file that cannot be read is no error: that render warns
    /// on stderr, as `dynrt render` does (again at the first render after a surface has
    /// changed which texture it maps, as the engine then opens its textures afresh), and the
    /// surfaces mapping it show their diffuse colour alone. Empty when `encoded` or the texels
    /// hold the image.
    std::string path{};
    /// Or the bytes of an image file, copied by add_texture (the caller's buffer may go away
    /// right after). Empty when `path` names a file.
    std::span<const unsigned char> encoded{};
    /// The bytes' format as a MIME type ("image/png", "image/jpeg"); empty: told from their
    /// first bytes (PNG, JPEG, BMP, GIF, WebP).
    std::string mime_type{};
    /// Or the texels themselves, copied by add_texture: `width` x `height` texels (each side
    /// in [1, 16384]) of `channels` values (1 grey, 2 grey and alpha, 3 RGB, 4 RGBA; alpha is
    /// read by cut-outs only, Surface::alpha_cutoff), row by row from the image's top-left
    /// corner (texture coordinates (0, 0)),
    /// as 8-bit values (0-255 for 0 to 1) in `texels8` or as floats (finite, >= 0; 1 is full)
    /// in `texels_float`: one of the two, holding width * height * channels values. Float
    /// texels are usually linear: give them with `srgb` = false. All empty and 0 for a file
    /// or its bytes.
    std::span<const std::uint8_t> texels8{};
    std::span<const float> texels_float{};  ///< the texels as floats (see texels8)
    int width = 0;                          ///< texels across (see texels8)
    int height = 0;                         ///< texels down (see texels8)
    int channels = 0;                       ///< values per texel, 1 to 4 (see texels8)
    /// Texels are sRGB-encoded (8-bit colour images, glTF's base colour): lookups convert them
    /// to linear. False: they are linear already. Taken as given, whatever the source.
    bool srgb = true;
};

/// How an Engine runs and builds its trees; fixed for its life.
struct EngineOptions {
    /// Worker threads for update, render and ray batches: 0 runs them on the calling thread's
    /// oneTBB arena (all cores unless the caller limits it); N > 0 gives the engine an arena of
    /// its own with N threads.
    int threads = 0;
    /// Borrowed: run the engine's work in this arena (it must outlive the engine); overrides
    /// `threads`.
    tbb::task_arena* arena = nullptr;
    /// BVH builds (docs/benchmarking.md "Choosing the cost ratio"): cost of a triangle test per node visit,
    /// in (0, 1e6], and the largest leaf, in [1, 64].
    float cost_ratio = 1.0f;
    int leaf_size = 8;  ///< the most triangles a leaf holds (see cost_ratio)
    /// Exploding meshes are rebuilt with this cost ratio (shallower trees build faster).
    float cost_ratio_exploding = 0.3f;
    /// A deformable mesh is rebuilt when refitting has raised its tree's SAH cost above
    /// (1 + rebuild_threshold) times its cost at the last build; >= 0, +inf never rebuilds.
    double rebuild_threshold = 0.3;
    /// The static meshes' tree keeps only each triangle's index in its leaves and reads the
    /// corners from the meshes' vertices as rays reach them: about 40 bytes a triangle fewer,
    /// the same hits bit for bit, slower rays (1.08-1.16x on our scenes; `--leaves compact`,
    /// docs/animation.md "Compact leaves"). Borrowed static vertices are then copied once.
    /// Moving meshes keep full blocks here (`--leaves compact` makes theirs compact too): their
    /// vertices are borrowed for update() only, and compact leaves would read them later.
    bool compact_leaves = false;
    /// The static meshes' tree keeps its child boxes in 8-bit planes: 128 bytes a node instead
    /// of 256, the same hits bit for bit (`--nodes quantized`, docs/animation.md "Quantised
    /// nodes").
    bool quantized_nodes = false;
    /// A budget for the process's resident memory, in bytes (0: none): the static meshes'
    /// tree is then built with the fastest layout whose build is predicted to stay within it,
    /// and compact_leaves and quantized_nodes are ignored. update()'s stats give the choice
    /// (static_layout, static_layout_why; `--memory-budget`, docs/animation.md "Memory budget").
    std::size_t memory_budget = 0;
};

/// A caller-owned image the engine renders into. Row-major, y = 0 the top row.
struct ImageView {
    int width = 0;   ///< pixels across, >= 1
    int height = 0;  ///< pixels down, >= 1
    /// Linear RGB, 3 floats per pixel: width * height * 3 floats.
    std::span<float> rgb;
    /// Optional (empty to skip): distance from the eye along the unit ray, +inf on a miss;
    /// width * height floats.
    std::span<float> depth = {};
    /// Optional (empty to skip): the MeshId value hit, or -1 on a miss; width * height.
    std::span<std::int32_t> mesh = {};
};

/// What Engine::render draws besides the view: lights, background, reuse, secondary rays,
/// normals and the share of the image.
struct RenderSettings {
    /// Empty: one light above and behind the eye's side of the scene (the renderer's default
    /// light, docs/rendering.md "Shading").
    std::vector<Light> lights;
    Vec3 background{0.05f, 0.06f, 0.08f};  ///< the colour of pixels whose ray hits nothing
    /// An equirectangular image file (.exr, .hdr, ...) that rays leaving the scene see instead
    /// of the background, camera rays and reflections alike (docs/rendering.md "Background and
    /// environment"); empty: none. Read once and kept while the path and scale stay the same.
    std::string environment;
    float environment_scale = 1.0f;  ///< what the environment's texels are multiplied by, >= 0
    /// The environment as this many directional lights besides `lights` (an image-based light
    /// by median cut, docs/rendering.md "Background and environment"), at most 256; with it,
    /// no default light when `lights` is empty. 0 (the default): the environment lights nothing.
    int environment_lights = 0;
    /// Ambient term, as a fraction of the diffuse colour.
    float ambient = 0.08f;
    /// Exact reuse of the previous render's pixels (docs/reuse.md "Reusing pixels between frames"):
    /// when the view, image size, lights and settings are those of the previous render, only
    /// the pixels whose rays may meet what changed since (meshes moved, removed, added, or a
    /// surface changed) are traced again; the image is bit-identical to a full render. False
    /// traces every pixel.
    bool reuse_pixels = true;
    /// Reflection and refraction rays for surfaces with reflectance or transmittance (docs/rendering.md
    /// "Reflection and refraction"): the deepest bounce traced, 0 to 64 (0: none), and the
    /// path weight, in [0, 1], below which a secondary ray is not traced.
    int max_depth = 5;
    float cutoff = 1.0f / 256.0f;  ///< the path weight below which no secondary ray is traced
    /// Shade with the meshes' vertex normals interpolated across each triangle (given in
    /// MeshDesc::normals or computed); false: with each triangle's own normal (flat).
    bool smooth_normals = true;
    /// Render only tile share `tile_share` of `tile_shares` (dynrt/api/distribute.h), for a
    /// program whose processes each render part of a frame: the pixels tile_share_pixels names
    /// are written, the others left as they are. Exact reuse works per share, the same share
    /// frame after frame. Default: the whole image.
    int tile_share = 0;
    int tile_shares = 1;  ///< how many shares the image is split into (see tile_share)
    /// Samples per pixel, 1 to 4096 (docs/rendering.md "Samples per pixel and area lights"):
    /// stratified per pixel, the same bits on any number of threads; 1 is each pixel's
    /// centre. Above 1 every pixel is traced (no pixel reuse), depth and mesh come from each
    /// pixel's first sample, and area lights take one point per sample.
    int samples_per_pixel = 1;
    /// The reconstruction filter of several samples: "box", "tent" or "blackman-harris".
    std::string filter = "blackman-harris";
    /// Adaptive anti-aliasing: above 0, every pixel takes one sample and only those differing
    /// from a neighbour by more than this (per channel, colours clamped to [0, 1]) or showing
    /// another mesh take samples_per_pixel. Needs the whole image (tile_shares 1).
    float aa_contrast = 0.0f;
};

/// A batch of rays held as separate arrays rather than as dynrt::Ray structs: the layout of
/// numpy's (N, 3) arrays and of most simulators' buffers, read in place (no Ray is built in
/// memory). Ray i is origins[3i..3i+2] + t directions[3i..3i+2] for t in [tmin, tmax], with the
/// same rules as dynrt::Ray. `tmin` and `tmax` hold one value per ray, or are empty: then
/// every ray takes `tmin_all` / `tmax_all`.
struct RayArrays {
    std::span<const float> origins;     ///< x, y, z per ray
    std::span<const float> directions;  ///< x, y, z per ray, as many as origins
    std::span<const float> tmin = {};   ///< one per ray, or empty: tmin_all for every ray
    std::span<const float> tmax = {};   ///< one per ray, or empty: tmax_all for every ray
    float tmin_all = 0.0f;              ///< every ray's tmin when `tmin` is empty
    float tmax_all = std::numeric_limits<float>::infinity();  ///< every ray's tmax when `tmax` is empty

    /// The number of rays: origins.size() / 3.
    std::size_t size() const { return origins.size() / 3; }
};

/// What a ray batch cost. Packet rays were traced in packets (see Engine::intersect); the
/// others one by one.
struct QueryStats {
    std::size_t rays = 0;         ///< rays in the batch
    std::size_t hits = 0;         ///< rays that hit (closest) or are occluded (any hit)
    std::size_t packet_rays = 0;  ///< rays traced in packets
    std::size_t single_rays = 0;  ///< rays traced one by one
    double ms = 0.0;              ///< wall clock of the call
    double mrays_per_s = 0.0;     ///< rays per microsecond of that wall clock
};

/// The engine of a simulation loop: the meshes handed to it, their trees, and the calls that
/// update them, render views of them and trace rays through them (see this header's top).
class DYNRT_API Engine {
public:
    /// Throws Error (invalid_argument) for bad options.
    explicit Engine(const EngineOptions& options = {});
    ~Engine();
    /// Takes `other`'s meshes, trees and state; `other` may then only be destroyed or assigned.
    Engine(Engine&& other) noexcept;
    /// Takes `other`'s meshes, trees and state, after freeing this engine's.
    Engine& operator=(Engine&& other) noexcept;
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    /// Adds a mesh; it is traced from the next update() on. Checks the description (sizes,
    /// indices in range, finite positions, texture coordinates and transform, a valid Surface:
    /// finite values, colours, shininess, reflectance and transmittance >= 0, ior > 0, a
    /// texture added and texture coordinates to map it with) and throws Error naming
    /// the mesh and the bad value. Returns a new id: ids count up from 0 and are never reused,
    /// so an id kept after remove_mesh is refused rather than taken for another mesh. (The
    /// storage of removed meshes is reused; after 2^31 - 1 ids the call throws invalid_state.)
    MeshId add_mesh(const MeshDesc& mesh);

    /// Adds an image for surfaces to map (Surface::diffuse_texture) and returns its id (ids
    /// count up from 0). Throws Error (invalid_argument) naming the texture when it gives
    /// none of a path, bytes and texels (empty bytes), or more than one, or texels that break
    /// TextureDesc's rules (size, channels, value count, float values). Only the description
    /// is checked here: a file or its bytes are read at the first render that needs them (see
    /// TextureDesc::path); texels are copied now.
    TextureId add_texture(const TextureDesc& texture);

    /// New object-space positions for a deformable, exploding or automatic mesh: the same
    /// vertex count, finite (checked at the next update(), which names the vertex). Copied or,
    /// for a borrowed mesh, pointed to (see Ownership::borrow). `normals`, when given, are its
    /// new shading normals (as MeshDesc::normals, copied); when not, a mesh added without
    /// normals gets them computed again from the new positions at the next update(), and one
    /// added with normals keeps its normals.
    void set_positions(MeshId mesh, std::span<const float> positions,
                       std::span<const float> normals = {});

    /// A new object-to-world transform (finite, affine) for any mesh but a static one.
    void set_transform(MeshId mesh, const Transform& transform);

    /// A new material (checked as add_mesh checks MeshDesc::surface; on Error, naming the mesh,
    /// the old one stays), used from the next render on.
    void set_surface(MeshId mesh, const Surface& surface);

    /// Takes the mesh out from the next update() on; its id is never reused. For a borrowed
    /// mesh the engine stops reading the buffer now. Its memory comes back: its vertices now,
    /// its triangles, normals, tree and per-mesh records at the next update() (queries until
    /// then still see it), or now when no update() has taken the mesh in yet; a later add_mesh
    /// reuses its place. So an engine whose meshes come and go holds, after each update(), the
    /// memory of its live meshes plus a few hundred bytes per free place, and has never more
    /// places than it had meshes at once (counting those removed since the last update), not
    /// one per mesh it ever added (memory_bytes()).
    void remove_mesh(MeshId mesh);

    /// The class the mesh is treated as now (for automatic meshes, the inferred one).
    Motion motion(MeshId mesh) const;

    /// Meshes added and not removed.
    std::size_t mesh_count() const;

    /// Heap bytes the engine holds for its meshes: their vertices (copied ones; borrowed
    /// buffers are the caller's), indices, normals, per-mesh records, trees (binary and wide,
    /// with their triangle copies), the top level, and what renders keep per mesh. The
    /// capacities of its vectors are summed, so it is what stays allocated, not what is in use.
    /// Left out: image-sized render buffers (they depend on the image size alone), the thread
    /// pool, and the allocator's own overhead. After remove_mesh and an update() it returns to
    /// what the remaining meshes need. May run concurrently with queries (it waits for a render).
    /// The textures' decoded images (every MIP level) are included once a render has read them.
    std::size_t memory_bytes() const;

    /// The textures the renders hold (texture_figures.h): how many could be read, their bytes
    /// (part of memory_bytes()) and the ms reading them took, figures of the render that last
    /// read them (the first render of a textured mesh, and again at the first render after a
    /// mesh's texture mapping changed). Zeros before, and when no mesh is textured. May run
    /// concurrently with queries (it waits for a render).
    TextureFigures texture_figures() const;

    /// Brings every mesh's tree up to date with the changes since the last update (the first
    /// call builds everything) and returns the step's figures: update_ms (checking and
    /// gathering vertices), refit / rebuild / top-level ms, what was skipped, refitted and
    /// rebuilt and why, the SAH cost and tree shape; total_ms is the whole call. `frame` in
    /// them counts the updates from 0. Throws Error naming mesh, step and vertex when geometry
    /// is not finite; the engine then keeps the trees of the last good update (but see
    /// Error::Code::invalid_geometry for borrowed static and rigid buffers).
    FrameStats update();

    /// Renders `view` at the image's size with Phong shading and a shadow ray per light (as
    /// `dynrt render` does) into `image`. Returns the frame's figures: the last update's
    /// figures plus the trace's (primary, shadow, shade ms, rays, rays/s). Throws Error for a
    /// degenerate view, spans of the wrong size, or before the first update().
    FrameStats render(const View& view, const ImageView& image,
                      const RenderSettings& settings = {}) const;

    /// Stops the render running now on another thread, if there is one: it returns soon, its
    /// FrameStats::cancelled set and its `image` left as it was; the next render traces every
    /// pixel. An update is never stopped. Callable from any thread, any time.
    void cancel_render() const;
    /// How far the render running now has come: its tile passes done and in all
    /// (dynrt/engine/render_progress.h); the last render's between renders. Callable from any
    /// thread, any time, e.g. to draw a progress bar or decide to cancel_render().
    RenderProgress render_progress() const;

    /// Closest hit of every ray, hits[i] for rays[i]; the same results as tracing each ray
    /// alone, bit for bit. The batch is cut into runs of 256 consecutive rays and each run into
    /// groups by the signs of the directions; a group of at least 16 rays whose directions all
    /// lie within about 25 degrees of its middle ray's is traced as one packet, much faster
    /// than ray by ray (QueryStats::packet_rays counts them). So order a batch the way its
    /// rays fan out: neighbouring pixels or lidar beams next to each other, not shuffled.
    /// Throws Error naming a bad ray, for hits.size() != rays.size(), or before the first
    /// update().
    QueryStats intersect(std::span<const Ray> rays, std::span<RayHit> hits) const;

    /// Whether anything is hit within [tmin, tmax] of every ray (1) or not (0): shadow and
    /// visibility tests, cheaper than closest hits. Errors as for intersect.
    QueryStats occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const;

    /// The same two queries on rays held as arrays (RayArrays), with the same results bit for
    /// bit as on the equal dynrt::Ray batch. Also throws Error when the arrays' sizes disagree
    /// (origins not 3 floats per ray, directions not as many, tmin or tmax neither empty nor
    /// one per ray).
    QueryStats intersect(const RayArrays& rays, std::span<RayHit> hits) const;
    /// occluded() on rays held as arrays (see the RayArrays intersect()).
    QueryStats occluded(const RayArrays& rays, std::span<std::uint8_t> occluded) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Writes linear RGB (3 floats per pixel, row-major, top row first) to an image file; the
/// extension picks the format: .png, .jpg, .bmp and .tga get sRGB-encoded 8-bit values clamped
/// to [0, 1], .hdr (Radiance) the linear floats. Throws Error naming the file for another
/// extension, a missing folder, a size mismatch or a failed write.
DYNRT_API void save_image(const std::string& path, int width, int height,
                          std::span<const float> rgb);

}  // namespace dynrt
