#pragma once
// Every way dynrt traces a ray, behind one call, so each stress check runs on all of them:
// the single-ray tracer and the packet tracer on a triangle BVH, and both again through the
// two-level structure with the mesh as a transformed instance (rays reach it in object space).
// Plus the counters the suite reports: rays that escape a closed mesh, and disagreements with
// the exact double-precision reference.

#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/bvh/watertight_intersector.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/two_level_packet.h"
#include "dynrt/scene/scene.h"

#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <tbb/parallel_for.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace dynrt::stress {

enum class Path : std::uint8_t { kSingle, kPacket, kTwoLevelSingle, kTwoLevelPacket };
inline constexpr std::array<Path, 4> kPaths = {Path::kSingle, Path::kPacket, Path::kTwoLevelSingle,
                                               Path::kTwoLevelPacket};

inline const char* path_name(Path path) {
    switch (path) {
        case Path::kSingle: return "single";
        case Path::kPacket: return "packet";
        case Path::kTwoLevelSingle: return "two-level single";
        case Path::kTwoLevelPacket: return "two-level packet";
    }
    return "?";
}

/// What every path answered for a batch of rays.
struct Answers {
    std::vector<bvh::Hit> closest;
    std::vector<std::uint8_t> any;
};

/// One mesh made traceable every way. The single and packet paths trace `world` directly; the
/// two-level paths trace `object` (the same mesh in its own space) as an instance placed by
/// `object_to_world`, whose inverse is computed in double. With object == world and an identity
/// placement all four paths see the very same triangles.
class Tracers {
public:
    Tracers(std::vector<bvh::Triangle> world, std::vector<bvh::Triangle> object, const glm::dmat4& object_to_world,
            const bvh::BuildConfig& config = {})
        : world_(std::move(world)), object_(std::move(object)) {
        tree_ = bvh::build_triangle_bvh(world_, config);
        object_tree_ = bvh::build_triangle_bvh(object_, config);
        tlas_ = place(object_tree_, object_to_world);
    }

    /// The top level points into this object: neither copied nor moved.
    Tracers(const Tracers&) = delete;
    Tracers& operator=(const Tracers&) = delete;

    /// Both paths on the same world triangles (placement: identity).
    explicit Tracers(std::vector<bvh::Triangle> world, const bvh::BuildConfig& config = {})
        : Tracers(world, world, glm::dmat4(1.0), config) {}

    const bvh::TriangleBvh& tree() const { return tree_; }
    const bvh::TriangleBvh& object_tree() const { return object_tree_; }
    const std::vector<bvh::Triangle>& world() const { return world_; }
    const std::vector<bvh::Triangle>& object() const { return object_; }

    /// Closest hit and any-hit of every ray along `path`, in parallel.
    void trace(Path path, std::span<const bvh::Ray> rays, Answers& out) const {
        trace(tree_, tlas_, path, rays, out);
    }

    /// A top level holding `tree` as its one instance, placed by `object_to_world` (inverse in
    /// double) and always transformed, even for the identity, so rays take the instance path.
    static bvh::TwoLevelBvh place(const bvh::TriangleBvh& tree, const glm::dmat4& object_to_world) {
        bvh::Instance instance;
        instance.blas = &tree;
        instance.identity = false;
        instance.object_to_world = glm::mat4(object_to_world);
        instance.world_to_object = glm::mat4(glm::inverse(glm::dmat4(instance.object_to_world)));
        instance.object = 0;
        bvh::TwoLevelBvh tlas;
        bvh::build_top_level(tlas, {instance});
        return tlas;
    }

