#include "dynrt/embree/embree_tracer.h"

#include "dynrt/embree/embree_rays.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/engine/resident_memory.h"
#include "dynrt/engine/shadow_ray_offset.h"
#include "dynrt/engine/stopwatch.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>


#include <algorithm>
#include <span>
#include <functional>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace dynrt::embree {

namespace {

constexpr int kLanes = 16;
/// A 16-ray packet covers kBlockSide x kBlockSide pixels; a tile holds whole blocks.
constexpr int kBlockSide = 4;
static_assert(kBlockSide * kBlockSide == kLanes, "one packet is one 4x4 block");
static_assert(packet::kTileSize % kBlockSide == 0, "a tile is made of whole blocks");

RTCBuildQuality rtc_quality(BuildQuality quality) {
    switch (quality) {
        case BuildQuality::refit: return RTC_BUILD_QUALITY_REFIT;
        case BuildQuality::low: return RTC_BUILD_QUALITY_LOW;
        case BuildQuality::medium: return RTC_BUILD_QUALITY_MEDIUM;
        case BuildQuality::high: return RTC_BUILD_QUALITY_HIGH;
    }
    return RTC_BUILD_QUALITY_MEDIUM;
}

void check(RTCDevice device, const char* what) {
    const RTCError error = rtcGetDeviceError(device);
    if (error != RTC_ERROR_NONE) {
        throw std::runtime_error(std::string("Embree: ") + what + " failed (error " +
                                 std::to_string(int(error)) + ")");
    }
}

void resize_hits(PixelHits& hits, std::size_t pixels) {
    hits.object.assign(pixels, -1);
    hits.prim.assign(pixels, -1);
    hits.u.assign(pixels, 0.0f);
    hits.v.assign(pixels, 0.0f);
}

/// Entry `p` of `out` gets a hit.
void store_hit(PixelHits& out, std::size_t p, unsigned geom, unsigned prim, float u, float v) {
    out.object[p] = std::int32_t(geom);
    out.prim[p] = std::int32_t(prim);
    out.u[p] = u;
    out.v[p] = v;
}

/// Runs body(tile) for every 16x16 tile in parallel, in Embree's floating-point mode.
template <typename Body>
void for_each_tile(int width, int height, Body&& body) {
    const packet::Tiling tiling(width, height);
    tbb::parallel_for(0, tiling.count(), [&](int i) {
        const EmbreeFloatMode mode;
        body(tiling.tile(i));
    });
}

/// A 4x4-pixel block of a tile: one 16-ray packet, lane = 4 * row + column, the arrangement
/// of Embree's own tutorials (a 16-wide SIMD program over a 2D block of pixels). Square blocks
/// keep a packet's rays closer together than a 16x1 row, so they share more of the tree.
struct Block {
    int x0, y0;          ///< top-left pixel
    int x_end, y_end;    ///< the tile's (and so the image's) bounds

    /// The pixel of `lane` (clamped into the tile for lanes past its edge, so every lane gets a
    /// real ray); true when the lane is inside the tile.
    bool pixel(int lane, int& x, int& y) const {
        const int px = x0 + lane % kBlockSide, py = y0 + lane / kBlockSide;
        x = std::min(px, x_end - 1);
        y = std::min(py, y_end - 1);
        return px < x_end && py < y_end;
    }
};

/// Runs body(block) for the tile's 4x4 blocks, row by row.
template <typename Body>
void for_each_block(const packet::Tile& tile, Body&& body) {
    for (int y = tile.y0; y < tile.y1; y += kBlockSide) {
        for (int x = tile.x0; x < tile.x1; x += kBlockSide) {
            body(Block{x, y, tile.x1, tile.y1});
        }
    }
}

}  // namespace

