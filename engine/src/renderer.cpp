#include "dynrt/engine/renderer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/simd.h"
#include "dynrt/packet/tiling.h"
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

namespace dynrt {

struct Renderer::State {
    anim::PosedScene posed;
    /// World-space triangles of all objects, concatenated in scene order.
    std::vector<bvh::Triangle> triangles;
    /// Object i owns triangles [object_first[i], object_first[i + 1]).
    std::vector<std::uint32_t> object_first;
    bvh::TriangleBvh accel;
    std::vector<bvh::Hit> hits;
    /// visible[pixel * lights + l]: light l reaches the pixel's hit point.
    std::vector<std::uint8_t> visible;
};

namespace {

void gather_triangles(const Scene& scene, const anim::PosedScene& posed,
                      std::vector<bvh::Triangle>& triangles,
                      std::vector<std::uint32_t>& object_first) {
    object_first.resize(scene.objects.size() + 1);
    std::size_t total = 0;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        object_first[i] = std::uint32_t(total);
        total += scene.objects[i].mesh.triangles.size();
    }
    object_first.back() = std::uint32_t(total);
    triangles.resize(total);
    tbb::parallel_for(std::size_t(0), scene.objects.size(), [&](std::size_t i) {
        const std::vector<glm::uvec3>& indices = scene.objects[i].mesh.triangles;
        const std::vector<glm::vec3>& p = posed.objects[i].positions;
        bvh::Triangle* out = triangles.data() + object_first[i];
        for (std::size_t t = 0; t < indices.size(); ++t) {
            out[t] = bvh::Triangle{p[indices[t].x], p[indices[t].y], p[indices[t].z]};
        }
    });
}

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
          origin(offset_along_normal(point, n)) {}

    /// The light is on the lit side of the surface, so a shadow ray is traced.
    bool faces(const PointLight& light) const { return glm::dot(n, light.position - point) > 0.0f; }

    /// dir spans origin -> light, so t in [0, 1) is exactly the segment before the light.
    bvh::Ray ray_to(const PointLight& light) const {
        bvh::Ray shadow;
        shadow.org = origin;
        shadow.dir = light.position - origin;
        shadow.tmin = 0.0f;
        shadow.tmax = 1.0f;
        return shadow;
    }
};

/// The shadow-ray origins of one tile's hits for the packet tracer, lane by lane in SIMD:
/// facing normal, hit point and offset origin by exactly the operations of facing_normal,
/// hit_point and offset_along_normal (glm's cross, normalize = v * (1 / sqrt(dot)), dot =
/// (x*x + y*y) + z*z), so the shadow rays are bit-identical to the single-ray tracer's.
struct TileShadowOrigins {
    packet::LaneMask hit;
    alignas(64) float n[3][packet::kPacketRays];
    alignas(64) float point[3][packet::kPacketRays];
    alignas(64) float origin[3][packet::kPacketRays];

    /// `primary` holds the tile's camera rays (lane tile_lane(tile, x, y)).
    void compute(const std::vector<bvh::Triangle>& triangles, const std::vector<bvh::Hit>& hits,
                 int width, const packet::Tile& tile, const packet::RayPacket& primary) {
        using L = packet::simd::Lanes<packet::simd::kNativeLanes>;
        using F = L::F;
        using I = L::I;
        constexpr int W = packet::simd::kNativeLanes;
        // Gather each hit's triangle and barycentrics into lanes; lanes without a hit get a
        // harmless triangle and are never used.
        alignas(64) float v[9][packet::kPacketRays];
        alignas(64) float bary[2][packet::kPacketRays];
        constexpr float kHarmless[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        // The hit triangles are scattered through a large array: request them all before
        // reading any, so the cache misses overlap.
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                const bvh::Hit& h = hits[std::size_t(y) * width + x];
                if (!h.is_hit()) continue;
                const char* t = reinterpret_cast<const char*>(&triangles[h.prim]);
                __builtin_prefetch(t);
                __builtin_prefetch(t + sizeof(bvh::Triangle) - 1);
            }
        }
        hit = packet::LaneMask{};
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            const packet::LanePixel px = packet::tile_pixel(tile, lane);
            const bvh::Hit* h = px.inside ? &hits[std::size_t(px.y) * width + px.x] : nullptr;
            float coords[9];
            if (h && h->is_hit()) {
                hit.set(lane);
                std::memcpy(coords, &triangles[h->prim], sizeof coords);
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
            for (int a = 0; a < 3; ++a) nv[a] = L::select(flip, -nv[a], nv[a]);
            // hit_point: (1 - u - v) v0 + u v1 + v v2.
            const F u = L::load(bary[0] + base), w = L::load(bary[1] + base);
            const F b0 = L::splat(1.0f) - u - w;
            for (int a = 0; a < 3; ++a) {
                const F p = b0 * v0[a] + u * v1[a] + w * v2[a];
                // offset_along_normal, with its constants (256 ulps per unit of normal,
                // 2^-16 absolute below 1/32); packet_renderer_test catches any drift.
                const I ulps = L::truncate(L::splat(256.0f) * nv[a]);
                const I bits = L::bits_of(p);
                const F moved = L::float_of(bits + L::select(p < L::splat(0.0f), -ulps, ulps));
                const F near_origin = p + L::splat(1.0f / 65536.0f) * nv[a];
                L::store(n[a] + base, nv[a]);
                L::store(point[a] + base, p);
                L::store(origin[a] + base,
                         L::select(L::abs(p) < L::splat(1.0f / 32.0f), near_origin, moved));
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
            const std::uint32_t lanes = hit.extract(base, W);
            if (lanes == 0) continue;
            const F to_x = lx - L::load(point[0] + base), to_y = ly - L::load(point[1] + base),
                    to_z = lz - L::load(point[2] + base);
            const F nx = L::load(n[0] + base), ny = L::load(n[1] + base), nz = L::load(n[2] + base);
            const std::uint32_t lit =
                L::bits((nx * to_x + ny * to_y + nz * to_z) > L::splat(0.0f)) & lanes;
            if (lit == 0) continue;
            const F ox = L::load(origin[0] + base), oy = L::load(origin[1] + base),
                    oz = L::load(origin[2] + base);
            L::store(out.org_x + base, ox);
            L::store(out.org_y + base, oy);
            L::store(out.org_z + base, oz);
            L::store(out.dir_x + base, lx - ox);
            L::store(out.dir_y + base, ly - oy);
            L::store(out.dir_z + base, lz - oz);
            L::store(out.tmin + base, L::splat(0.0f));
            L::store(out.tmax + base, L::splat(1.0f));
            out.active.words[base >> 6] |= std::uint64_t(lit) << (base & 63);
        }
    }
};

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

