#include "rendering/secondary_rays.h"

#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/shadow_ray_offset.h"
#include "dynrt/engine/stopwatch.h"
#include "rendering/tile_tracing.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>

namespace dynrt::detail {

SecondaryWork& SecondaryWork::operator+=(const SecondaryWork& o) {
    reflection_rays += o.reflection_rays;
    refraction_rays += o.refraction_rays;
    shadow_rays += o.shadow_rays;
    packet_rays += o.packet_rays;
    single_rays += o.single_rays;
    if (rays_per_depth.size() < o.rays_per_depth.size()) rays_per_depth.resize(o.rays_per_depth.size(), 0);
    for (std::size_t k = 0; k < o.rays_per_depth.size(); ++k) rays_per_depth[k] += o.rays_per_depth[k];
    if (packet_rays_per_depth.size() < o.packet_rays_per_depth.size()) {
        packet_rays_per_depth.resize(o.packet_rays_per_depth.size(), 0);
    }
    for (std::size_t k = 0; k < o.packet_rays_per_depth.size(); ++k) {
        packet_rays_per_depth[k] += o.packet_rays_per_depth[k];
    }
    reflection_ms += o.reflection_ms;
    refraction_ms += o.refraction_ms;
    shadow_ms += o.shadow_ms;
    other_ms += o.other_ms;
    trace += o.trace;
    return *this;
}

bool any_secondary(std::span<const Material> materials, const SecondaryRays& settings) {
    if (settings.max_depth <= 0) return false;
    return std::any_of(materials.begin(), materials.end(),
                       [](const Material& m) { return m.traces_secondary(); });
}

namespace {

using packet::kPacketRays;
using packet::LaneMask;
using packet::RayPacket;

enum class Kind { reflection, refraction };

/// One bounce still to trace: a tile's rays of one kind and depth, each in its pixel's lane,
/// with its path's weight.
struct Bounce {
    RayPacket rays;
    alignas(64) float weight[3][kPacketRays];
    int depth = 0;
    Kind kind = Kind::reflection;
};

/// A thread's buffers, kept across tiles (a bounce is 13 KiB; the stack holds at most two
/// per depth).
struct Scratch {
    std::vector<std::unique_ptr<Bounce>> stack;
    std::size_t top = 0;
    bvh::InstanceHit hits[kPacketRays];
    TileShadowOrigins origins;
    RayPacket shadow;
    std::vector<LaneMask> visible;
    packet::ShadedColors local;
    alignas(64) float weight[3][kPacketRays];