void check_embree_fits(const Scene& scene) {
    std::size_t vertices = 0, triangles = 0;
    for (const Object& object : scene.objects) {
        vertices += object.mesh.positions.size();
        triangles += object.mesh.triangles.size();
    }
    // The posed positions and Embree's copy (12 bytes a vertex each), the index copies (12
    // bytes a triangle each), and Embree's tree at its lowest (about 40 bytes a triangle).
    const double needed = 24.0 * double(vertices) + 64.0 * double(triangles);
    const auto available = double(available_memory());
    if (available <= 0.0 || needed <= available) return;
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << scene.source << ": Embree would hold every object's "
         << triangles << " triangles in world space (copies of a shared mesh each in full), about "
         << needed / 1e9 << " GB, and " << available / 1e9
         << " GB are available: trace it with dynrt, which instances copies";
    throw std::runtime_error(text.str());
}

const char* quality_name(BuildQuality quality) {
    switch (quality) {
        case BuildQuality::refit: return "refit";
        case BuildQuality::low: return "low";
        case BuildQuality::medium: return "medium";
        case BuildQuality::high: return "high";
    }
    return "?";
}

struct EmbreeTracer::State {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    /// The frame build() posed (frame 0); load_frame borrows the caller's instead.
    anim::PosedScene own_posed;
    /// The frame in the scene: positions per object. Each object's triangles.
    const anim::PosedScene* posed = nullptr;
    std::vector<std::vector<glm::uvec3>> indices;
    /// Per object, its geometry's vertex buffer (null for an empty object), to update.
    std::vector<float*> vertex_buffers;
    BuildQuality quality = BuildQuality::low;

    void release_scene() {
        if (scene) rtcReleaseScene(scene);
        scene = nullptr;
        vertex_buffers.clear();
    }
    /// The world-space triangle `prim` of `object`.
    bvh::Triangle triangle(std::int32_t object, std::int32_t prim) const {
        const glm::uvec3& t = indices[std::size_t(object)][std::size_t(prim)];
        const std::vector<glm::vec3>& p = posed->objects[std::size_t(object)].positions;
        return bvh::Triangle{p[t.x], p[t.y], p[t.z]};
    }
    /// A new scene holding `frame`'s triangles, not committed.
    void create(const Scene& scene, const anim::PosedScene& frame, BuildQuality quality);
    /// The same with each object's world positions from positions_of(object, scratch).
    template <typename PositionsOf>
    void create_from(const Scene& scene, PositionsOf&& positions_of, BuildQuality quality);
    /// Copies object `object`'s new positions into its vertex buffer and marks it updated.
    void update_object(std::size_t object, std::span<const glm::vec3> positions);
};

namespace {

void copy_positions(std::span<const glm::vec3> p, float* vertices) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, p.size(), 16384),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t v = range.begin(); v < range.end(); ++v) {
                              vertices[3 * v] = p[v].x;
                              vertices[3 * v + 1] = p[v].y;
                              vertices[3 * v + 2] = p[v].z;
                          }
                      });
}

}  // namespace

EmbreeTracer::EmbreeTracer() : state_(std::make_unique<State>()) {
    state_->device = rtcNewDevice(nullptr);
    if (!state_->device) throw std::runtime_error("Embree: cannot create a device");
}

EmbreeTracer::~EmbreeTracer() {
    state_->release_scene();
    rtcReleaseDevice(state_->device);
}

void EmbreeTracer::State::create(const Scene& source, const anim::PosedScene& frame,
                                 BuildQuality build_quality) {
    create_from(
        source,
        [&](std::size_t i, std::vector<glm::vec3>&) -> const std::vector<glm::vec3>& {
            return frame.objects[i].positions;
        },
        build_quality);
    posed = &frame;
}

