#include "rendering/exact_reuse.h"

#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/packet/two_level_packet.h"
#include "rendering/changed_space.h"
#include "rendering/same_view.h"
#include "rendering/tile_pass.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace dynrt::detail {

namespace {

/// The settings that decide a pixel's value (the tracers and culling give the same bits, but
/// the tracer is compared too, so that a comparison of the two always traces both in full).
bool same_image_settings(const TraceSettings& a, const TraceSettings& b) {
    return a.width == b.width && a.height == b.height && a.tracer == b.tracer &&
           a.hit_buffers == b.hit_buffers && a.background == b.background && a.environment == b.environment &&
           a.ambient == b.ambient && a.packet.lanes == b.packet.lanes &&
           a.secondary.max_depth == b.secondary.max_depth && a.secondary.cutoff == b.secondary.cutoff &&
           a.smooth_normals == b.smooth_normals && a.tiles == b.tiles && a.sampling == b.sampling;
}

/// Whether the shadow rays of `light` toward end points in `ends` may meet `space`'s boxes
/// (select_hull into `near` when `near` is not null): they lie in the hull of the light's
/// position and `ends` for a point light; an area light's leave anywhere on it, so they lie in
/// the box of the light's bounds and `ends` (the hull of its centre and that box). A
/// directional light's leave their origins (`ends` holds those) toward it without end.
bool shadows_may_meet(const ChangedSpace& space, const PointLight& light, const bvh::Aabb& ends,
                      ChangedSpace* near) {
    if (light.kind == PointLight::Kind::directional) {
        const glm::vec3 toward = -light.direction;
        return near != nullptr ? space.select_sweep(ends, toward, *near) : space.meets_sweep(ends, toward);
    }
    bvh::Aabb points = ends;
    if (light.shape != PointLight::Shape::point) points.extend(light_bounds(light));
    return near != nullptr ? space.select_hull(light.position, points, *near)
                           : space.meets_hull(light.position, points);
}

/// The terms of a material that the shading kernel's PhongMaterial leaves out.
bool same_scene_terms(const Material& a, const Material& b) {
    return a.reflectance == b.reflectance && a.transmittance == b.transmittance && a.ior == b.ior &&
           a.diffuse_map == b.diffuse_map && a.emission_map == b.emission_map;
}

bool same_material(const packet::PhongMaterial& a, const packet::PhongMaterial& b) {
    return a.diffuse == b.diffuse && a.specular == b.specular && a.shininess == b.shininess &&
           a.emission == b.emission && a.ambient == b.ambient && a.own_ambient == b.own_ambient;
}

/// Object `i`'s material now and then differ (its index, or the material's values).
bool material_changed(const ReuseMemory& memory, const ReuseInputs& now, std::size_t i) {
    const std::int32_t then_index = memory.object_material[i], now_index = now.object_material[i];
    if (then_index != now_index) return true;
    const auto index = std::size_t(now_index);
    if (index >= now.materials.size() || index >= memory.materials.size()) {
        return index < now.materials.size() || index < memory.materials.size();
    }
    if (!same_material(memory.materials[index], now.materials[index])) return true;
    if (index >= now.scene_materials.size() || index >= memory.scene_materials.size()) {
        return now.scene_materials.size() != memory.scene_materials.size();
    }
    return !same_scene_terms(memory.scene_materials[index], now.scene_materials[index]);
}

/// The most boxes (objects' parts) a plan tests rays against; see plan_exact_reuse.
constexpr std::size_t kMostChangedParts = 1024;

/// Object i's parts when they were recorded, else its one box.
void add_parts(std::span<const std::vector<bvh::Aabb>> parts, std::span<const bvh::Aabb> boxes,
               std::size_t i, std::vector<bvh::Aabb>& out) {
    // An object with triangles has at least one part; none recorded means its box.
    if (i < parts.size() && !parts[i].empty()) out.insert(out.end(), parts[i].begin(), parts[i].end());
    else out.push_back(boxes[i]);
}

ReusePlan full(std::string reason) {
    ReusePlan plan;
    plan.full = true;
    plan.reason = std::move(reason);
    return plan;
}

float largest_coordinate(const bvh::Aabb& box) {
    if (box.is_empty()) return 0.0f;
    float m = 0.0f;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(box.lo[a]), std::fabs(box.hi[a])});
    return m;
}

