#include "dynrt/engine/renderer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/packet/tiling.h"
#include "shadow_ray_offset.h"
#include "stopwatch.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
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
    for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
        s.hits[p] = bvh::intersect_closest(s.accel, rays.ray(x, y));
    });
    stats.primary_ms = clock.lap_ms();
    stats.primary_rays = pixels;

    // ---- Shadow rays: one per hit and light on the lit side ----
    s.visible.assign(pixels * lights.size(), 0);
    tbb::combinable<std::size_t> shadow_rays([] { return std::size_t(0); });
    for_each_pixel_in_tiles(width, height, [&](int x, int y, std::size_t p) {
        const bvh::Hit& hit = s.hits[p];
        if (!hit.is_hit()) return;
        const bvh::Ray primary = rays.ray(x, y);
        const bvh::Triangle& tri = s.triangles[hit.prim];
        const glm::vec3 n = facing_normal(tri, primary.dir);
        const glm::vec3 point = hit_point(tri, hit);
        const glm::vec3 origin = offset_along_normal(point, n);
        std::size_t traced = 0;
        for (std::size_t l = 0; l < lights.size(); ++l) {
            if (!(glm::dot(n, lights[l].position - point) > 0.0f)) continue;
            // dir spans origin -> light, so t in [0, 1) is exactly the segment before the light.
            bvh::Ray shadow;
            shadow.org = origin;
            shadow.dir = lights[l].position - origin;
            shadow.tmin = 0.0f;
            shadow.tmax = 1.0f;
            ++traced;
            s.visible[p * lights.size() + l] = !bvh::intersect_any(s.accel, shadow);
        }
        shadow_rays.local() += traced;
    });
    stats.shadow_ms = clock.lap_ms();
    stats.shadow_rays = shadow_rays.combine(std::plus<>());

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
