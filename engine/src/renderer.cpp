#include "dynrt/engine/renderer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/simd.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/packet/two_level_packet.h"
#include "scene_accel.h"
#include "shadow_ray_offset.h"
#include "stopwatch.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>

namespace dynrt {

struct Renderer::State {
    /// The scene the trees belong to, its poser (one per sequence: it precomputes what never
    /// changes) and the lights the frames use.
    const Scene* scene = nullptr;
    std::optional<anim::ScenePoser> poser;
    std::vector<PointLight> lights;
    anim::PosedScene posed;
    SceneAccel accel;
    /// The last update's figures, and its wall time (part of the frame's total).
    FrameStats update_stats;
    double update_wall_ms = 0.0;
    bool updated = false;
    std::vector<bvh::InstanceHit> hits;
    /// visible[pixel * lights + l]: light l reaches the pixel's hit point (single-ray tracer;
    /// the packet tracer keeps its verdicts per tile).
    std::vector<std::uint8_t> visible;
    /// The scene's materials as the shading kernel reads them, each object's material index
    /// and the lights, refreshed per trace (kept to avoid reallocating).
    std::vector<packet::PhongMaterial> materials;
    std::vector<std::int32_t> object_material;
    std::vector<packet::ShadingLight> shading_lights;
};

namespace {

/// Unit geometric normal of `tri`, turned to face against `dir`.
glm::vec3 facing_normal(const bvh::Triangle& tri, const glm::vec3& dir) {
    const glm::vec3 n = glm::normalize(glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    return glm::dot(n, dir) > 0.0f ? -n : n;
}

/// The hit point from barycentrics: unlike org + t * dir, its error does not grow with the
/// distance travelled, so the small shadow-ray offset is enough to clear the surface.
glm::vec3 hit_point(const bvh::Triangle& tri, const bvh::Hit& hit) {
    return (1.0f - hit.u - hit.v) * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
}

template <typename PerPixel>
void for_each_pixel_in_tiles(int width, int height, PerPixel&& per_pixel) {
    const packet::Tiling tiling(width, height);
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        const packet::Tile tile = tiling.tile(i);
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) per_pixel(x, y, std::size_t(y) * width + x);
        }
    });
}

bvh::Aabb bounds_of(const anim::PosedScene& posed) {
    bvh::Aabb bounds;
    for (const anim::PosedObject& object : posed.objects) {
        for (const glm::vec3& p : object.positions) bounds.extend(p);
    }
    return bounds;
}

/// Runs per_tile(tile) for every 16x16 tile of the image, in parallel.
template <typename PerTile>
void for_each_tile(int width, int height, PerTile&& per_tile) {
    const packet::Tiling tiling(width, height);
    tbb::parallel_for(0, tiling.count(), [&](int i) { per_tile(tiling.tile(i)); });
}

/// Where a pixel's shadow rays start and what they need to know: the facing normal and the
/// hit point, exactly as both tracers compute them.
struct ShadowOrigin {
    glm::vec3 n, point, origin;

    ShadowOrigin(const bvh::Triangle& tri, const bvh::Hit& hit, const glm::vec3& primary_dir)
        : n(facing_normal(tri, primary_dir)), point(hit_point(tri, hit)),
          origin(offset_along_normal(point, n, triangle_magnitude(tri.v0, tri.v1, tri.v2))) {}

    /// The light is on the lit side of the surface, so a shadow ray is traced.
    bool faces(const PointLight& light) const { return glm::dot(n, light.position - point) > 0.0f; }

    /// The shadow ray runs from the light to the offset origin: t in [0, 1] is exactly the
    /// segment between them. From the light, all the shadow rays of a tile share one origin,
    /// which gives packets a tight beam (culling, cheaper box tests); see packet/README.md,
    /// "Shadow ray direction", for what it gained.
    bvh::Ray ray_to(const PointLight& light) const {
        bvh::Ray shadow;
        shadow.org = light.position;
        shadow.dir = shadow_ray_end(origin, n, light.position) - light.position;
        shadow.tmin = 0.0f;
        shadow.tmax = 1.0f;
        return shadow;
    }
};