    /// The same for any tree and top level: the single and packet paths trace `tree`, the
    /// two-level ones `tlas`.
    static void trace(const bvh::TriangleBvh& tree, const bvh::TwoLevelBvh& tlas, Path path,
                      std::span<const bvh::Ray> rays, Answers& out) {
        out.closest.assign(rays.size(), bvh::Hit{});
        out.any.assign(rays.size(), 0);
        const std::size_t packets = (rays.size() + packet::kPacketRays - 1) / packet::kPacketRays;
        tbb::parallel_for(std::size_t(0), packets, [&](std::size_t p) {
            const std::size_t first = p * packet::kPacketRays;
            const std::size_t n = std::min<std::size_t>(packet::kPacketRays, rays.size() - first);
            if (path == Path::kSingle || path == Path::kTwoLevelSingle) {
                for (std::size_t i = first; i < first + n; ++i) {
                    if (path == Path::kSingle) {
                        out.closest[i] = bvh::intersect_closest(tree, rays[i]);
                        out.any[i] = bvh::intersect_any(tree, rays[i]);
                    } else {
                        out.closest[i] = bvh::intersect_closest(tlas, rays[i]).hit;
                        out.any[i] = bvh::intersect_any(tlas, rays[i]);
                    }
                }
                return;
            }
            auto packet = std::make_unique<packet::RayPacket>();
            packet->clear();
            for (std::size_t k = 0; k < n; ++k) packet->set_ray(int(k), rays[first + k]);
            packet::LaneMask occluded;
            if (path == Path::kPacket) {
                auto hits = std::make_unique<packet::PacketHits>();
                packet::intersect_closest(tree, *packet, *hits);
                packet::intersect_any(tree, *packet, occluded);
                for (std::size_t k = 0; k < n; ++k) out.closest[first + k] = hits->hit(int(k));
            } else {
                auto hits = std::make_unique<packet::InstanceHits>();
                packet::intersect_closest(tlas, *packet, *hits);
                packet::intersect_any(tlas, *packet, occluded);
                for (std::size_t k = 0; k < n; ++k) out.closest[first + k] = hits->hit(int(k)).hit;
            }
            for (std::size_t k = 0; k < n; ++k) out.any[first + k] = occluded.test(int(k));
        });
    }

private:
    std::vector<bvh::Triangle> world_, object_;
    bvh::TriangleBvh tree_, object_tree_;
    bvh::TwoLevelBvh tlas_;
};

/// Closest hit by the watertight test over every triangle, degenerate ones included when
/// `with_degenerate` (a refitted tree keeps triangles that became degenerate; a build drops
/// them). Ties in t go to the lower index, as in the tracers (bvh::testing's brute force keeps
/// the last of equal hits, which only matters where triangles coincide).
inline bvh::Hit brute_force_closest(std::span<const bvh::Triangle> tris, const bvh::Ray& ray, bool with_degenerate) {
    const bvh::WatertightRay wray(ray);
    bvh::Hit best;
    float tmax = ray.tmax;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        if (!with_degenerate && bvh::is_degenerate(tris[i])) continue;
        bvh::Hit h;
        if (bvh::intersect_watertight(wray, tris[i], ray.tmin, tmax, h) && (h.t < best.t || !best.is_hit())) {
            best = h;
            best.prim = std::uint32_t(i);
            tmax = h.t;
        }
    }
    return best;
}

/// Bit-for-bit equality of two hits (t, u, v and triangle).
inline bool same_hit(const bvh::Hit& a, const bvh::Hit& b) {
    return a.prim == b.prim && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

/// Rays that escape a closed mesh from inside, per path: no closest hit, or no any-hit.
struct LeakCount {
    std::uint64_t rays = 0;
    std::uint64_t closest_misses = 0;
    std::uint64_t any_misses = 0;
    std::string first;  ///< the first escaping ray, for the failure message

    std::uint64_t leaks() const { return closest_misses + any_misses; }
};

inline std::string describe(const bvh::Ray& r) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "org (%a %a %a) dir (%a %a %a)", r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y,
                  r.dir.z);
    return buf;
}

