#include "rendering/secondary_rays.h"

#include "dynrt/bvh/morton_code.h"
#include "dynrt/bvh/prefetch.h"
#include "dynrt/bvh/radix_sort.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/shadow_ray_offset.h"
#include "dynrt/engine/stopwatch.h"
#include "rendering/stage_work.h"
#include "rendering/tile_tracing.h"

#include <glm/geometric.hpp>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace dynrt::detail {

SecondaryWork& SecondaryWork::operator+=(const SecondaryWork& o) {
    reflection_rays += o.reflection_rays;
    refraction_rays += o.refraction_rays;
    shadows += o.shadows;
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
    if (ms_per_depth.size() < o.ms_per_depth.size()) ms_per_depth.resize(o.ms_per_depth.size(), 0.0);
    for (std::size_t k = 0; k < o.ms_per_depth.size(); ++k) ms_per_depth[k] += o.ms_per_depth[k];
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

/// The two kinds of secondary ray; a ray's children are slots [2 * ray + kind].
enum Kind : int { kRefraction = 0, kReflection = 1 };

/// One ray of a path: where it starts and goes, its path's weight, and its pixel.
/// Left uninitialised when made without values: waves and runs of them are sized first and
/// written after.
struct PathRay {
    glm::vec3 org, dir, weight;
    std::uint32_t pixel;
};

/// The children a ray's hit spawned, by kind (ray[k] is set where made[k]; the others are
/// left uninitialised, so that a hit spawning nothing costs nothing to answer).
struct Spawned {
    PathRay ray[2];
    bool made[2] = {false, false};
    bool any() const { return made[0] || made[1]; }
};

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

/// The children spawned at hit lane `lane` of `origins` by a path of weight `path` through
/// pixel `pixel`: a reflection and a refraction ray whose weights reach the cut-off.
Spawned spawn_at(const SecondaryFrame& f, const TileShadowOrigins& origins, int lane,
                 const glm::vec3& path, std::uint32_t pixel) {
    Spawned out;
    const packet::SurfacePacket& surface = origins.surface;
    const Material& m = f.materials[std::size_t(surface.material[lane])];
    if (!m.traces_secondary()) return out;
    const glm::vec3 d(-surface.view[0][lane], -surface.view[1][lane], -surface.view[2][lane]);
    const glm::vec3 n(surface.normal[0][lane], surface.normal[1][lane], surface.normal[2][lane]);
    // The directions take the shading normal, or the geometric one where it would send a ray
    // into its own surface (shading_split_holds).
    const glm::vec3 shading(surface.shading_normal[0][lane], surface.shading_normal[1][lane],
                            surface.shading_normal[2][lane]);
    Split split = split_at(m, d, shading, origins.back_hit.test(lane));
    if (shading != n && !shading_split_holds(d, shading, n, split.reflected, split.refracted)) {
        split = split_at(m, d, n, origins.back_hit.test(lane));
    }
    const glm::vec3 wr = path * split.wr, wt = path * split.wt;
    const float cutoff = f.tracing.settings.cutoff;
    if (max_channel(wr) >= cutoff) {
        const glm::vec3 org(origins.origin[0][lane], origins.origin[1][lane], origins.origin[2][lane]);
        out.ray[kReflection] = PathRay{org, split.reflected, wr, pixel};
        out.made[kReflection] = true;
    }
    if (max_channel(wt) >= cutoff) {
        const glm::vec3 point(surface.point[0][lane], surface.point[1][lane], surface.point[2][lane]);
        out.ray[kRefraction] =
            PathRay{offset_along_normal(point, -n, origins.magnitude[lane]), split.refracted, wt, pixel};
        out.made[kRefraction] = true;
    }
    return out;
}

/// Rays made by a pass, up to two per ray it shaded, in the order it shaded them: packet c
/// writes its children from slot 2 * 256 * c on, so that each packet writes its own run.
struct Children {
    std::vector<PathRay> rays;
    std::vector<std::uint8_t> kind;
    std::vector<std::uint32_t> parent;  ///< the parent ray's index in its wave
    std::vector<std::uint32_t> count;   ///< per packet

    static constexpr std::size_t kPerPacket = 2 * std::size_t(packet::kPacketRays);

    void reset(std::size_t packets) {
        count.assign(packets, 0);
        const std::size_t slots = packets * kPerPacket;
        if (rays.size() < slots) {
            rays.resize(slots);
            kind.resize(slots);
            parent.resize(slots);
        }
    }
    void add(std::size_t packet_index, const PathRay& ray, int k, std::uint32_t from) {
        const std::size_t slot = packet_index * kPerPacket + count[packet_index]++;
        rays[slot] = ray;
        kind[slot] = std::uint8_t(k);
        parent[slot] = from;
    }
};

/// One depth's rays across the frame (depth 0: the camera hits that spawn any, with only their
/// pixel), and what tracing them gave.
struct Wave {
    std::vector<PathRay> rays;
    std::vector<std::uint8_t> kind;
    /// Per ray, once traced: its hit and its share of its pixel (weight times what it sees).
    /// Kept at their size when the wave is emptied: each pass writes every ray's.
    std::vector<bvh::InstanceHit> hit;
    std::vector<glm::vec3> share;
    /// Per ray and kind, its child's index in the next wave, or -1.
    std::vector<std::int32_t> child;
    /// The next depth's rays, as this wave's shading made them.
    Children spawned;

    std::size_t size() const { return rays.size(); }
    void resize(std::size_t n) {
        rays.resize(n);
        kind.resize(n);
        child.assign(2 * n, -1);
    }
};

/// Makes `next` of what `wave`'s packets spawned, packet by packet, and links each new ray
/// to its parent.
void make_next(Wave& wave, Wave& next) {
    const Children& made = wave.spawned;
    std::vector<std::size_t> first(made.count.size() + 1, 0);
    for (std::size_t c = 0; c < made.count.size(); ++c) first[c + 1] = first[c] + made.count[c];
    next.resize(first.back());
    tbb::parallel_for(std::size_t(0), made.count.size(), [&](std::size_t c) {
        for (std::size_t m = 0; m < made.count[c]; ++m) {
            const std::size_t slot = c * Children::kPerPacket + m, at = first[c] + m;
            next.rays[at] = made.rays[slot];
            next.kind[at] = made.kind[slot];
            wave.child[2 * std::size_t(made.parent[slot]) + made.kind[slot]] = std::int32_t(at);
        }
    });
}

/// A thread's buffers for tracing one packet of a wave.
struct PacketScratch {
    RayPacket rays;
    LaneHits hits;
    std::uint32_t index[kPacketRays];
    TileShadowOrigins origins;
    RayPacket shadow;
    std::vector<LaneMask> visible;
    packet::ShadedColors colors;
};

/// Rays fill_packet fetches ahead of the one it copies.
constexpr std::size_t kGatherAhead = 8;

/// Rays [begin, end) of a wave in the order of `keys` (a ray's index in each key's low 32 bits)
/// as one packet, and their indices, into `p`. The rays are scattered over the wave (sorted
/// anew), so each is fetched kGatherAhead rays ahead, with its hit when `with_hits` (the
/// shading pass reads them next): one cache miss a ray otherwise, a twentieth of BART robots'
/// frame.
void fill_packet(const std::uint64_t* keys, std::size_t begin, std::size_t end,
                 const Wave& wave, PacketScratch& p, bool with_hits) {
    p.rays.clear();
    const std::size_t count = end - begin;
    const auto fetch = [&](std::size_t k) {
        const auto i = std::uint32_t(keys[begin + k]);
        bvh::prefetch_line(&wave.rays[i]);
        bvh::prefetch_line(reinterpret_cast<const char*>(&wave.rays[i]) + sizeof(PathRay) - 1);
        if (with_hits) bvh::prefetch_line(&wave.hit[i]);
    };
    for (std::size_t k = 0; k < kGatherAhead && k < count; ++k) fetch(k);
    for (std::size_t k = 0; k < count; ++k) {
        if (k + kGatherAhead < count) fetch(k + kGatherAhead);
        const auto i = std::uint32_t(keys[begin + k]);
        p.index[k] = i;
        const PathRay& ray = wave.rays[i];
        p.rays.set_ray(int(k), bvh::Ray{ray.org, ray.dir, 0.0f, std::numeric_limits<float>::infinity()});
    }
}

/// A wave is sorted by its keys' top 22 bits: kind and octant and the top 18 bits of the
/// origin's Morton code (a 64^3 grid over the scene), or miss and 21 bits of the hit point's;
/// rays equal there keep their order (their parents'). Sorting all 32 key bits made BART
/// robots' secondary stage 1.08-1.13x slower (two more radix passes over 3 M rays a frame) and
/// kitchen's no faster.
constexpr int kSortBits = 22;

/// Lights from which the shading pass sorts a wave's hits anew (SecondaryStage::trace_wave).
constexpr std::size_t kResortMinLights = 2;

/// Rays of a wave, at most a packet's worth, as positions in its sorted order.
struct Chunk {
    std::uint32_t begin, end;
};

}  // namespace