/// One tile's hits as shading and shadow rays need them, lane by lane in SIMD: facing normal,
/// hit point and offset origin by exactly the operations of facing_normal, hit_point and
/// offset_along_normal (glm's cross, normalize = v * (1 / sqrt(dot)), dot = (x*x + y*y) +
/// z*z), so the shadow rays are bit-identical to the single-ray tracer's; plus the view
/// vector and material per lane, so the shading kernel reads the same arrays while they are
/// hot.
struct TileShadowOrigins {
    packet::SurfacePacket surface;  ///< hit mask, point, normal, view, material
    alignas(64) float origin[3][packet::kPacketRays];

    /// `primary` holds the tile's camera rays (lane tile_lane(tile, x, y)); object i has
    /// material object_material[i].
    void compute(const SceneAccel& accel, const std::vector<bvh::InstanceHit>& hits, int width,
                 const packet::Tile& tile, const packet::RayPacket& primary,
                 const std::vector<std::int32_t>& object_material) {
        packet::LaneMask& hit = surface.hit;
        using L = packet::simd::Lanes<packet::simd::kNativeLanes>;
        using F = L::F;
        using I = L::I;
        constexpr int W = packet::simd::kNativeLanes;
        // Gather each hit's triangle and barycentrics into lanes; lanes without a hit get a
        // harmless triangle and are never used.
        alignas(64) float v[9][packet::kPacketRays];
        alignas(64) float bary[2][packet::kPacketRays];
        constexpr float kHarmless[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        // The hit triangles are scattered through large arrays: request them all before
        // reading any, so the cache misses overlap.
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                const bvh::InstanceHit& h = hits[std::size_t(y) * width + x];
                if (!h.is_hit()) continue;
                const char* t = reinterpret_cast<const char*>(accel.triangle_address(h.object, h.hit.prim));
                __builtin_prefetch(t);
                __builtin_prefetch(t + sizeof(bvh::Triangle) - 1);
            }
        }
        hit = packet::LaneMask{};
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            const packet::LanePixel px = packet::tile_pixel(tile, lane);
            const bvh::Hit* h = nullptr;
            float coords[9];
            if (px.inside && hits[std::size_t(px.y) * width + px.x].is_hit()) {
                const bvh::InstanceHit& ih = hits[std::size_t(px.y) * width + px.x];
                h = &ih.hit;
                hit.set(lane);
                const bvh::Triangle tri = accel.world_triangle(ih.object, ih.hit.prim);
                std::memcpy(coords, &tri, sizeof coords);
                surface.material[lane] = object_material[ih.object];
            } else {
                std::memcpy(coords, kHarmless, sizeof coords);
            }
            for (int k = 0; k < 9; ++k) v[k][lane] = coords[k];
            bary[0][lane] = h ? h->u : 0.0f;
            bary[1][lane] = h ? h->v : 0.0f;
        }
        const float* dir_in[3] = {primary.dir_x, primary.dir_y, primary.dir_z};
        for (int base = 0; base < packet::kPacketRays; base += W) {
            if (hit.extract(base, W) == 0) continue;
            F v0[3], v1[3], v2[3], e1[3], e2[3];
            for (int a = 0; a < 3; ++a) {
                v0[a] = L::load(v[a] + base);
                v1[a] = L::load(v[3 + a] + base);
                v2[a] = L::load(v[6 + a] + base);
                e1[a] = v1[a] - v0[a];
                e2[a] = v2[a] - v0[a];
            }
            // facing_normal: normalize(cross(e1, e2)), negated where it faces along the ray.
            const F c[3] = {e1[1] * e2[2] - e2[1] * e1[2], e1[2] * e2[0] - e2[2] * e1[0],
                            e1[0] * e2[1] - e2[0] * e1[1]};
            const F inv_len = L::splat(1.0f) / L::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            F nv[3] = {c[0] * inv_len, c[1] * inv_len, c[2] * inv_len};
            const F d[3] = {L::load(dir_in[0] + base), L::load(dir_in[1] + base),
                            L::load(dir_in[2] + base)};
            const I flip = (nv[0] * d[0] + nv[1] * d[1] + nv[2] * d[2]) > L::splat(0.0f);
            for (int a = 0; a < 3; ++a) {
                nv[a] = L::select(flip, -nv[a], nv[a]);
                L::store(surface.view[a] + base, -d[a]);
            }
            // hit_point: (1 - u - v) v0 + u v1 + v v2.
            const F u = L::load(bary[0] + base), w = L::load(bary[1] + base);
            const F b0 = L::splat(1.0f) - u - w;
            // triangle_magnitude: the largest |coordinate| of the three vertices.
            F magnitude = L::splat(0.0f);
            for (const F* vertex : {v0, v1, v2}) {
                for (int a = 0; a < 3; ++a) {
                    const F m = L::abs(vertex[a]);
                    magnitude = L::select(m > magnitude, m, magnitude);
                }
            }
            for (int a = 0; a < 3; ++a) {
                const F p = b0 * v0[a] + u * v1[a] + w * v2[a];
                // offset_along_normal, with its constants (256 ulps per unit of normal,
                // 2^-16 of the magnitude below 1/32 of it); packet_renderer_test catches any
                // drift.
                const I ulps = L::truncate(L::splat(kShadowIntScale) * nv[a]);
                const I bits = L::bits_of(p);
                const F moved = L::float_of(bits + L::select(p < L::splat(0.0f), -ulps, ulps));
                const F near_origin = p + L::splat(kShadowFloatScale) * magnitude * nv[a];
                L::store(surface.normal[a] + base, nv[a]);
                L::store(surface.point[a] + base, p);
                L::store(origin[a] + base,
                         L::select(L::abs(p) < L::splat(kShadowOrigin) * magnitude, near_origin, moved));
            }
        }
    }

    /// Fills `out` with the shadow rays toward `light` of the hit lanes on its lit side
    /// (ShadowOrigin::faces and ray_to, lane by lane).
    void rays_to(const PointLight& light, packet::RayPacket& out) const {
        using L = packet::simd::Lanes<packet::simd::kNativeLanes>;
        using F = L::F;
        constexpr int W = packet::simd::kNativeLanes;
        out.clear();
        const F lx = L::splat(light.position.x), ly = L::splat(light.position.y),
                lz = L::splat(light.position.z);
        for (int base = 0; base < packet::kPacketRays; base += W) {
            const std::uint32_t lanes = surface.hit.extract(base, W);
            if (lanes == 0) continue;
            const F to_x = lx - L::load(surface.point[0] + base),
                    to_y = ly - L::load(surface.point[1] + base),
                    to_z = lz - L::load(surface.point[2] + base);
            const F nx = L::load(surface.normal[0] + base), ny = L::load(surface.normal[1] + base),
                    nz = L::load(surface.normal[2] + base);
            const std::uint32_t lit =
                L::bits((nx * to_x + ny * to_y + nz * to_z) > L::splat(0.0f)) & lanes;
            if (lit == 0) continue;
            const F ox = L::load(origin[0] + base), oy = L::load(origin[1] + base),
                    oz = L::load(origin[2] + base);
            // shadow_ray_end: push kShadowLightScale * D further along the normal.
            const F dx = L::abs(lx - ox), dy = L::abs(ly - oy), dz = L::abs(lz - oz);
            F d = dx;
            d = L::select(dy > d, dy, d);
            d = L::select(dz > d, dz, d);
            const F push = L::splat(kShadowLightScale) * d;
            const F ex = ox + push * nx, ey = oy + push * ny, ez = oz + push * nz;
            L::store(out.org_x + base, lx);
            L::store(out.org_y + base, ly);
            L::store(out.org_z + base, lz);
            L::store(out.dir_x + base, ex - lx);
            L::store(out.dir_y + base, ey - ly);
            L::store(out.dir_z + base, ez - lz);
            L::store(out.tmin + base, L::splat(0.0f));
            L::store(out.tmax + base, L::splat(1.0f));
            out.active.words[base >> 6] |= std::uint64_t(lit) << (base & 63);
        }
    }
};