template <typename PositionsOf>
void EmbreeTracer::State::create_from(const Scene& source, PositionsOf&& positions_of,
                                      BuildQuality build_quality) {
    release_scene();
    posed = nullptr;
    quality = build_quality;
    indices.resize(source.objects.size());
    vertex_buffers.assign(source.objects.size(), nullptr);
    scene = rtcNewScene(device);
    check(device, "rtcNewScene");
    // Refit and low are Embree's options for animated scenes: both with the dynamic flag.
    const bool dynamic = build_quality == BuildQuality::low || build_quality == BuildQuality::refit;
    rtcSetSceneBuildQuality(scene, build_quality == BuildQuality::refit
                                       ? RTC_BUILD_QUALITY_LOW
                                       : rtc_quality(build_quality));
    rtcSetSceneFlags(scene, dynamic ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_NONE);
    std::vector<glm::vec3> scratch;
    for (std::size_t i = 0; i < source.objects.size(); ++i) {
        const std::vector<glm::uvec3>& tris = source.objects[i].mesh.triangles;
        indices[i] = tris;
        if (tris.empty()) continue;  // an empty geometry is an Embree error
        const auto& positions = positions_of(i, scratch);
        const std::span<const glm::vec3> p(positions.data(), positions.size());
        if (p.empty()) continue;
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geom, rtc_quality(build_quality));
        // Own (not shared) buffers: Embree pads them for its 16-byte vertex loads.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p.size()));
        auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris.size()));
        check(device, "rtcSetNewGeometryBuffer");
        copy_positions(p, vertices);
        for (std::size_t t = 0; t < tris.size(); ++t) {
            index[3 * t] = tris[t].x;
            index[3 * t + 1] = tris[t].y;
            index[3 * t + 2] = tris[t].z;
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(scene, geom, unsigned(i));
        vertex_buffers[i] = vertices;
        rtcReleaseGeometry(geom);
        check(device, "creating a triangle geometry");
    }
}

void EmbreeTracer::State::update_object(std::size_t object, std::span<const glm::vec3> positions) {
    copy_positions(positions, vertex_buffers[object]);
    RTCGeometry geom = rtcGetGeometry(scene, unsigned(object));
    rtcUpdateGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(geom);
}

double EmbreeTracer::build(const Scene& scene, BuildQuality quality) {
    check_embree_fits(scene);
    State& s = *state_;
    anim::pose_scene(scene, 0, s.own_posed);
    // ---- Buffers: created and filled outside the timed part ----
    s.create(scene, s.own_posed, quality);
    // ---- Build: the commit alone is timed ----
    const EmbreeFloatMode mode;
    const Stopwatch clock;
    rtcCommitScene(s.scene);
    const double ms = clock.elapsed_ms();
    check(s.device, "rtcCommitScene");
    return ms;
}

namespace {

/// A full pose as the geometry a load reads (every object's world positions).
class PosedGeometry final : public FrameGeometry {
public:
    explicit PosedGeometry(const anim::PosedScene& posed) : posed_(posed) {}
    std::span<const glm::vec3> world_positions(std::size_t object, std::vector<glm::vec3>&) const override {
        return posed_.objects[object].positions;
    }
    bool changed(std::size_t object) const override { return posed_.objects[object].changed; }

private:
    const anim::PosedScene& posed_;
};

}  // namespace

FrameLoad EmbreeTracer::load_frame(const Scene& scene, const anim::PosedScene& posed,
                                   BuildQuality quality) {
    const FrameLoad load = load_geometry(scene, PosedGeometry(posed), quality);
    state_->posed = &posed;  // for the shadow rays' origins (occluded16, occluded1)
    return load;
}

double EmbreeTracer::intersect1(const Camera& camera, int width, int height, PixelHits& out) {
    if (!state_->scene) throw std::logic_error("EmbreeTracer::intersect1 before build");
    RTCScene scene = state_->scene;
    const packet::PinholeRays rays(camera, width, height);
    resize_hits(out, std::size_t(width) * std::size_t(height));
    const Stopwatch clock;
    for_each_tile(width, height, [&](const packet::Tile& tile) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        // The tile's rays made in SIMD, as dynrt's single-ray tracer makes them, so both sides
        // pay the same for making rays.
        packet::RayPacket camera_rays;
        rays.fill_tile(tile, camera_rays);
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                RTCRayHit rh = to_rtc_ray_hit(camera_rays.ray(packet::tile_lane(tile, x, y)));
                rtcIntersect1(scene, &context, &rh);
                if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                const std::size_t p = std::size_t(y) * width + x;
                store_hit(out, p, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
            }
        }
    });
    return clock.elapsed_ms();
}