/// The gathered first bounce and the waves, kept across the stage.
struct SecondaryBuffers::Data {
    /// A thread's gathered tiles: each tile's camera hits that spawned rays, in lane order,
    /// and the rays they spawned (a hit's refraction before its reflection).
    struct Gathered {
        struct Segment {
            int tile;
            std::size_t roots_begin, roots_end, rays_begin, rays_end;
        };
        std::vector<Segment> segments;
        bool called = false;  ///< gather ran on the thread
        std::vector<std::uint32_t> pixel;  ///< per root
        std::vector<PathRay> rays;
        std::vector<std::uint8_t> kind;
        std::vector<std::uint32_t> root;   ///< per ray, its root's index in `pixel`
    };
    tbb::enumerable_thread_specific<Gathered> gathered;
    std::vector<Wave> waves;
    /// The wave being traced: a sort key per ray (over its index), and the keys sorted (in
    /// `keys` or `key_scratch`).
    std::vector<std::uint64_t> keys, key_scratch;
    const std::uint64_t* sorted = nullptr;
    std::vector<Chunk> chunks;
    tbb::enumerable_thread_specific<PacketScratch> scratch;
    tbb::combinable<SecondaryWork> work;
};

SecondaryBuffers::SecondaryBuffers() : data_(std::make_unique<Data>()) {}
SecondaryBuffers::~SecondaryBuffers() = default;
SecondaryBuffers::SecondaryBuffers(SecondaryBuffers&&) noexcept = default;
SecondaryBuffers& SecondaryBuffers::operator=(SecondaryBuffers&&) noexcept = default;