/// What shading a tile needs besides the tile's own data; fixed for a frame.
struct TileShading {
    std::span<const packet::PhongMaterial> materials;
    std::span<const packet::ShadingLight> lights;
    float ambient;
    glm::vec3 background;
    int lanes;  ///< PacketConfig::lanes: the kernel's SIMD width (same bits either way)
};

/// Shades one tile's hits (packet::shade; `visible[l]`: the lanes light l reaches) and writes
/// every pixel of the tile into `out`, whose buffers are already sized: colour, depth, object,
/// prim and normal, or the background and the miss values. `colors` is scratch.
void shade_tile(const TileShading& shading, const packet::Tile& tile,
                const TileShadowOrigins& origins, std::span<const packet::LaneMask> visible,
                const std::vector<bvh::InstanceHit>& hits, packet::ShadedColors& colors,
                RenderedFrame& out) {
    const packet::SurfacePacket& surface = origins.surface;
    if (surface.hit.any()) {
        packet::shade(surface, shading.materials, shading.lights, visible, shading.ambient, colors,
                      shading.lanes);
    }
    const bool hit_buffers = !out.depth.empty();
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(out.width) + std::size_t(x);
            const int lane = packet::tile_lane(tile, x, y);
            const bool hit = surface.hit.test(lane);
            out.color[p] = hit ? glm::vec3(colors.rgb[0][lane], colors.rgb[1][lane],
                                           colors.rgb[2][lane])
                               : shading.background;
            if (!hit_buffers) continue;
            if (!hit) {
                out.depth[p] = std::numeric_limits<float>::infinity();
                out.object[p] = -1;
                out.prim[p] = -1;
                out.normal[p] = glm::vec3(0.0f);
                continue;
            }
            const bvh::InstanceHit& h = hits[p];
            out.depth[p] = h.hit.t;
            out.object[p] = std::int32_t(h.object);
            out.prim[p] = std::int32_t(h.hit.prim);
            out.normal[p] = {surface.normal[0][lane], surface.normal[1][lane],
                             surface.normal[2][lane]};
        }
    }
}