double EmbreeTracer::intersect16(const Camera& camera, int width, int height, PixelHits& out) {
    if (!state_->scene) throw std::logic_error("EmbreeTracer::intersect16 before build");
    RTCScene scene = state_->scene;
    const packet::PinholeRays rays(camera, width, height);
    resize_hits(out, std::size_t(width) * std::size_t(height));
    const Stopwatch clock;
    for_each_tile(width, height, [&](const packet::Tile& tile) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        for_each_block(tile, [&](const Block& block) {
            alignas(64) int valid[kLanes];
            RTCRayHit16 rh;  // RTC_ALIGN(64) in its declaration
            for (int lane = 0; lane < kLanes; ++lane) {
                int x, y;
                valid[lane] = block.pixel(lane, x, y) ? -1 : 0;
                // Masked-off lanes still get a harmless ray, so no lane holds garbage.
                set_rtc_ray_hit16(rh, lane, rays.ray(x, y), unsigned(lane));
            }
            rtcIntersect16(valid, scene, &context, &rh);
            for (int lane = 0; lane < kLanes; ++lane) {
                int x, y;
                if (!block.pixel(lane, x, y)) continue;
                if (rh.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
                const std::size_t p = std::size_t(y) * width + x;
                store_hit(out, p, rh.hit.geomID[lane], rh.hit.primID[lane], rh.hit.u[lane], rh.hit.v[lane]);
            }
        });
    });
    return clock.elapsed_ms();
}

namespace {

/// Sizes `out` for one entry per logged ray, then runs body(packet, index of its first ray in
/// `out`) for every logged packet in parallel, in Embree's floating-point mode; returns ms.
template <typename Body>
double for_each_logged_packet(const SecondaryRayLog& log, PixelHits& out, Body&& body) {
    std::vector<std::size_t> first(log.packets.size() + 1, 0);
    for (std::size_t i = 0; i < log.packets.size(); ++i) first[i + 1] = first[i] + log.packets[i].rays.size();
    resize_hits(out, first.back());
    const Stopwatch clock;
    tbb::parallel_for(std::size_t(0), log.packets.size(), [&](std::size_t i) {
        const EmbreeFloatMode mode;
        body(log.packets[i], first[i]);
    });
    return clock.elapsed_ms();
}

}  // namespace

double EmbreeTracer::intersect16_logged(const SecondaryRayLog& log, bool coherent, PixelHits& out) {
    if (!state_->scene) throw std::logic_error("EmbreeTracer::intersect16_logged before build");
    RTCScene scene = state_->scene;
    return for_each_logged_packet(log, out, [&](const SecondaryRayPacket& logged, std::size_t first) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        // Each active lane's index into the packet's rays.
        int ray_of[packet::kPacketRays];
        int k = 0;
        for (int lane = 0; lane < packet::kPacketRays; ++lane) ray_of[lane] = logged.lanes.test(lane) ? k++ : -1;
        // Blocks of 16 consecutive lanes: rays next to each other in the renderer's sorted
        // order (one kind and octant, nearby origins).
        for (int base = 0; base < packet::kPacketRays; base += kLanes) {
            alignas(64) int valid[kLanes];
            RTCRayHit16 rh;
            int any = -1;
            for (int b = 0; b < kLanes; ++b) {
                valid[b] = ray_of[base + b] >= 0 ? -1 : 0;
                if (ray_of[base + b] >= 0 && any < 0) any = ray_of[base + b];
            }
            if (any < 0) continue;
            for (int b = 0; b < kLanes; ++b) {
                // Masked-off lanes still get a harmless ray (the block's first).
                const int r = ray_of[base + b] >= 0 ? ray_of[base + b] : any;
                set_rtc_ray_hit16(rh, b, logged.rays[std::size_t(r)], unsigned(b));
            }
            rtcIntersect16(valid, scene, &context, &rh);
            for (int b = 0; b < kLanes; ++b) {
                const int r = ray_of[base + b];
                if (r < 0 || rh.hit.geomID[b] == RTC_INVALID_GEOMETRY_ID) continue;
                store_hit(out, first + std::size_t(r), rh.hit.geomID[b], rh.hit.primID[b], rh.hit.u[b], rh.hit.v[b]);
            }
        }
    });
}