float largest_coordinate(const glm::vec3& p) {
    return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
}

/// A unique stamp per trace, across pipelines, so a frame written by one pipeline is never
/// taken for another's.
std::uint64_t next_stamp() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;
}

/// Per thread: how long each stage took on this thread, and what it traced.

/// Whether any pixel of `tile` hits a material that spawns secondary rays.
bool tile_spawns_secondary(const TraceInputs& in, const packet::Tile& tile, int width,
                           const std::vector<bvh::InstanceHit>& hits) {
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            const bvh::InstanceHit& hit = hits[std::size_t(y) * width + x];
            if (!hit.is_hit()) continue;
            const auto m = std::size_t(in.object_material[hit.object]);
            if (in.scene_materials[m].traces_secondary()) return true;
        }
    }
    return false;
}

}  // namespace

ReusePlan plan_exact_reuse(const ReuseMemory& memory, const ReuseInputs& now) {
    if (!memory.valid) return full("first frame");
    if (now.frame_stamp == 0 || now.frame_stamp != memory.stamp) {
        return full("not the frame the last trace wrote");
    }
    if (!same_camera(memory.camera, now.camera)) return full(kCameraMoved);
    if (!same_image_settings(memory.settings, now.settings)) return full("image settings changed");
    if (!same_lights(memory.lights, now.lights)) return full("lights changed");
    if (now.object_boxes.size() < memory.object_boxes.size()) {
        return full("objects removed from the scene");
    }
    ReusePlan plan;
    plan.full = false;
    std::size_t moved = 0, restyled = 0, added = 0;
    std::vector<bvh::Aabb> coarse;
    for (std::size_t i = 0; i < now.object_boxes.size(); ++i) {
        if (i >= memory.object_boxes.size()) {
            ++added;
            add_parts(now.object_parts, now.object_boxes, i, plan.changed);
            coarse.push_back(now.object_boxes[i]);
            continue;
        }
        const bool geometry = now.object_versions[i] != memory.object_versions[i];
        const bool material = !geometry && material_changed(memory, now, i);
        if (!geometry && !material) continue;
        ++(geometry ? moved : restyled);
        add_parts(memory.object_parts, memory.object_boxes, i, plan.changed);
        add_parts(now.object_parts, now.object_boxes, i, plan.changed);
        coarse.push_back(memory.object_boxes[i]);
        coarse.push_back(now.object_boxes[i]);
    }
    // Every tile tests its pyramid and its shadow hulls against every box: past a thousand,
    // the objects' own boxes (fewer, looser) are cheaper to test than their parts, and past a
    // thousand of those the tests cost more than tracing every pixel (BART robots with a still
    // camera, 3,600 boxes: 56 ms a frame against 25 for a full trace).
    if (plan.changed.size() > kMostChangedParts) plan.changed.swap(coarse);
    if (plan.changed.size() > kMostChangedParts) {
        return full(std::to_string(moved + restyled + added) +
                    " objects changed: too many boxes to test");
    }
    if (moved + restyled + added == 0) {
        plan.reason = "nothing changed";
        return plan;
    }
    const auto count = [](std::size_t n, const char* what) {
        return std::to_string(n) + (n == 1 ? " object " : " objects ") + what;
    };
    std::string reason;
    for (const auto& [n, what] : {std::pair{moved, "changed"}, std::pair{restyled, "changed material"},
                                  std::pair{added, "added"}}) {
        if (n == 0) continue;
        if (!reason.empty()) reason += ", ";
        reason += count(n, what);
    }
    plan.reason = std::move(reason);
    return plan;
}