PointLight default_light(const bvh::Aabb& bounds) {
    const float r = 0.5f * glm::length(bounds.extent());
    return PointLight{bounds.center() + 4.0f * r * glm::normalize(glm::vec3(-0.5f, 1.0f, 0.8f)),
                      1.0f};
}

}  // namespace

bvh::Aabb scene_bounds(const Scene& scene) {
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    return bounds_of(posed);
}

std::vector<PointLight> effective_lights(const Scene& scene, const RenderOptions& options) {
    if (!options.lights.empty()) return options.lights;
    if (!scene.lights.empty()) return scene.lights;
    return {default_light(scene_bounds(scene))};
}

Renderer::Renderer(RenderOptions options)
    : options_(std::move(options)), state_(std::make_unique<State>()) {}

Renderer::~Renderer() = default;

void Renderer::reset() {
    State& s = *state_;
    s.accel.clear();
    s.poser.reset();
    s.scene = nullptr;
    s.updated = false;
}

const anim::PosedScene& Renderer::posed() const {
    if (!state_->updated) throw std::logic_error("Renderer::posed before any update");
    return state_->posed;
}

void Renderer::render(const Scene& scene, const Camera& camera, int frame, RenderedFrame& out) {
    update(scene, frame);
    trace(camera, out);
}

void Renderer::update(const Scene& scene, int frame) {
    State& s = *state_;
    if (s.scene != &scene || !s.poser) {
        // A new scene: a poser for it (settings checked here), set up once per sequence.
        reset();
        anim::PoseSettings settings = options_.pose;
        settings.skip_fixed_positions = true;
        s.poser.emplace(scene, std::move(settings));
        s.lights.clear();
        s.scene = &scene;
    }
    s.updated = false;
    const Stopwatch update_clock;
    FrameStats& stats = s.update_stats;
    stats = FrameStats{};
    stats.frame = frame;

    // ---- Update: evaluate the animation, then bring every object's tree to this frame ----
    Stopwatch clock;
    s.poser->pose(frame, s.posed);
    stats.update_ms = clock.lap_ms();
    UpdatePolicy policy;
    policy.build = options_.build;
    policy.exploding_cost_ratio = options_.cost_ratio_exploding;
    policy.rebuild_threshold = options_.rebuild_threshold;
    s.accel.update(scene, *s.poser, s.posed, policy, stats);
    s.update_wall_ms = update_clock.elapsed_ms();
    // The lights, once per sequence and untimed. After the update, so that bad geometry is
    // reported at the frame asked for (the default light is placed from frame 0's bounds).
    if (s.lights.empty()) s.lights = effective_lights(scene, options_);
    s.updated = true;
}