double EmbreeTracer::intersect1_logged(const SecondaryRayLog& log, PixelHits& out) {
    if (!state_->scene) throw std::logic_error("EmbreeTracer::intersect1_logged before build");
    RTCScene scene = state_->scene;
    return for_each_logged_packet(log, out, [&](const SecondaryRayPacket& logged, std::size_t first) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (std::size_t r = 0; r < logged.rays.size(); ++r) {
            RTCRayHit rh = to_rtc_ray_hit(logged.rays[r]);
            rtcIntersect1(scene, &context, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            store_hit(out, first + r, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v);
        }
    });
}

namespace {

/// What a pixel's shadow rays share, computed once for all lights exactly as the renderer does:
/// the facing normal, the hit point and the offset origin.
struct ShadowOrigin {
    bool hit = false;
    glm::vec3 normal{0.0f}, point{0.0f}, origin{0.0f};
};

/// `triangle_of(object, prim)` gives a hit's world-space triangle.
template <typename TriangleOf>
ShadowOrigin shadow_origin(const TriangleOf& triangle_of, const packet::PinholeRays& rays,
                           const PixelHits& hits, int width, int x, int y) {
    ShadowOrigin o;
    const std::size_t p = std::size_t(y) * width + x;
    if (hits.object[p] < 0) return o;
    o.hit = true;
    const bvh::Triangle tri = triangle_of(hits.object[p], hits.prim[p]);
    const glm::vec3 dir = rays.ray(x, y).dir;
    const glm::vec3 n = glm::normalize(glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    o.normal = glm::dot(n, dir) > 0.0f ? -n : n;
    o.point = (1.0f - hits.u[p] - hits.v[p]) * tri.v0 + hits.u[p] * tri.v1 + hits.v[p] * tri.v2;
    o.origin = offset_along_normal(o.point, o.normal, triangle_magnitude(tri.v0, tri.v1, tri.v2));
    return o;
}

/// The renderer's shadow ray toward `light` (from the light to the offset origin, pushed further
/// for the light's distance, t in [0, 1]), or false when the light is on the pixel's unlit side
/// or the pixel has no hit.
bool shadow_ray(const ShadowOrigin& o, const PointLight& light, glm::vec3& org, glm::vec3& dir) {
    if (!o.hit || !(glm::dot(o.normal, light.position - o.point) > 0.0f)) return false;
    org = light.position;
    dir = shadow_ray_end(o.origin, o.normal, light.position) - light.position;
    return true;
}

void reset_counts(std::vector<std::uint32_t>* occluded, int width, int height) {
    if (occluded) occluded->assign(std::size_t(width) * std::size_t(height), 0u);
}

}  // namespace

double EmbreeTracer::occluded16(const Camera& camera, int width, int height,
                                const std::vector<PointLight>& lights, const PixelHits& hits,
                                std::size_t& rays_traced, std::vector<std::uint32_t>* occluded) {
    if (!state_->scene) throw std::logic_error("EmbreeTracer::occluded16 before build");
    const State& s = *state_;
    const auto triangle_of = [&s](std::int32_t object, std::int32_t prim) {
        return s.triangle(object, prim);
    };
    const packet::PinholeRays rays(camera, width, height);
    reset_counts(occluded, width, height);
    tbb::combinable<std::size_t> counts([] { return std::size_t(0); });
    const Stopwatch clock;
    for_each_tile(width, height, [&](const packet::Tile& tile) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        std::size_t traced = 0;
        for_each_block(tile, [&](const Block& block) {
            ShadowOrigin origins[kLanes];
            for (int lane = 0; lane < kLanes; ++lane) {
                int x, y;
                if (block.pixel(lane, x, y)) origins[lane] = shadow_origin(triangle_of, rays, hits, width, x, y);
            }
            for (const PointLight& light : lights) {
                alignas(64) int valid[kLanes];
                RTCRay16 ray;
                int active = 0;
                for (int lane = 0; lane < kLanes; ++lane) {
                    glm::vec3 org(0.0f), dir(0.0f, 0.0f, 1.0f);
                    const bool lit = shadow_ray(origins[lane], light, org, dir);
                    valid[lane] = lit ? -1 : 0;
                    active += lit;
                    set_rtc_ray16(ray, lane, bvh::Ray{org, dir, 0.0f, 1.0f}, unsigned(lane));
                }
                if (active == 0) continue;
                rtcOccluded16(valid, s.scene, &context, &ray);
                traced += std::size_t(active);
                if (!occluded) continue;
                for (int lane = 0; lane < kLanes; ++lane) {
                    int x, y;
                    // rtcOccluded16 sets tfar to -inf for the occluded valid lanes.
                    if (valid[lane] && block.pixel(lane, x, y) && ray.tfar[lane] < 0.0f) {
                        ++(*occluded)[std::size_t(y) * width + x];
                    }
                }
            }
        });
        counts.local() += traced;
    });
    const double ms = clock.elapsed_ms();
    rays_traced = counts.combine(std::plus<>());
    return ms;
}