void remember_inputs(const ReuseInputs& now, ReuseMemory& memory, RenderedFrame& out) {
    memory.camera = now.camera;
    memory.settings = now.settings;
    memory.lights.assign(now.lights.begin(), now.lights.end());
    memory.materials.assign(now.materials.begin(), now.materials.end());
    memory.scene_materials.assign(now.scene_materials.begin(), now.scene_materials.end());
    memory.object_material.assign(now.object_material.begin(), now.object_material.end());
    // Parts only of the objects whose geometry changed since they were recorded: each
    // object's parts stay paired with the version they were taken at.
    const std::size_t had = memory.object_parts.size();
    memory.object_parts.resize(now.object_parts.size());
    for (std::size_t i = 0; i < now.object_parts.size(); ++i) {
        if (i < had && i < memory.object_versions.size() && i < now.object_versions.size() &&
            memory.object_versions[i] == now.object_versions[i]) {
            continue;
        }
        memory.object_parts[i] = now.object_parts[i];
    }
    memory.object_boxes.assign(now.object_boxes.begin(), now.object_boxes.end());
    memory.object_versions.assign(now.object_versions.begin(), now.object_versions.end());
    memory.stamp = next_stamp();
    memory.valid = true;
    out.reuse_stamp = memory.stamp;
}

namespace {

/// What every tile of an exact-reuse trace reads besides the pass, and the memory it updates.
struct ReuseFrame {
    const TilePass& pass;
    const Camera& camera;
    const ChangedSpace& space;
    ReuseMemory& memory;
    bool all;  ///< every pixel is traced (ReusePlan::full)
};

/// The lanes of tile `t` whose camera rays may see something else than at the last trace
/// (every lane when the whole frame is traced).
packet::LaneMask changed_primary(const ReuseFrame& f, int t, const packet::Tile& tile,
                                 TileRays& rays, ChangedSpace& near) {
    if (f.all) return rays.get().active;
    // The corner pixels' rays (padding covers their rounding against fill_tile's), moved out
    // by the reconstruction filter's reach when the pixels take jittered samples.
    const packet::PinholeRays& pinhole = f.pass.pinhole;
    const float r = f.pass.sample.sampling.spp > 1 ? filter_radius(f.pass.sample.sampling.filter) : 0.0f;
    const float x0 = float(tile.x0) - r, x1 = float(tile.x1 - 1) + r;
    const float y0 = float(tile.y0) - r, y1 = float(tile.y1 - 1) + r;
    const glm::vec3 corners[4] = {pinhole.ray_at(x0, y0).dir, pinhole.ray_at(x1, y0).dir,
                                  pinhole.ray_at(x0, y1).dir, pinhole.ray_at(x1, y1).dir};
    // Only the boxes the tile's pyramid may meet are tested further.
    if (!f.space.select_pyramid(f.camera.eye, corners, near) ||
        (f.memory.all_hit[t] && !near.meets_hull(f.camera.eye, f.memory.hit_points[t]))) {
        return {};
    }
    const packet::RayPacket& tile_rays = rays.get();
    alignas(64) float until[packet::kPacketRays];
    std::fill(std::begin(until), std::end(until), 0.0f);
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            const bvh::InstanceHit& hit = f.pass.hits[std::size_t(y) * f.pass.width + x];
            until[packet::tile_lane(tile, x, y)] = hit.is_hit() ? hit.hit.t : std::numeric_limits<float>::infinity();
        }
    }
    return near.meets_rays(tile_rays, until, tile_rays.active);
}