void Renderer::render(const Scene& scene, const Camera& camera, int frame, RenderedFrame& out) {
    State& s = *state_;
    const Stopwatch frame_clock;
    const int width = options_.width, height = options_.height;
    const CameraRays rays(camera, width, height);
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    FrameStats& stats = out.stats;
    stats = FrameStats{};
    stats.frame = frame;

    // ---- Update: the scene at this frame, flattened into world-space triangles ----
    Stopwatch clock;
    anim::pose_scene(scene, frame, s.posed);
    gather_triangles(scene, s.posed, s.triangles, s.object_first);
    // The default light is placed from the bounds at frame 0; when this is frame 0 they come
    // from the geometry just posed instead of posing it a second time.
    const std::vector<PointLight> lights =
        frame == 0 && options_.lights.empty() && scene.lights.empty()
            ? std::vector<PointLight>{default_light(bounds_of(s.posed))}
            : effective_lights(scene, options_);
    stats.update_ms = clock.lap_ms();
    stats.triangles = s.triangles.size();

    // ---- Build ----
    s.accel = bvh::build_triangle_bvh(s.triangles, options_.build);
    stats.build_ms = clock.lap_ms();
    const bvh::BvhStats shape = bvh::compute_stats(s.accel.bvh);
    stats.degenerate_skipped = s.accel.degenerate_skipped;
    stats.sah_cost = bvh::sah_cost(s.accel.bvh, options_.build.sah_costs());
    stats.nodes = shape.nodes;
    stats.leaves = shape.leaves;
    stats.leaf_tris_mean = shape.leaf_prims_mean;
    stats.leaf_tris_max = shape.leaf_prims_max;
    stats.depth = shape.depth;
    clock.lap_ms();  // the statistics are reporting, not building: keep them out of both

    // ---- Primary rays, one 16x16 tile per task ----
    s.hits.resize(pixels);
    const bool count = options_.tracer == Tracer::packet && options_.count_packet_work;
    tbb::combinable<packet::PacketStats> work;
    if (options_.tracer == Tracer::packet) {
        const packet::PinholeRays pinhole(camera.eye, camera.target, camera.up, camera.fov_y_deg,
                                          width, height);
        for_each_tile(width, height, [&](const packet::Tile& tile) {
            packet::RayPacket packet_rays;
            packet::PacketHits packet_hits;
            pinhole.fill_tile(tile, packet_rays);
            packet::intersect_closest(s.accel, packet_rays, packet_hits, options_.packet,
                                      count ? &work.local() : nullptr);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    s.hits[std::size_t(y) * width + x] = packet_hits.hit(packet::tile_lane(tile, x, y));
                }
            }
        });
    } else {
        for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
            s.hits[p] = bvh::intersect_closest(s.accel, rays.ray(x, y));
        });
    }
    stats.primary_ms = clock.lap_ms();
    stats.primary_rays = pixels;

    // ---- Shadow rays: one per hit and light on the lit side ----
    s.visible.assign(pixels * lights.size(), 0);
    tbb::combinable<std::size_t> shadow_rays([] { return std::size_t(0); });
    if (options_.tracer == Tracer::packet) {
        // One packet per tile and light: the tile's hit points toward the light.
        const packet::PinholeRays pinhole(camera.eye, camera.target, camera.up, camera.fov_y_deg,
                                          width, height);
        for_each_tile(width, height, [&](const packet::Tile& tile) {
            packet::RayPacket packet_rays;
            pinhole.fill_tile(tile, packet_rays);  // the camera rays, for the facing normals
            TileShadowOrigins origins;
            origins.compute(s.triangles, s.hits, width, tile, packet_rays);
            if (!origins.hit.any()) return;
            std::size_t traced = 0;
            for (std::size_t l = 0; l < lights.size(); ++l) {
                origins.rays_to(lights[l], packet_rays);
                if (!packet_rays.active.any()) continue;
                traced += std::size_t(packet_rays.active.count());
                packet::LaneMask occluded;
                packet::intersect_any(s.accel, packet_rays, occluded, options_.packet,
                                      count ? &work.local() : nullptr);
                for (int y = tile.y0; y < tile.y1; ++y) {
                    for (int x = tile.x0; x < tile.x1; ++x) {
                        const int lane = packet::tile_lane(tile, x, y);
                        if (!packet_rays.active.test(lane)) continue;
                        s.visible[(std::size_t(y) * width + x) * lights.size() + l] =
                            !occluded.test(lane);
                    }
                }
            }
            shadow_rays.local() += traced;
        });
    } else {
        for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
            const bvh::Hit& hit = s.hits[p];
            if (!hit.is_hit()) return;
            const ShadowOrigin origin(s.triangles[hit.prim], hit, rays.ray(x, y).dir);
            std::size_t traced = 0;
            for (std::size_t l = 0; l < lights.size(); ++l) {
                if (!origin.faces(lights[l])) continue;
                ++traced;
                s.visible[p * lights.size() + l] = !bvh::intersect_any(s.accel, origin.ray_to(lights[l]));
            }
            shadow_rays.local() += traced;
        });
    }
    stats.shadow_ms = clock.lap_ms();
    stats.shadow_rays = shadow_rays.combine(std::plus<>());
    if (count) {
        const packet::PacketStats total =
            work.combine([](packet::PacketStats a, const packet::PacketStats& b) { return a += b; });
        stats.ray_triangle_tests = total.ray_triangle_tests;
        stats.ray_triangle_culled = total.culled_active_bounds + total.culled_beam_planes +
                                    total.culled_triangle_edges + total.culled_near_far;
    }

    // ---- Shade, and fill the per-pixel outputs ----
    out.width = width;
    out.height = height;
    out.color.resize(pixels);
    out.depth.resize(pixels);
    out.object.resize(pixels);
    out.prim.resize(pixels);
    out.normal.resize(pixels);
    for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
        const bvh::Hit& hit = s.hits[p];
        if (!hit.is_hit()) {
            out.color[p] = options_.background;
            out.depth[p] = std::numeric_limits<float>::infinity();
            out.object[p] = -1;
            out.prim[p] = -1;
            out.normal[p] = glm::vec3(0.0f);
            return;
        }
        const bvh::Ray primary = rays.ray(x, y);
        const bvh::Triangle& tri = s.triangles[hit.prim];
        const std::size_t object = std::size_t(
            std::upper_bound(s.object_first.begin(), s.object_first.end(), hit.prim) -
            s.object_first.begin() - 1);
        const Material& material = scene.materials[scene.objects[object].material];
        const glm::vec3 n = facing_normal(tri, primary.dir);
        const glm::vec3 point = hit_point(tri, hit);
        const glm::vec3 v = -primary.dir;
        glm::vec3 color = options_.ambient * material.diffuse;
        for (std::size_t l = 0; l < lights.size(); ++l) {
            if (!s.visible[p * lights.size() + l]) continue;
            const glm::vec3 to_light = glm::normalize(lights[l].position - point);
            const float n_dot_l = glm::dot(n, to_light);
            const glm::vec3 r = 2.0f * n_dot_l * n - to_light;
            const float specular = std::pow(std::max(0.0f, glm::dot(r, v)), material.shininess);
            color += lights[l].intensity * (material.diffuse * n_dot_l + material.specular * specular);
        }
        out.color[p] = color;
        out.depth[p] = hit.t;
        out.object[p] = std::int32_t(object);
        out.prim[p] = std::int32_t(hit.prim - s.object_first[object]);
        out.normal[p] = n;
    });
    stats.shade_ms = clock.lap_ms();

    stats.total_ms = frame_clock.elapsed_ms();
    const auto mrays_per_s = [](std::size_t rays_traced, double ms) {
        return ms > 0.0 ? double(rays_traced) / (ms * 1e3) : 0.0;
    };
    stats.primary_mrays_per_s = mrays_per_s(stats.primary_rays, stats.primary_ms);
    stats.shadow_mrays_per_s = mrays_per_s(stats.shadow_rays, stats.shadow_ms);
}

}  // namespace dynrt