    Bounce& push() {
        if (top == stack.size()) stack.push_back(std::make_unique<Bounce>());
        Bounce& b = *stack[top++];
        b.rays.clear();
        return b;
    }
};

Scratch& thread_scratch() {
    thread_local Scratch scratch;
    return scratch;
}

float max_channel(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

/// The reflected and refracted weights and directions at one hit (renderer.h's model).
struct Split {
    glm::vec3 wr{0.0f}, wt{0.0f};
    glm::vec3 reflected{0.0f}, refracted{0.0f};
};

Split split_at(const Material& m, const glm::vec3& d, const glm::vec3& n, bool back_hit) {
    Split s;
    const float d_dot_n = glm::dot(d, n);
    s.reflected = glm::normalize(d - 2.0f * d_dot_n * n);
    s.wr = m.reflectance;
    const bool transmits = m.transmittance.x > 0.0f || m.transmittance.y > 0.0f || m.transmittance.z > 0.0f;
    if (!transmits) return s;
    const float eta = back_hit ? m.ior : 1.0f / m.ior;
    const float cos_i = -d_dot_n;
    const float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
    if (sin2_t > 1.0f) {  // total internal reflection
        s.wr += m.transmittance;
        return s;
    }
    const float cos_t = std::sqrt(1.0f - sin2_t);
    const float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    // A ray in the surface's plane (cos_i = 0) reflects fully (and would divide 0 by 0).
    const float fresnel = cos_i > 0.0f ? 0.5f * (rs * rs + rp * rp) : 1.0f;
    s.wr += fresnel * m.transmittance;
    s.wt = (1.0f - fresnel) * m.transmittance;
    s.refracted = glm::normalize(eta * d + (eta * cos_i - cos_t) * n);
    return s;
}

void set_lane(RayPacket& rays, int lane, const glm::vec3& org, const glm::vec3& dir) {
    bvh::Ray ray;
    ray.org = org;
    ray.dir = dir;
    ray.tmin = 0.0f;
    ray.tmax = std::numeric_limits<float>::infinity();
    rays.set_ray(lane, ray);
}

/// Pushes the reflection and refraction bounces spawned at `origins`' hit lanes, whose paths
/// weigh `weight` and whose rays had depth `depth` - 1.
void spawn(const SecondaryFrame& f, const TileShadowOrigins& origins,
           const float (&weight)[3][kPacketRays], int depth, Scratch& s) {
    if (depth > f.tracing.settings.max_depth) return;
    const packet::SurfacePacket& surface = origins.surface;
    Bounce* reflection = nullptr;
    Bounce* refraction = nullptr;
    surface.hit.for_each([&](int lane) {
        const Material& m = f.materials[std::size_t(surface.material[lane])];
        if (!m.traces_secondary()) return;
        const glm::vec3 d(-surface.view[0][lane], -surface.view[1][lane], -surface.view[2][lane]);
        const glm::vec3 n(surface.normal[0][lane], surface.normal[1][lane], surface.normal[2][lane]);
        const glm::vec3 path(weight[0][lane], weight[1][lane], weight[2][lane]);
        // The directions take the shading normal, or the geometric one where it would
        // send a ray into its own surface (shading_split_holds).
        const glm::vec3 shading(surface.shading_normal[0][lane], surface.shading_normal[1][lane],
                                surface.shading_normal[2][lane]);
        Split split = split_at(m, d, shading, origins.back_hit.test(lane));
        if (shading != n && !shading_split_holds(d, shading, n, split.reflected, split.refracted)) {
            split = split_at(m, d, n, origins.back_hit.test(lane));
        }
        const glm::vec3 wr = path * split.wr, wt = path * split.wt;
        if (max_channel(wr) >= f.tracing.settings.cutoff) {
            if (reflection == nullptr) {
                reflection = &s.push();
                reflection->depth = depth;
                reflection->kind = Kind::reflection;
            }
            const glm::vec3 org(origins.origin[0][lane], origins.origin[1][lane], origins.origin[2][lane]);
            set_lane(reflection->rays, lane, org, split.reflected);
            for (int c = 0; c < 3; ++c) reflection->weight[c][lane] = wr[c];
        }
        if (max_channel(wt) >= f.tracing.settings.cutoff) {
            if (refraction == nullptr) {
                refraction = &s.push();
                refraction->depth = depth;
                refraction->kind = Kind::refraction;
            }
            const glm::vec3 point(surface.point[0][lane], surface.point[1][lane], surface.point[2][lane]);
            set_lane(refraction->rays, lane, offset_along_normal(point, -n, origins.magnitude[lane]),
                     split.refracted);
            for (int c = 0; c < 3; ++c) refraction->weight[c][lane] = wt[c];
        }
    });
}

}  // namespace

void add_secondary(const SecondaryFrame& f, const TileShadowOrigins& primary,
                   packet::ShadedColors& colors, SecondaryWork& work) {
    Scratch& s = thread_scratch();
    Stopwatch clock;
    s.top = 0;
    for (int c = 0; c < 3; ++c) std::fill(s.weight[c], s.weight[c] + kPacketRays, 1.0f);
    spawn(f, primary, s.weight, 1, s);
    const int max_depth = f.tracing.settings.max_depth;
    if (work.rays_per_depth.size() < std::size_t(std::max(max_depth, 0))) {
        work.rays_per_depth.resize(std::size_t(max_depth), 0);
        work.packet_rays_per_depth.resize(std::size_t(max_depth), 0);
    }
    const glm::vec3 background = f.shading.background;
    while (s.top > 0) {
        // The bounce on top is traced and shaded, then replaced by the bounces it spawns.
        Bounce& bounce = *s.stack[s.top - 1];
        const std::size_t rays = std::size_t(bounce.rays.active.count());
        (bounce.kind == Kind::reflection ? work.reflection_rays : work.refraction_rays) += rays;
        work.rays_per_depth[std::size_t(bounce.depth - 1)] += rays;
        work.other_ms += clock.lap_ms();
        if (f.log != nullptr) f.log->add(bounce.rays, bounce.kind == Kind::refraction, bounce.depth);
        TraceWork* trace_work = f.tracing.count ? &work.trace : nullptr;
        const auto packed = std::size_t(f.tracing.tracer.closest(bounce.rays, RayCoherence::scattered, s.hits, trace_work));
        work.packet_rays += packed;
        work.single_rays += rays - packed;
        work.packet_rays_per_depth[std::size_t(bounce.depth - 1)] += packed;
        (bounce.kind == Kind::reflection ? work.reflection_ms : work.refraction_ms) += clock.lap_ms();

        const LaneMask active = bounce.rays.active;
        s.origins.compute_lanes(
            f.tracing.accel,
            [&](int lane) -> const bvh::InstanceHit* {
                return active.test(lane) && s.hits[lane].is_hit() ? &s.hits[lane] : nullptr;
            },
            bounce.rays, f.object_material);
        const LaneMask& hit = s.origins.surface.hit;
        work.other_ms += clock.lap_ms();
        work.shadow_rays += trace_tile_shadows(f.tracing.tracer, RayCoherence::scattered, s.origins,
                                               f.lights, s.shadow, s.visible, trace_work);
        work.shadow_ms += clock.lap_ms();
        shade_lanes(f.shading, s.origins, s.visible, s.local);
        active.for_each([&](int lane) {
            const bool is_hit = hit.test(lane);
            for (int c = 0; c < 3; ++c) {
                const float seen = is_hit ? s.local.rgb[c][lane] : background[c];
                colors.rgb[c][lane] += bounce.weight[c][lane] * seen;
            }
        });
        // Its weights outlive the slot, which the spawned bounces reuse.
        for (int c = 0; c < 3; ++c) std::copy_n(bounce.weight[c], kPacketRays, s.weight[c]);
        const int depth = bounce.depth;
        --s.top;
        spawn(f, s.origins, s.weight, depth + 1, s);
    }
    work.other_ms += clock.lap_ms();
}

void report_secondary(const SecondaryWork& work, double scale, TraceStats& stats) {
    stats.secondary_ms =
        work.thread_ms() * scale;
    stats.reflection_rays = work.reflection_rays;
    stats.refraction_rays = work.refraction_rays;
    stats.secondary_shadow_rays = work.shadow_rays;
    stats.secondary_packet_rays = work.packet_rays;
    stats.secondary_single_rays = work.single_rays;
    stats.secondary_rays_per_depth = work.rays_per_depth;
    stats.secondary_packet_rays_per_depth = work.packet_rays_per_depth;
    const auto mrays_per_s = [](std::size_t rays, double ms) {
        return ms > 0.0 ? double(rays) / (ms * 1e3) : 0.0;
    };
    stats.reflection_mrays_per_s = mrays_per_s(work.reflection_rays, work.reflection_ms * scale);
    stats.refraction_mrays_per_s = mrays_per_s(work.refraction_rays, work.refraction_ms * scale);
}

}  // namespace dynrt::detail