SecondaryStage::SecondaryStage(const SecondaryFrame& frame, SecondaryBuffers& buffers)
    : frame_(frame), state_(*buffers.data_) {
    for (SecondaryBuffers::Data::Gathered& g : state_.gathered) {
        g.segments.clear();
        g.pixel.clear();
        g.rays.clear();
        g.kind.clear();
        g.root.clear();
        g.called = false;
    }
    state_.work.clear();
}

void SecondaryStage::gather(int tile_index, const packet::Tile& tile, int width,
                            const TileShadowOrigins& origins) {
    SecondaryBuffers::Data::Gathered& g = state_.gathered.local();
    g.called = true;
    const std::size_t roots_begin = g.pixel.size(), rays_begin = g.rays.size();
    const glm::vec3 one(1.0f);
    origins.surface.hit.for_each([&](int lane) {
        const packet::LanePixel px = packet::tile_pixel(tile, lane);
        const auto pixel = std::uint32_t(std::size_t(px.y) * std::size_t(width) + std::size_t(px.x));
        const Spawned spawned = spawn_at(frame_, origins, lane, one, pixel);
        if (!spawned.any()) return;
        for (const int k : {kRefraction, kReflection}) {
            if (!spawned.made[k]) continue;
            g.rays.push_back(spawned.ray[k]);
            g.kind.push_back(std::uint8_t(k));
            g.root.push_back(std::uint32_t(g.pixel.size()));
        }
        g.pixel.push_back(pixel);
    });
    if (g.pixel.size() > roots_begin) {
        g.segments.push_back({tile_index, roots_begin, g.pixel.size(), rays_begin, g.rays.size()});
    }
}

/// Sorts `keys` (each a sort key over a ray's index in its low 32 bits) by their top kSortBits
/// bits and cuts them into packets: at most 256 rays, none across a change of the key's top
/// `group_bits` bits.
void SecondaryStage::sort_into_packets(int group_bits) {
    SecondaryBuffers::Data& s = state_;
    const std::size_t n = s.keys.size();
    s.key_scratch.resize(n);
    s.sorted = bvh::radix_sort_bits(s.keys.data(), s.key_scratch.data(), n, 64 - kSortBits, kSortBits);
    s.chunks.clear();
    const int shift = 64 - group_bits;
    std::size_t begin = 0;
    for (std::size_t i = 1; i <= n; ++i) {
        if (i == n || i - begin == std::size_t(kPacketRays) || (s.sorted[i] >> shift) != (s.sorted[begin] >> shift)) {
            s.chunks.push_back({std::uint32_t(begin), std::uint32_t(i)});
            begin = i;
        }
    }
}