/// Tile `t`'s shadow rays toward each light that may be blocked otherwise than at the last
/// trace (those of the re-traced `primary` lanes, and those meeting a changed box), traced
/// again; visible[l] gets the lanes light l reaches now, kept or re-traced, and the memory
/// what the next trace tests. Returns the lanes whose shadows alone were traced again.
packet::LaneMask retrace_shadows(const ReuseFrame& f, int t, TileShadowOrigins& origins,
                                 const packet::LaneMask& primary, ChangedSpace& near,
                                 std::vector<packet::LaneMask>& visible, StageWork& tw) {
    const std::span<const PointLight> lights = f.pass.in.lights;
    visible.assign(lights.size(), packet::LaneMask{});
    packet::LaneMask shadows_only;
    packet::RayPacket shadow;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const std::size_t slot = std::size_t(t) * lights.size() + l;
        const packet::ShadingLight& shading = f.pass.shading.lights[l];
        const TileShadowOrigins::LeftOut left = origins.rays_to(shading, l, shadow);
        const packet::LaneMask lit = shadow.active;
        if (!(origins.surface.hit & ~primary).any()) {
            // Every hit traced afresh: the rays not cast, for the report (a tile's kept hits
            // would be counted again each frame they are kept).
            ShadowCounts fresh;
            fresh.add(shading, std::size_t(origins.surface.hit.count()), std::size_t(lit.count()), left);
            tw.add_skipped_shadows(fresh);
        }
        packet::LaneMask retrace = lit & primary;
        if (shadows_may_meet(f.space, lights[l], f.memory.shadow_ends[slot], &near)) {
            // Shadow rays run from the light over t in [0, 1].
            const packet::LaneMask meets = near.meets_rays(shadow, shadow.tmax, lit & ~primary);
            retrace |= meets;
            shadows_only |= meets;
        }
        // Through glass, what reaches a kept lane is not remembered: its shadow rays are all
        // traced again (the tiles where nothing may change are not shaded again at all).
        const std::span<const glm::vec3> glass = f.pass.shading.glass;
        if (!glass.empty()) {
            shadows_only |= lit & ~primary & ~retrace;
            retrace = lit;
        }
        packet::LaneMask reached;
        if (retrace.any()) {
            shadow.active = retrace;
            reached = shadow_reach(f.pass.in.tracer, RayCoherence::tile, glass, shadow, origins, l, lights.size(),
                                   f.pass.trace_work(tw));
            tw.shadow_rays += std::size_t(retrace.count());
        }
        const packet::LaneMask before = f.memory.visible[slot];
        visible[l] = (before & ~primary & ~retrace) | reached;
        f.memory.visible[slot] = visible[l];
        if (primary.any()) {
            bvh::Aabb ends;
            const bool directional = lights[l].kind == PointLight::Kind::directional;
            lit.for_each([&](int lane) {
                const bvh::Ray ray = shadow.ray(lane);
                ends.extend(directional ? ray.org : ray.org + ray.dir);
            });
            f.memory.shadow_ends[slot] = ends;
        }
    }
    return shadows_only;
}

/// Exact reuse's choice of rays for trace_tile (tile_pass.h), for tile number `t`: its camera
/// rays and shadow rays that may have changed traced again, then, if any pixel may show
/// something else, the whole tile shaded (the same bits where nothing changed) and its
/// secondary rays gathered.
class ReuseTile {
public:
    ReuseTile(const ReuseFrame& f, int t, const packet::Tile& tile, ChangedSpace& near)
        : f_(f), t_(t), tile_(tile), near_(near) {}

    packet::LaneMask camera_lanes(TileRays& rays) { return changed_primary(f_, t_, tile_, rays, near_); }

    bool may_change(const packet::LaneMask& primary) {
        const std::span<const PointLight> lights = f_.pass.in.lights;
        bool shadows_may_change = false;
        for (std::size_t l = 0; l < lights.size() && !shadows_may_change; ++l) {
            shadows_may_change = shadows_may_meet(
                f_.space, lights[l], f_.memory.shadow_ends[std::size_t(t_) * lights.size() + l], nullptr);
        }
        secondary_here_ = f_.pass.secondary &&
                          tile_spawns_secondary(f_.pass.in, tile_, f_.pass.width, f_.pass.hits);
        return primary.any() || shadows_may_change || secondary_here_;
    }

    bool shadows(TileShadowOrigins& origins, const packet::LaneMask& primary, TileRays& rays,
                 std::vector<packet::LaneMask>& visible, StageWork& work) {
        if (primary.any()) {
            bvh::Aabb points;
            origins.surface.hit.for_each([&](int lane) {
                points.extend(glm::vec3(origins.surface.point[0][lane], origins.surface.point[1][lane],
                                        origins.surface.point[2][lane]));
            });
            f_.memory.hit_points[t_] = points;
            f_.memory.all_hit[t_] = origins.surface.hit == rays.get().active;
        }
        packet::LaneMask shadows_only = retrace_shadows(f_, t_, origins, primary, near_, visible, work);
        if (secondary_here_) {
            // Every pixel whose hit spawns secondary rays is traced again from its hit on.
            (origins.surface.hit & ~primary & ~shadows_only).for_each([&](int lane) {
                const auto m = std::size_t(origins.surface.material[lane]);
                if (f_.pass.in.scene_materials[m].traces_secondary()) shadows_only.set(lane);
            });
        }
        work.shadows_only += std::size_t(shadows_only.count());
        return primary.any() || shadows_only.any();  // else the same pixels again
    }