void Renderer::trace(const Camera& camera, RenderedFrame& out) {
    State& s = *state_;
    if (!s.updated) throw std::logic_error("Renderer::trace before any update");
    const Scene& scene = *s.scene;
    const std::vector<PointLight>& lights = s.lights;
    const int width = options_.width, height = options_.height;
    const CameraRays rays(camera, width, height);
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    FrameStats& stats = out.stats;
    stats = s.update_stats;
    const bvh::TwoLevelBvh& accel = s.accel.top_level();
    // The shading kernel's view of materials and lights (bookkeeping, outside the stage clocks).
    s.materials.clear();
    for (const Material& m : scene.materials) {
        s.materials.push_back(packet::PhongMaterial{m.diffuse, m.specular, m.shininess});
    }
    s.object_material.clear();
    for (const Object& object : scene.objects) {
        s.object_material.push_back(std::int32_t(object.material));
    }
    s.shading_lights.clear();
    for (const PointLight& light : lights) {
        s.shading_lights.push_back(packet::ShadingLight{light.position, light.intensity});
    }
    const Stopwatch trace_clock;
    Stopwatch clock;

    // ---- Primary rays, one 16x16 tile per task ----
    s.hits.resize(pixels);
    const bool count = options_.tracer == Tracer::packet && options_.count_packet_work;
    tbb::combinable<packet::PacketStats> work;
    if (options_.tracer == Tracer::packet) {
        const packet::PinholeRays& pinhole = rays.pinhole();
        for_each_tile(width, height, [&](const packet::Tile& tile) {
            packet::RayPacket packet_rays;
            packet::InstanceHits packet_hits;
            pinhole.fill_tile(tile, packet_rays);
            packet::intersect_closest(accel, packet_rays, packet_hits, options_.packet,
                                      count ? &work.local() : nullptr);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    bvh::InstanceHit& hit = s.hits[std::size_t(y) * width + x];
                    hit = packet_hits.hit(packet::tile_lane(tile, x, y));
                    s.accel.resolve(hit);
                }
            }
        });
    } else {
        for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
            s.hits[p] = bvh::intersect_closest(accel, rays.ray(x, y));
            s.accel.resolve(s.hits[p]);
        });
    }
    stats.primary_ms = clock.lap_ms();
    stats.primary_rays = pixels;

    // ---- Shadow rays (one per hit and light on the lit side), then shading ----
    out.width = width;
    out.height = height;
    out.color.resize(pixels);
    const std::size_t hit_pixels = options_.hit_buffers ? pixels : 0;
    out.depth.resize(hit_pixels);
    out.object.resize(hit_pixels);
    out.prim.resize(hit_pixels);
    out.normal.resize(hit_pixels);
    const TileShading shading{s.materials, s.shading_lights, options_.ambient,
                              options_.background, options_.packet.lanes};
    const packet::PinholeRays& pinhole = rays.pinhole();
    const packet::Tiling tiling(width, height);
    tbb::combinable<std::size_t> shadow_rays([] { return std::size_t(0); });
    if (options_.tracer == Tracer::packet) {
        // One shadow packet per tile and light (the tile's hit points toward the light), then
        // the tile is shaded in the same task, on the normals and hit points the shadow rays
        // were made from while they are still in cache. Both stages thus share one parallel
        // loop and one wall-clock interval: each task times its shadow part (origins and
        // shadow packets) and its shading part (kernel and output writes) on its own thread,
        // and the interval is split between shadow_ms and shade_ms in proportion to the two
        // summed thread times, i.e. by the share of the workers' time each stage took.
        struct StageThreadMs {
            double shadow = 0.0, shade = 0.0;
        };
        tbb::combinable<StageThreadMs> thread_ms;
        tbb::combinable<std::vector<packet::LaneMask>> visible_buffers;
        tbb::parallel_for(0, tiling.count(), [&](int i) {
            Stopwatch task_clock;
            const packet::Tile tile = tiling.tile(i);
            packet::RayPacket packet_rays;
            pinhole.fill_tile(tile, packet_rays);  // the camera rays, for the facing normals
            TileShadowOrigins origins;
            origins.compute(s.accel, s.hits, width, tile, packet_rays, s.object_material);
            std::vector<packet::LaneMask>& visible = visible_buffers.local();
            visible.assign(lights.size(), packet::LaneMask{});
            std::size_t traced = 0;
            for (std::size_t l = 0; l < lights.size() && origins.surface.hit.any(); ++l) {
                origins.rays_to(lights[l], packet_rays);
                if (!packet_rays.active.any()) continue;
                traced += std::size_t(packet_rays.active.count());
                packet::LaneMask occluded;
                packet::intersect_any(accel, packet_rays, occluded, options_.packet,
                                      count ? &work.local() : nullptr);
                for (int w = 0; w < packet::kPacketRays / 64; ++w) {
                    visible[l].words[w] = packet_rays.active.words[w] & ~occluded.words[w];
                }
            }
            shadow_rays.local() += traced;
            StageThreadMs& ms = thread_ms.local();
            ms.shadow += task_clock.lap_ms();
            packet::ShadedColors colors;
            shade_tile(shading, tile, origins, visible, s.hits, colors, out);
            ms.shade += task_clock.lap_ms();
        });
        const double wall_ms = clock.lap_ms();
        const StageThreadMs sum = thread_ms.combine([](StageThreadMs a, const StageThreadMs& b) {
            return StageThreadMs{a.shadow + b.shadow, a.shade + b.shade};
        });
        const double thread_total = sum.shadow + sum.shade;
        stats.shadow_ms = thread_total > 0.0 ? wall_ms * (sum.shadow / thread_total) : wall_ms;
        stats.shade_ms = wall_ms - stats.shadow_ms;
    } else {
        s.visible.assign(pixels * lights.size(), 0);
        for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
            const bvh::InstanceHit& hit = s.hits[p];
            if (!hit.is_hit()) return;
            const ShadowOrigin origin(s.accel.world_triangle(hit.object, hit.hit.prim), hit.hit,
                                      rays.ray(x, y).dir);
            std::size_t traced = 0;
            for (std::size_t l = 0; l < lights.size(); ++l) {
                if (!origin.faces(lights[l])) continue;
                ++traced;
                s.visible[p * lights.size() + l] = !bvh::intersect_any(accel, origin.ray_to(lights[l]));
            }
            shadow_rays.local() += traced;
        });
        stats.shadow_ms = clock.lap_ms();
        // The same shading kernel as the packet tracer, so both render the same bits; the
        // normals and hit points are recomputed per tile (as the shadow stage computed them).
        tbb::combinable<std::vector<packet::LaneMask>> visible_buffers;
        tbb::parallel_for(0, tiling.count(), [&](int i) {
            const packet::Tile tile = tiling.tile(i);
            packet::RayPacket camera_rays;
            pinhole.fill_tile(tile, camera_rays);
            TileShadowOrigins origins;
            origins.compute(s.accel, s.hits, width, tile, camera_rays, s.object_material);
            std::vector<packet::LaneMask>& visible = visible_buffers.local();
            visible.assign(lights.size(), packet::LaneMask{});
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const std::size_t p = std::size_t(y) * width + x;
                    const int lane = packet::tile_lane(tile, x, y);
                    for (std::size_t l = 0; l < lights.size(); ++l) {
                        if (s.visible[p * lights.size() + l]) visible[l].set(lane);
                    }
                }
            }
            packet::ShadedColors colors;
            shade_tile(shading, tile, origins, visible, s.hits, colors, out);
        });
        stats.shade_ms = clock.lap_ms();
    }
    stats.shadow_rays = shadow_rays.combine(std::plus<>());
    if (count) {
        const packet::PacketStats total =
            work.combine([](packet::PacketStats a, const packet::PacketStats& b) { return a += b; });
        stats.ray_triangle_tests = total.ray_triangle_tests;
        stats.ray_triangle_culled = total.culled_active_bounds + total.culled_beam_planes +
                                    total.culled_triangle_edges + total.culled_near_far;
    }


    stats.total_ms = s.update_wall_ms + trace_clock.elapsed_ms();
    const auto mrays_per_s = [](std::size_t rays_traced, double ms) {
        return ms > 0.0 ? double(rays_traced) / (ms * 1e3) : 0.0;
    };
    stats.primary_mrays_per_s = mrays_per_s(stats.primary_rays, stats.primary_ms);
    stats.shadow_mrays_per_s = mrays_per_s(stats.shadow_rays, stats.shadow_ms);
}

}  // namespace dynrt