void SecondaryStage::trace_wave(int depth) {
    SecondaryBuffers::Data& s = state_;
    Wave& wave = s.waves[std::size_t(depth)];
    const std::size_t n = wave.size();
    if (n > std::numeric_limits<std::uint32_t>::max()) {
        throw std::length_error("more than 2^32 secondary rays of one depth in a frame");
    }
    wave.hit.resize(n);  // every element is written by each pass
    wave.share.resize(n);
    const bvh::MortonGrid grid(frame_.tracing.accel.world_bounds());
    const auto for_each_ray = [&](auto&& per_ray) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i < r.end(); ++i) per_ray(i);
                          });
    };
    s.keys.resize(n);
    // Closest hits, in packets of one kind and direction octant whose origins are close: key
    // kind (bit 63), octant (60-62), the top 28 bits of the origin's Morton code over the
    // scene's bounds (32-59), index (0-31).
    for_each_ray([&](std::size_t i) {
        const PathRay& ray = wave.rays[i];
        const std::uint64_t octant = std::uint64_t(ray.dir.x < 0.0f) | std::uint64_t(ray.dir.y < 0.0f) << 1 |
                                     std::uint64_t(ray.dir.z < 0.0f) << 2;
        s.keys[i] = std::uint64_t(wave.kind[i]) << 63 | octant << 60 |
                    std::uint64_t(grid.code(ray.org) >> 2) << 32 | i;
    });
    sort_into_packets(4);
    tbb::parallel_for(std::size_t(0), s.chunks.size(), [&](std::size_t c) {
        trace_closest(depth, s.chunks[c].begin, s.chunks[c].end);
    });

    // Shadow rays and shading, in packets whose hit points are close (a light's shadow rays
    // then span a narrow cone, and the rays the hits spawn come out in Morton order of their
    // origins): key miss (bit 63), the hit point's Morton code (32-61). Worth its sort when a
    // hit casts several shadow rays: with it BART kitchen's frames (6 lights, 1024x1024) took
    // 0.89x the time (411 against 460 ms), robots' (1 light) 1.05x, museum's (2) the same.
    // Otherwise the shading pass keeps the closest-hit pass's packets.
    if (frame_.lights.size() >= kResortMinLights) {
        for_each_ray([&](std::size_t i) {
            const PathRay& ray = wave.rays[i];
            const bvh::InstanceHit& hit = wave.hit[i];
            const std::uint64_t code = hit.is_hit() ? grid.code(ray.org + hit.hit.t * ray.dir) : 0;
            s.keys[i] = std::uint64_t(!hit.is_hit()) << 63 | code << 32 | i;
        });
        sort_into_packets(1);
    }
    wave.spawned.reset(s.chunks.size());
    tbb::parallel_for(std::size_t(0), s.chunks.size(), [&](std::size_t c) { shade_packet(depth, c); });
}

void SecondaryStage::trace_closest(int depth, std::size_t begin, std::size_t end) {
    SecondaryBuffers::Data& s = state_;
    const SecondaryFrame& f = frame_;
    Wave& wave = s.waves[std::size_t(depth)];
    PacketScratch& p = s.scratch.local();
    SecondaryWork& work = s.work.local();
    const auto d = std::size_t(depth - 1);
    if (work.rays_per_depth.size() <= d) {
        work.rays_per_depth.resize(d + 1, 0);
        work.packet_rays_per_depth.resize(d + 1, 0);
        work.ms_per_depth.resize(d + 1, 0.0);
    }
    Stopwatch clock;
    const int count = int(end - begin);
    fill_packet(s.sorted, begin, end, wave, p, false);
    const bool reflection = wave.kind[p.index[0]] == kReflection;
    (reflection ? work.reflection_rays : work.refraction_rays) += std::size_t(count);
    work.rays_per_depth[d] += std::size_t(count);
    if (f.log != nullptr) f.log->add(p.rays, !reflection, depth);
    work.other_ms += clock.lap_ms();

    TraceWork* trace_work = f.tracing.count ? &work.trace : nullptr;
    const auto packed = std::size_t(f.tracing.tracer.closest(p.rays, RayCoherence::scattered, p.hits, trace_work));
    work.packet_rays += packed;
    work.single_rays += std::size_t(count) - packed;
    work.packet_rays_per_depth[d] += packed;
    for (int k = 0; k < count; ++k) wave.hit[p.index[k]] = p.hits[k];
    const double traced_ms = clock.lap_ms();
    (reflection ? work.reflection_ms : work.refraction_ms) += traced_ms;
    work.ms_per_depth[d] += traced_ms;
}