inline void count_leaks(std::span<const bvh::Ray> rays, const Answers& answers, LeakCount& count) {
    count.rays += rays.size();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool miss = !answers.closest[i].is_hit(), no_any = answers.any[i] == 0;
        count.closest_misses += miss;
        count.any_misses += no_any;
        if ((miss || no_any) && count.first.empty()) {
            count.first = describe(rays[i]) + (miss ? " (no closest hit)" : " (no any-hit)");
        }
    }
}

/// A scene of one object holding `tris` (three own vertices per triangle, identity transform),
/// posed, with the exact reference built over it.
struct ReferenceWorld {
    Scene scene;
    anim::PosedScene posed;
    std::unique_ptr<reference::ReferenceTracer> tracer;

    explicit ReferenceWorld(std::span<const bvh::Triangle> tris) {
        scene.source = "stress";
        scene.materials.push_back(Material{});
        Object object;
        object.name = "mesh";
        for (const bvh::Triangle& t : tris) {
            const auto base = static_cast<std::uint32_t>(object.mesh.positions.size());
            object.mesh.positions.insert(object.mesh.positions.end(), {t.v0, t.v1, t.v2});
            object.mesh.triangles.emplace_back(base, base + 1, base + 2);
        }
        scene.objects.push_back(std::move(object));
        anim::pose_scene(scene, 0, posed);
        tracer = std::make_unique<reference::ReferenceTracer>(scene, posed);
    }
};

/// Closest hits checked against the reference: where it says the answer is determined (kNone),
/// hit or miss, triangle and t (within t_rel_tol relative) must match; on a shared edge or
/// vertex (kPrimitive) a hit is required and t must match within t_rel_tol + t_spread_rel;
/// kAny rays are counted and skipped.
struct Agreement {
    std::uint64_t rays = 0;
    std::uint64_t ambiguous_primitive = 0;
    std::uint64_t ambiguous_any = 0;
    std::uint64_t disagreements = 0;
    std::string first;
};

inline void check_against_reference(std::span<const bvh::Ray> rays, std::span<const reference::ReferenceHit> want,
                                    const Answers& got, Agreement& out, double t_rel_tol = 1e-5) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ++out.rays;
        const reference::ReferenceHit& w = want[i];
        const bvh::Hit& g = got.closest[i];
        std::string bad;
        if (w.ambiguity == reference::Ambiguity::kAny) {
            ++out.ambiguous_any;
            continue;
        }
        const auto t_bad = [&](double extra) {
            return std::fabs(double(g.t) - w.t) > (t_rel_tol + extra) * std::fabs(w.t);
        };
        if (w.ambiguity == reference::Ambiguity::kPrimitive) {
            ++out.ambiguous_primitive;
            if (!g.is_hit()) bad = "miss on a shared edge";
            else if (t_bad(w.t_spread_rel)) bad = "t off";
        } else if (g.is_hit() != w.is_hit()) {
            bad = g.is_hit() ? "hit where the reference misses" : "miss where the reference hits";
        } else if (g.is_hit() && std::int32_t(g.prim) != w.prim) {
            bad = "other triangle";
        } else if (g.is_hit() && t_bad(0.0)) {
            bad = "t off";
        }
        if (bad.empty()) continue;
        ++out.disagreements;
        if (out.first.empty()) {
            std::ostringstream s;
            s.precision(9);
            s << bad << ": " << describe(rays[i]) << " got prim " << std::int64_t(g.is_hit() ? g.prim : -1) << " t "
              << g.t << ", reference prim " << w.prim << " t " << w.t << " (" << reference::to_string(w.ambiguity)
              << ")";
            out.first = s.str();
        }
    }
}

/// The reference's answers for a batch of rays, in parallel.
inline std::vector<reference::ReferenceHit> reference_hits(const reference::ReferenceTracer& ref,
                                                           std::span<const bvh::Ray> rays) {
    std::vector<reference::ReferenceHit> out(rays.size());
    tbb::parallel_for(std::size_t(0), rays.size(), [&](std::size_t i) { out[i] = ref.closest(rays[i]); });
    return out;
}

}  // namespace dynrt::stress