double EmbreeTracer::occluded1(const Camera& camera, int width, int height,
                               const std::vector<PointLight>& lights, const PixelHits& hits,
                               std::size_t& rays_traced, std::vector<std::uint32_t>* occluded) {
    if (!state_->scene) throw std::logic_error("EmbreeTracer::occluded1 before build");
    const State& s = *state_;
    const auto triangle_of = [&s](std::int32_t object, std::int32_t prim) {
        return s.triangle(object, prim);
    };
    const packet::PinholeRays rays(camera, width, height);
    reset_counts(occluded, width, height);
    tbb::combinable<std::size_t> counts([] { return std::size_t(0); });
    const Stopwatch clock;
    for_each_tile(width, height, [&](const packet::Tile& tile) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        std::size_t traced = 0;
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                const ShadowOrigin o = shadow_origin(triangle_of, rays, hits, width, x, y);
                for (const PointLight& light : lights) {
                    glm::vec3 org, dir;
                    if (!shadow_ray(o, light, org, dir)) continue;
                    RTCRay ray;
                    ray.org_x = org.x;
                    ray.org_y = org.y;
                    ray.org_z = org.z;
                    ray.dir_x = dir.x;
                    ray.dir_y = dir.y;
                    ray.dir_z = dir.z;
                    ray.tnear = 0.0f;
                    ray.tfar = 1.0f;
                    ray.time = 0.0f;
                    ray.mask = ~0u;
                    ray.id = 0;
                    ray.flags = 0;
                    rtcOccluded1(s.scene, &context, &ray);
                    ++traced;
                    if (occluded && ray.tfar < 0.0f) ++(*occluded)[std::size_t(y) * width + x];
                }
            }
        }
        counts.local() += traced;
    });
    const double ms = clock.elapsed_ms();
    rays_traced = counts.combine(std::plus<>());
    return ms;
}

FrameLoad EmbreeTracer::load_geometry(const Scene& scene, const FrameGeometry& geometry,
                                      BuildQuality quality) {
    State& s = *state_;
    FrameLoad load;
    Stopwatch clock;
    if (!s.scene || s.quality != quality || s.indices.size() != scene.objects.size()) {
        check_embree_fits(scene);
        s.create_from(
            scene,
            [&](std::size_t i, std::vector<glm::vec3>& scratch) { return geometry.world_positions(i, scratch); },
            quality);
    } else {
        std::vector<glm::vec3> scratch;
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            if (!s.vertex_buffers[i] || !geometry.changed(i)) continue;
            s.update_object(i, geometry.world_positions(i, scratch));
        }
        check(s.device, "updating vertex buffers");
    }
    load.upload_ms = clock.lap_ms();
    const EmbreeFloatMode mode;
    rtcCommitScene(s.scene);
    load.commit_ms = clock.lap_ms();
    check(s.device, "rtcCommitScene");
    return load;
}