void SecondaryStage::shade_packet(int depth, std::size_t packet_index) {
    SecondaryBuffers::Data& s = state_;
    const std::size_t begin = s.chunks[packet_index].begin, end = s.chunks[packet_index].end;
    const SecondaryFrame& f = frame_;
    Wave& wave = s.waves[std::size_t(depth)];
    PacketScratch& p = s.scratch.local();
    SecondaryWork& work = s.work.local();
    Stopwatch clock;
    const int count = int(end - begin);
    fill_packet(s.sorted, begin, end, wave, p, true);
    p.origins.compute_lanes(
        f.tracing.accel,
        [&](int lane) -> const bvh::InstanceHit* {
            const bvh::InstanceHit& hit = wave.hit[p.index[lane]];
            return p.rays.active.test(lane) && hit.is_hit() ? &hit : nullptr;
        },
        p.rays, f.object_material);
    p.origins.sample_lights(f.lights, [&](int lane) { return f.sample.at(wave.rays[p.index[lane]].pixel); },
                            f.sample.sampling.spp);
    work.other_ms += clock.lap_ms();
    TraceWork* trace_work = f.tracing.count ? &work.trace : nullptr;
    work.shadows += trace_tile_shadows(f.tracing.tracer, RayCoherence::scattered, p.origins, f.shading.lights,
                                       f.shading.glass, p.shadow, p.visible, trace_work);
    work.shadow_ms += clock.lap_ms();

    shade_lanes(f.shading, p.origins, p.visible, p.colors);
    const bool deeper = depth < f.tracing.settings.max_depth;
    for (int k = 0; k < count; ++k) {
        const std::uint32_t i = p.index[k];
        const bool hit = p.origins.surface.hit.test(k);
        const PathRay& ray = wave.rays[i];
        const glm::vec3 seen = hit ? glm::vec3(p.colors.rgb[0][k], p.colors.rgb[1][k], p.colors.rgb[2][k])
                                   : f.shading.miss(ray.dir);
        wave.share[i] = ray.weight * seen;
        if (!hit || !deeper) continue;
        const Spawned spawned = spawn_at(f, p.origins, k, ray.weight, ray.pixel);
        for (const int kind : {kRefraction, kReflection}) {
            if (spawned.made[kind]) wave.spawned.add(packet_index, spawned.ray[kind], kind, i);
        }
    }
    work.other_ms += clock.lap_ms();
}

namespace {

/// Adds to `color` the shares of ray `i` of waves[depth] (none for depth 0, the camera hit)
/// and of its children's paths, depth first, a refraction's path before a reflection's.
void add_path(const std::vector<Wave>& waves, std::size_t depth, std::size_t i, glm::vec3& color) {
    const Wave& wave = waves[depth];
    if (depth > 0) color += wave.share[i];
    for (const int k : {kRefraction, kReflection}) {
        const std::int32_t c = wave.child[2 * i + std::size_t(k)];
        if (c >= 0) add_path(waves, depth + 1, std::size_t(c), color);
    }
}

}  // namespace