    void written(const TileShadowOrigins&, TileRays&, RenderedFrame&) {}
    bool gathers_secondary() const { return secondary_here_; }

private:
    const ReuseFrame& f_;
    int t_;
    const packet::Tile& tile_;
    ChangedSpace& near_;
    bool secondary_here_ = false;
};

}  // namespace

void trace_frame_reusing(const TraceInputs& in, const Camera& camera, const TraceSettings& options,
                         const ReusePlan& plan, ReuseMemory& memory, TraceScratch& scratch,
                         RenderedFrame& out, const SamplePass& sample) {
    const int width = options.width, height = options.height;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const packet::PinholeRays pinhole(camera, width, height);
    // The tiles this trace renders (a process's share, or all); the memory is per tile of it.
    const packet::Tiling tiling(width, height, options.tiles);
    const std::size_t share_pixels = options.tiles.whole() ? pixels : tiling.pixel_count();
    const std::size_t light_count = in.lights.size();
    TraceStats& stats = out.stats;
    stats.reuse_mode = pixel_reuse_name(PixelReuse::exact);
    stats.reuse_reason = plan.reason;
    stats.interpolated_pixels = 0;
    stats.pixels_filled = 0;
    const TileShading shading = frame_shading(in, options, scratch);
    // Until remember_inputs: a trace that throws half way leaves nothing to reuse.
    memory.valid = false;
    if (plan.full) {
        // Nothing to keep: size the frame and the memory for a full trace.
        size_frame(options, scratch, out);
        const std::size_t tiles = std::size_t(tiling.count());
        memory.hit_points.assign(tiles, bvh::Aabb{});
        memory.all_hit.assign(tiles, 0);
        memory.visible.assign(tiles * light_count, packet::LaneMask{});
        memory.shadow_ends.assign(tiles * light_count, bvh::Aabb{});
    }
    const auto finish = [&](const StageWork& sum, double wall_ms) {
        report_stages(sum, wall_ms, stats);
        stats.pixels_traced = sum.primary_rays;
        stats.pixels_shadows_retraced = sum.shadows_only;
        stats.pixels_reused = share_pixels - sum.primary_rays - sum.shadows_only;
    };
    if (!plan.full && plan.changed.empty()) {
        finish(StageWork{}, 0.0);
        return;
    }

    // The scale of everything the tests compare: scene, changed boxes, eye and lights.
    float scale = std::max(largest_coordinate(in.accel.world_bounds()), largest_coordinate(camera.eye));
    for (const bvh::Aabb& box : plan.changed) scale = std::max(scale, largest_coordinate(box));
    for (const PointLight& light : in.lights) scale = std::max(scale, largest_coordinate(light.position));
    const ChangedSpace space(plan.changed, scale);

    const bool count = options.count_packet_work;
    FrameSecondary secondary(in, options, shading, scratch, sample);
    const TilePass pass{in, pinhole, shading, secondary.stage(), scratch.hits, width, count, sample};
    const ReuseFrame frame{pass, camera, space, memory, plan.full};
    tbb::combinable<StageWork> work;
    // Per thread, the changed boxes near the tile at hand (storage reused across tiles).
    tbb::combinable<ChangedSpace> nearby;
    const Stopwatch wall;
    tbb::parallel_for(0, tiling.count(), [&](int t) {
        const packet::Tile tile = tiling.tile(t);
        ReuseTile choice(frame, t, tile, nearby.local());
        trace_tile(pass, t, tile, choice, work.local(), out);
    });
    const StageWork sum = work.combine([](StageWork a, const StageWork& b) { return a += b; });
    finish(sum, wall.elapsed_ms());
    if (secondary.stage()) secondary.stage()->trace(out, stats);
    if (count) sum.trace.report(stats);
}

}  // namespace dynrt::detail