void EmbreeTracer::forget() { state_->release_scene(); }

namespace {

/// The lanes of block `b` (0-15) of a 256-lane batch: a 4x4 block of a tile's pixels (lane =
/// 16 * row + column) when `tile`, else 16 consecutive lanes.
int block_lane(bool tile, int b, int k) {
    if (!tile) return b * kLanes + k;
    const int bx = b % kBlockSide, by = b / kBlockSide;
    return (by * kBlockSide + k / kBlockSide) * packet::kTileSize + bx * kBlockSide + k % kBlockSide;
}

/// Runs body(lane, valid) for each block of `rays` holding an active lane: lane[k] is the
/// batch lane that goes in slot k of the 16-ray packet (for a masked-off slot an active lane
/// of the block, so that no slot holds garbage), valid[k] -1 for an active slot, 0 otherwise.
template <typename Body>
void for_each_active_block(const packet::RayPacket& rays, bool tile, Body&& body) {
    for (int b = 0; b < packet::kPacketRays / kLanes; ++b) {
        alignas(64) int valid[kLanes];
        int lane[kLanes];
        int any = -1;
        for (int k = 0; k < kLanes; ++k) {
            lane[k] = block_lane(tile, b, k);
            valid[k] = rays.active.test(lane[k]) ? -1 : 0;
            if (valid[k] != 0 && any < 0) any = lane[k];
        }
        if (any < 0) continue;
        for (int k = 0; k < kLanes; ++k) {
            if (valid[k] == 0) lane[k] = any;
        }
        body(lane, valid);
    }
}

/// The context of the seam's calls: coherent for a tile's rays.
RTCIntersectContext seam_context(bool tile) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (tile) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    return context;
}

}  // namespace

void EmbreeTracer::closest_lanes(const packet::RayPacket& rays, bool tile, HitTarget hits) const {
    const EmbreeFloatMode mode;
    RTCIntersectContext context = seam_context(tile);
    for_each_active_block(rays, tile, [&](const int* lane, int* valid) {
        RTCRayHit16 rh;
        for (int k = 0; k < kLanes; ++k) set_rtc_ray_hit16(rh, k, rays.ray(lane[k]), unsigned(k));
        rtcIntersect16(valid, state_->scene, &context, &rh);
        for (int k = 0; k < kLanes; ++k) {
            if (!valid[k]) continue;
            bvh::InstanceHit& hit = hits[lane[k]];
            hit = bvh::InstanceHit{};
            if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
            hit.object = rh.hit.geomID[k];
            hit.hit = bvh::Hit{rh.ray.tfar[k], rh.hit.u[k], rh.hit.v[k], rh.hit.primID[k]};
        }
    });
}

packet::LaneMask EmbreeTracer::occluded_lanes(const packet::RayPacket& rays, bool tile) const {
    const EmbreeFloatMode mode;
    RTCIntersectContext context = seam_context(tile);
    packet::LaneMask occluded;
    for_each_active_block(rays, tile, [&](const int* lane, int* valid) {
        RTCRay16 r;
        for (int k = 0; k < kLanes; ++k) set_rtc_ray16(r, k, rays.ray(lane[k]), unsigned(k));
        rtcOccluded16(valid, state_->scene, &context, &r);
        for (int k = 0; k < kLanes; ++k) {
            // rtcOccluded16 sets tfar to -inf for an occluded ray.
            if (valid[k] && r.tfar[k] < 0.0f) occluded.set(lane[k]);
        }
    });
    return occluded;
}

}  // namespace dynrt::embree