void SecondaryStage::trace(RenderedFrame& out, TraceStats& stats) {
    SecondaryBuffers::Data& s = state_;
    const Stopwatch wall;
    const int max_depth = frame_.tracing.settings.max_depth;
    s.waves.resize(std::size_t(max_depth) + 1);
    // The tiles' gathered hits and rays, in tile order whichever thread gathered them.
    struct Piece {
        const SecondaryBuffers::Data::Gathered* from;
        SecondaryBuffers::Data::Gathered::Segment segment;
    };
    std::vector<Piece> pieces;
    for (const SecondaryBuffers::Data::Gathered& g : s.gathered) {
        for (const SecondaryBuffers::Data::Gathered::Segment& segment : g.segments) pieces.push_back({&g, segment});
    }
    std::sort(pieces.begin(), pieces.end(),
              [](const Piece& a, const Piece& b) { return a.segment.tile < b.segment.tile; });
    // Depth 0 (each root's pixel) and depth 1 (the rays they spawned), linked, in tile order.
    std::vector<std::size_t> roots_at(pieces.size() + 1, 0), rays_at(pieces.size() + 1, 0);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        const auto& seg = pieces[k].segment;
        roots_at[k + 1] = roots_at[k] + (seg.roots_end - seg.roots_begin);
        rays_at[k + 1] = rays_at[k] + (seg.rays_end - seg.rays_begin);
    }
    Wave& roots = s.waves[0];
    roots.resize(roots_at.back());
    s.waves[1].resize(rays_at.back());  // the stage exists only for max_depth >= 1
    tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t k) {
        const SecondaryBuffers::Data::Gathered& g = *pieces[k].from;
        const auto& seg = pieces[k].segment;
        for (std::size_t r = seg.roots_begin; r < seg.roots_end; ++r) {
            roots.rays[roots_at[k] + (r - seg.roots_begin)].pixel = g.pixel[r];
        }
        Wave& first = s.waves[1];
        for (std::size_t j = seg.rays_begin; j < seg.rays_end; ++j) {
            const std::size_t at = rays_at[k] + (j - seg.rays_begin);
            const std::size_t root = roots_at[k] + (g.root[j] - seg.roots_begin);
            first.rays[at] = g.rays[j];
            first.kind[at] = g.kind[j];
            roots.child[2 * root + g.kind[j]] = std::int32_t(at);
        }
    });
    // Depth by depth: the rays the last depth spawned, sorted and traced in packets.
    for (int depth = 1; depth <= max_depth; ++depth) {
        if (depth > 1) make_next(s.waves[std::size_t(depth) - 1], s.waves[std::size_t(depth)]);
        if (s.waves[std::size_t(depth)].size() == 0) break;
        trace_wave(depth);
    }
    // Each pixel's shares, added to the colour its camera ray's shading gave.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, roots.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i) {
                              add_path(s.waves, 0, i, out.color[roots.rays[i].pixel]);
                          }
                      });
    const double wall_ms = wall.elapsed_ms();

    SecondaryWork sum = s.work.combine([](SecondaryWork a, const SecondaryWork& b) { return a += b; });
    const double thread_ms = sum.thread_ms();
    const double scale = thread_ms > 0.0 ? wall_ms / thread_ms : 0.0;
    stats.secondary_ms = wall_ms;
    stats.reflection_rays = sum.reflection_rays;
    stats.refraction_rays = sum.refraction_rays;
    stats.secondary_shadow_rays = sum.shadows.cast;
    stats.shadow_rays_back_side += sum.shadows.back_side;
    stats.shadow_rays_shading_side += sum.shadows.shading_side;
    stats.shadow_rays_dark_light += sum.shadows.dark_light;
    stats.secondary_packet_rays = sum.packet_rays;
    stats.secondary_single_rays = sum.single_rays;
    // A depth per entry once any tile had hits to spawn from, as the per-tile recursion reported.
    const bool gathered = std::any_of(s.gathered.begin(), s.gathered.end(),
                                      [](const SecondaryBuffers::Data::Gathered& g) { return g.called; });
    if (gathered) {
        sum.rays_per_depth.resize(std::size_t(max_depth), 0);
        sum.packet_rays_per_depth.resize(std::size_t(max_depth), 0);
    }
    stats.secondary_rays_per_depth = sum.rays_per_depth;
    stats.secondary_mrays_per_s_per_depth.clear();
    for (std::size_t k = 0; k < sum.rays_per_depth.size(); ++k) {
        const double ms = k < sum.ms_per_depth.size() ? sum.ms_per_depth[k] * scale : 0.0;
        stats.secondary_mrays_per_s_per_depth.push_back(mrays_per_s(sum.rays_per_depth[k], ms));
    }
    stats.secondary_packet_rays_per_depth = sum.packet_rays_per_depth;
    stats.reflection_mrays_per_s = mrays_per_s(sum.reflection_rays, sum.reflection_ms * scale);
    stats.refraction_mrays_per_s = mrays_per_s(sum.refraction_rays, sum.refraction_ms * scale);
    stats.secondary_shadow_mrays_per_s = mrays_per_s(sum.shadows.cast, sum.shadow_ms * scale);
}

}  // namespace dynrt::detail
