// Packet traversal against the single-ray tracer: for every pixel of every tile, the packet's
// closest hit must equal bvh::intersect_closest bit for bit (t, u, v and prim), and its any-hit
// verdict must equal bvh::intersect_any, over procedural scenes and the bundled scene, random
// and axis-aligned cameras (1 and 170 degree fields of view, eyes inside the geometry), image
// sizes that are not multiples of 16, every combination of the culling stages and both lane
// widths (the native SIMD width and the scalar build of the same kernels). Shadow packets
// (distinct origins, one light) and incoherent packets (random rays) cover the paths without a
// common origin.

#include "same_bits.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/simd.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/scene/scene.h"


#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace dynrt::packet {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Accel {
    std::vector<bvh::Triangle> tris;
    bvh::TriangleBvh bvh;
    /// The same triangles' binary tree (built without the wide tree): the single-ray tracer
    /// that checks the packets runs on it, an implementation independent of the wide tree's.
    bvh::TriangleBvh binary;
    bvh::Aabb bounds;
};

Accel build_accel(const Scene& scene, bvh::BuildConfig config = {}) {
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    Accel a;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const std::vector<glm::vec3>& p = posed.objects[i].positions;
        for (const glm::uvec3& t : scene.objects[i].mesh.triangles) {
            a.tris.push_back(bvh::Triangle{p[t.x], p[t.y], p[t.z]});
            a.bounds.extend(a.tris.back().bounds());
        }
    }
    a.bvh = bvh::build_triangle_bvh(a.tris, config);
    config.wide = false;
    a.binary = bvh::build_triangle_bvh(a.tris, config);
    return a;
}

/// Every subset of the four culling stages.
std::vector<PacketCulling> all_cullings() {
    std::vector<PacketCulling> out;
    for (int m = 0; m < 16; ++m) {
        out.push_back(PacketCulling{(m & 1) != 0, (m & 2) != 0, (m & 4) != 0, (m & 8) != 0});
    }
    return out;
}

/// Every culling combination at both lane widths. The speed knobs vary across them so that
/// every path runs somewhere: leaf culling at every leaf or only at wide ones, subtrees handed
/// to single rays never, at the default, or eagerly.
std::vector<PacketConfig> all_configs() {
    std::vector<PacketConfig> out;
    int i = 0;
    for (int lanes : {simd::kNativeLanes, 1}) {
        for (const PacketCulling& c : all_cullings()) {
            PacketConfig config;
            config.culling = c;
            config.lanes = lanes;
            config.cull_min_steps = i % 2 == 0 ? 1 : PacketConfig{}.cull_min_steps;
            config.single_ray_max = i % 3 == 0 ? 0 : i % 3 == 1 ? PacketConfig{}.single_ray_max : 16;
            out.push_back(config);
            ++i;
        }
        if (simd::kNativeLanes == 1) break;
    }
    return out;
}

std::string describe(const PacketConfig& config) {
    return "lanes " + std::to_string(config.lanes) + ", culling " + config.culling.to_string() +
           ", cull_min_steps " + std::to_string(config.cull_min_steps) + ", single_ray_max " +
           std::to_string(config.single_ray_max);
}

using dynrt::test::same_bits;

/// The single-ray tracer's answers on `accel` (Accel::binary) for every lane of a packet
/// (misses for inactive lanes).
struct SingleRay {
    bvh::Hit closest[kPacketRays];
    bool any[kPacketRays];

    SingleRay(const bvh::TriangleBvh& accel, const RayPacket& packet) {
        for (int lane = 0; lane < kPacketRays; ++lane) {
            const bool active = packet.active.test(lane);
            closest[lane] = active ? bvh::intersect_closest(accel, packet.ray(lane)) : bvh::Hit{};
            any[lane] = active && bvh::intersect_any(accel, packet.ray(lane));
        }
    }
};

/// Lane-by-lane comparison of a packet's closest hits with the single-ray tracer's.
::testing::AssertionResult closest_agrees(const SingleRay& single, const RayPacket& packet,
                                          const PacketHits& hits) {
    for (int lane = 0; lane < kPacketRays; ++lane) {
        const bvh::Hit got = hits.hit(lane);
        const bvh::Hit want = single.closest[lane];
        if (got.prim != want.prim || !same_bits(got.t, want.t) || !same_bits(got.u, want.u) ||
            !same_bits(got.v, want.v)) {
            const bvh::Ray r = packet.ray(lane);
            std::ostringstream s;
            s.precision(9);
            s << "lane " << lane << (packet.active.test(lane) ? "" : " (inactive)") << ": packet prim "
              << got.prim << " t " << got.t << " u " << got.u << " v " << got.v
              << ", single ray prim " << want.prim << " t " << want.t << " u " << want.u << " v "
              << want.v << "; ray org (" << r.org.x << ", " << r.org.y << ", " << r.org.z
              << ") dir (" << r.dir.x << ", " << r.dir.y << ", " << r.dir.z << ")";
            return ::testing::AssertionFailure() << s.str();
        }
    }
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult any_agrees(const SingleRay& single, const LaneMask& occluded) {
    for (int lane = 0; lane < kPacketRays; ++lane) {
        const bool want = single.any[lane];
        if (occluded.test(lane) != want) {
            return ::testing::AssertionFailure()
                   << "lane " << lane << ": packet says " << (occluded.test(lane) ? "" : "not ")
                   << "occluded, single ray " << (want ? "occluded" : "not occluded");
        }
    }
    return ::testing::AssertionSuccess();
}

/// Shadow rays of one tile packet's hits toward `light`: from each hit point nudged along the
/// normal toward the light, to the light (t in [0, 1]); lanes without a hit or facing away from
/// the light stay inactive.
void make_shadow_packet(const std::vector<bvh::Triangle>& tris, const RayPacket& primary,
                        const PacketHits& hits, glm::vec3 light, RayPacket& out) {
    out.clear();
    for (int lane = 0; lane < kPacketRays; ++lane) {
        const bvh::Hit h = hits.hit(lane);
        if (!h.is_hit()) continue;
        const bvh::Triangle& t = tris[h.prim];
        glm::vec3 n = glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
        if (glm::dot(n, primary.ray(lane).dir) > 0.0f) n = -n;
        const glm::vec3 p = (1.0f - h.u - h.v) * t.v0 + h.u * t.v1 + h.v * t.v2;
        if (!(glm::dot(n, light - p) > 0.0f)) continue;
        bvh::Ray r;
        r.org = p + n * (1e-4f * (1.0f + glm::length(p)));
        r.dir = light - r.org;
        r.tmin = 0.0f;
        r.tmax = 1.0f;
        out.set_ray(lane, r);
    }
}

struct Totals {
    std::size_t rays = 0, hits = 0, shadow_rays = 0, occluded = 0;
    PacketStats stats;
};

/// Traces every tile of a width x height image from `camera` under every config and compares
/// with single rays: closest hits, then shadow rays toward `light` from those hits.
void check_camera(const Accel& a, const Camera& camera, int width, int height, glm::vec3 light,
                  const std::vector<PacketConfig>& configs, Totals& totals) {
    const packet::PinholeRays rays(camera, width, height);
    const Tiling tiling(width, height);
    auto primary = std::make_unique<RayPacket>();
    auto shadow = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    for (int i = 0; i < tiling.count(); ++i) {
        const Tile tile = tiling.tile(i);
        fill_tile(tile, [&](int x, int y) { return rays.ray(x, y); }, *primary);
        totals.rays += std::size_t(primary->active.count());
        const auto single = std::make_unique<SingleRay>(a.binary, *primary);
        // Shadow rays from the single-ray hits (equal to every config's, as checked below).
        for (int lane = 0; lane < kPacketRays; ++lane) {
            const bvh::Hit& h = single->closest[lane];
            hits->t[lane] = h.t;
            hits->u[lane] = h.u;
            hits->v[lane] = h.v;
            hits->prim[lane] = h.prim;
            totals.hits += h.is_hit();
        }
        make_shadow_packet(a.tris, *primary, *hits, light, *shadow);
        totals.shadow_rays += std::size_t(shadow->active.count());
        const auto single_shadow = std::make_unique<SingleRay>(a.binary, *shadow);
        for (const PacketConfig& config : configs) {
            SCOPED_TRACE(describe(config) + ", tile " + std::to_string(i));
            intersect_closest(a.bvh, *primary, *hits, config, &totals.stats);
            ASSERT_TRUE(closest_agrees(*single, *primary, *hits));
            LaneMask occluded;
            intersect_any(a.bvh, *shadow, occluded, config, &totals.stats);
            ASSERT_TRUE(any_agrees(*single_shadow, occluded));
            totals.occluded += std::size_t(occluded.count());
        }
    }
}

/// A camera from `eye` toward `target` with up chosen not parallel to the view.
Camera look(glm::vec3 eye, glm::vec3 target, float fov, glm::vec3 up = {0, 1, 0}) {
    Camera c;
    c.eye = eye;
    c.target = target;
    c.fov_y_deg = fov;
    const glm::vec3 view = glm::normalize(target - eye);
    c.up = std::fabs(glm::dot(view, glm::normalize(up))) > 0.99f ? glm::vec3(0, 0, 1) : up;
    return c;
}

/// The cameras of one scene: its default camera, axis-aligned views from every side (whose
/// central pixels have exactly zero direction components), eyes inside the geometry, random
/// cameras, and extreme fields of view.
std::vector<Camera> cameras_for(const bvh::Aabb& b, std::uint32_t seed, int random_count) {
    const glm::vec3 c = b.center();
    const float r = 0.5f * glm::length(b.extent());
    std::vector<Camera> cams = {default_camera(b)};
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const glm::vec3& axis : axes) {
        cams.push_back(look(c + 2.0f * r * axis, c, 45.0f));
        cams.push_back(look(c - 2.0f * r * axis, c, 45.0f));
    }
    cams.push_back(look(c + 0.05f * r * glm::vec3(1.0f, 0.6f, 0.3f), c + glm::vec3(1.0f, 0.25f, -0.4f), 70.0f));
    cams.push_back(look(c + 0.1f * r * glm::vec3(-0.3f, 0.2f, 0.5f), c + glm::vec3(-1.0f, -0.2f, 0.1f), 170.0f));
    Camera narrow = default_camera(b);
    narrow.fov_y_deg = 1.0f;
    cams.push_back(narrow);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> fov(1.0f, 170.0f);
    for (int i = 0; i < random_count; ++i) {
        const float reach = i % 2 == 0 ? 0.7f : 2.5f;  // inside or outside the scene box
        const glm::vec3 eye = c + reach * r * glm::vec3(u(rng), u(rng), u(rng));
        const glm::vec3 target = c + 0.5f * r * glm::vec3(u(rng), u(rng), u(rng));
        if (glm::length(target - eye) < 1e-3f * r) continue;
        cams.push_back(look(eye, target, fov(rng), glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0, 2, 0)));
    }
    return cams;
}

struct SceneCase {
    const char* label;
    std::string spec;  ///< empty: the bundled default scene
    int random_cameras;
    /// The tree the packets trace: the wide one (the default build) or the binary one. The
    /// single rays they are compared with always trace the binary tree.
    bool wide = true;
};

class PacketVsSingleRay : public ::testing::TestWithParam<SceneCase> {};

TEST_P(PacketVsSingleRay, ClosestAndAnyHitsAgreeForEveryPixel) {
    const SceneCase& param = GetParam();
    const Scene scene = load_scene(param.spec.empty() ? default_scene_path().string() : param.spec);
    bvh::BuildConfig build;
    build.wide = param.wide;
    const Accel a = build_accel(scene, build);
    ASSERT_TRUE(bvh::validate(a.bvh, a.tris, 8).empty());
    ASSERT_EQ(a.bvh.wide.empty(), !param.wide);
    const glm::vec3 light = default_camera(a.bounds).eye + glm::vec3(0.0f, 0.5f * glm::length(a.bounds.extent()), 0.0f);
    const std::vector<PacketConfig> all = all_configs();
    const int sizes[][2] = {{37, 23}, {16, 16}, {21, 18}, {17, 33}};
    Totals totals;
    int k = 0;
    for (const Camera& camera : cameras_for(a.bounds, 1234u, param.random_cameras)) {
        // The whole matrix of configs on the first four views; on the others the default
        // config of each width and a rotating eighth of the matrix, to keep the test fast.
        std::vector<PacketConfig> configs;
        if (k < 4) {
            configs = all;
        } else {
            configs = {PacketConfig{}, PacketConfig{PacketCulling{}, 1}};
            for (std::size_t j = 0; j < all.size() / 8; ++j) {
                configs.push_back(all[(std::size_t(k) * 3 + j * 8) % all.size()]);
            }
        }
        const int* size = sizes[k++ % 4];
        SCOPED_TRACE("camera " + std::to_string(k - 1) + " " + std::to_string(size[0]) + "x" +
                     std::to_string(size[1]));
        check_camera(a, camera, size[0], size[1], light, configs, totals);
        if (HasFatalFailure()) return;
    }
    // The comparisons must have had something to compare.
    EXPECT_GT(totals.hits, totals.rays / 10);
    EXPECT_LT(totals.hits, totals.rays);
    EXPECT_GT(totals.shadow_rays, 0u);
    EXPECT_GT(totals.stats.early_hits, 0u);
    EXPECT_GT(totals.stats.early_misses, 0u);
    EXPECT_GT(totals.stats.culled_active_bounds, 0u);
    EXPECT_GT(totals.stats.culled_beam_planes, 0u);
    RecordProperty("rays", int(totals.rays));
    RecordProperty("occluded", int(totals.occluded));
}

// A ground plane with spheres resting on it, one floating, and a soup box (contacts, shared
// edges along axis-aligned views), near the origin and far from it.
const std::string kComposition =
    "plane:8@0,-1,0,4#808080+sphere:600@-0.8,-0.4,0.3,0.6+sphere:300@1.2,-0.5,-0.6,0.5"
    "+sphere:200@0.1,0.9,0.2,0.35+soup:600@-0.6,-1,-2,1.4";
const std::string kFarComposition =
    "plane:6@1500,-980,-700,50+sphere:500@1480,-965,-690,15+soup:1500@1470,-980,-730,40"
    "+sphere:300@1520,-930,-690,10";

INSTANTIATE_TEST_SUITE_P(
    Scenes, PacketVsSingleRay,
    ::testing::Values(SceneCase{"sphere20000", "sphere:20000", 3},
                      SceneCase{"soup20000", "soup:20000", 3},
                      SceneCase{"composition", kComposition, 4},
                      SceneCase{"farComposition", kFarComposition, 2},
                      SceneCase{"defaultScene", "", 1},
                      SceneCase{"compositionBinaryTree", kComposition, 2, false},
                      SceneCase{"defaultSceneBinaryTree", "", 0, false}),
    [](const ::testing::TestParamInfo<SceneCase>& info) { return std::string(info.param.label); });

/// Leaf sizes and cost ratios change the tree's shape, and with it which rays share leaves.
TEST(PacketTraversal, AgreesUnderOtherBuildConfigs) {
    const Scene scene = load_scene(kComposition);
    struct Variant {
        unsigned leaf;
        float ratio;
        bool compact;    // compact leaves (the corners read through the triangles' indices)
        bool quantized;  // quantised nodes (the boxes decoded from 8-bit planes)
    };
    for (const Variant v : {Variant{1u, 1.0f, false, false}, Variant{16u, 0.1f, false, false},
                            Variant{4u, 4.0f, false, false}, Variant{8u, 1.0f, true, false},
                            Variant{16u, 0.1f, true, false}, Variant{8u, 1.0f, false, true},
                            Variant{1u, 1.0f, true, true}}) {
        bvh::BuildConfig config;
        config.leaf_size_max = v.leaf;
        config.cost_ratio = v.ratio;
        config.compact_leaves = v.compact;
        config.quantized_nodes = v.quantized;
        const Accel a = build_accel(scene, config);
        ASSERT_EQ(a.bvh.wide.compact, v.compact);
        ASSERT_EQ(a.bvh.wide.quantized, v.quantized);
        SCOPED_TRACE("leaf " + std::to_string(v.leaf) + (v.compact ? ", compact" : "") +
                     (v.quantized ? ", quantised" : ""));
        Totals totals;
        check_camera(a, default_camera(a.bounds), 37, 23, glm::vec3(2, 8, 3), all_configs(), totals);
        check_camera(a, look(glm::vec3(0, 0.2f, 0), glm::vec3(1, 0, 0), 120.0f), 20, 20,
                     glm::vec3(2, 8, 3), all_configs(), totals);
        if (HasFatalFailure()) return;
    }
}

/// Quantised nodes far from the origin (1500 units out, where a float's step is 1/8192 and the
/// planes' grid is coarser still): packets and single rays agree with the exact reference.
TEST(PacketTraversal, AgreesWithQuantizedNodesFarFromTheOrigin) {
    const Scene scene = load_scene(kFarComposition);
    bvh::BuildConfig config;
    config.quantized_nodes = true;
    const Accel a = build_accel(scene, config);
    ASSERT_TRUE(a.bvh.wide.quantized);
    Totals totals;
    check_camera(a, default_camera(a.bounds), 29, 31, glm::vec3(1500, -900, -650), all_configs(), totals);
    EXPECT_GT(totals.hits, totals.rays / 10);
    EXPECT_GT(totals.occluded, 0u);
}

/// A one-leaf scene where each culling stage must remove something, seen by one 16x16 packet
/// from (0, 0, 4) looking down -z with tmax 3.5: a quad at z = 0 filling the view lies beyond
/// tmax (near/far), a triangle off to the side lies outside the beam (beam planes), one cuts
/// across the beam's corner region with its vertices outside different beam planes (edges),
/// and a small triangle at z = 1 is hit.
TEST(PacketTraversal, EachCullingStageCullsAndResultsStayExact) {
    Scene scene;
    scene.source = "culling";
    scene.materials.push_back(Material{});
    const auto add = [&](const char* name, std::vector<glm::vec3> p) {
        Object o;
        o.name = name;
        o.mesh.positions = std::move(p);
        for (std::uint32_t i = 0; i + 2 < o.mesh.positions.size(); i += 3) {
            o.mesh.triangles.push_back(glm::uvec3(i, i + 1, i + 2));
        }
        scene.objects.push_back(o);
    };
    add("far quad", {{-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, -3, 0}, {3, 3, 0}, {-3, 3, 0}});
    add("aside", {{5, 0, 0.5f}, {6, 0, 0.5f}, {5, 1, 0.5f}});
    add("corner", {{1.0f, 3.0f, 0.6f}, {3.0f, 1.0f, 0.6f}, {3.0f, 3.0f, 0.6f}});
    add("near", {{-0.2f, -0.2f, 1}, {0.2f, -0.2f, 1}, {0, 0.2f, 1}});
    bvh::BuildConfig one_leaf;
    one_leaf.cost_ratio = 0.01f;
    one_leaf.leaf_size_max = 16;
    const Accel a = build_accel(scene, one_leaf);
    ASSERT_EQ(bvh::compute_stats(a.bvh).leaves, 1u);

    Camera camera;
    camera.eye = glm::vec3(0, 0, 4);
    camera.target = glm::vec3(0, 0, 0);
    camera.fov_y_deg = 40.0f;
    const packet::PinholeRays rays(camera, 16, 16);
    auto packet = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    fill_tile(Tile{0, 0, 16, 16}, [&](int x, int y) {
        bvh::Ray r = rays.ray(x, y);
        r.tmax = 3.5f;
        return r;
    }, *packet);
    const auto single = std::make_unique<SingleRay>(a.binary, *packet);
    int hit_count = 0;
    for (int lane = 0; lane < kPacketRays; ++lane) hit_count += single->closest[lane].is_hit();
    EXPECT_GT(hit_count, 0);
    EXPECT_LT(hit_count, kPacketRays);
    for (int lanes : {simd::kNativeLanes, 1}) {
        PacketConfig config;
        config.lanes = lanes;
        config.cull_min_steps = 1;
        config.single_ray_max = 0;
        PacketStats stats;
        intersect_closest(a.bvh, *packet, *hits, config, &stats);
        EXPECT_TRUE(closest_agrees(*single, *packet, *hits));
        LaneMask occluded;
        intersect_any(a.bvh, *packet, occluded, config, &stats);
        EXPECT_TRUE(any_agrees(*single, occluded));
        SCOPED_TRACE("lanes " + std::to_string(lanes));
        // Each stage removes one triangle for all 256 rays, in both traces; the far quad's two
        // triangles go to near/far.
        EXPECT_EQ(stats.culled_beam_planes, 2u * kPacketRays);
        EXPECT_EQ(stats.culled_triangle_edges, 2u * kPacketRays);
        EXPECT_EQ(stats.culled_near_far, 2u * 2u * kPacketRays);
        EXPECT_EQ(stats.ray_triangle_tests, 2u * kPacketRays);  // the near triangle, twice
    }
}

/// Incoherent packets: random origins and directions, no common origin or axis permutation,
/// random t windows; closest and any hit.
TEST(PacketTraversal, IncoherentPacketsAgree) {
    const Accel a = build_accel(load_scene("soup:2000"));
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto packet = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    const glm::vec3 lo = a.bounds.lo - a.bounds.extent() * 0.2f;
    const glm::vec3 hi = a.bounds.hi + a.bounds.extent() * 0.2f;
    std::size_t hit_count = 0;
    for (int round = 0; round < 6; ++round) {
        packet->clear();
        for (int lane = 0; lane < kPacketRays; ++lane) {
            if (round % 3 == 1 && lane % 5 == 0) continue;  // some inactive lanes
            bvh::Ray r;
            r.org = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
            const glm::vec3 to = lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng));
            r.dir = to - r.org;
            if (round % 4 == 3) r.dir[lane % 3] = 0.0f;  // zero components
            if (r.dir == glm::vec3(0.0f)) r.dir = glm::vec3(0, 0, 1);
            r.tmin = round % 2 == 0 ? 0.0f : 0.3f * u(rng);
            r.tmax = round % 3 == 0 ? kInf : 0.3f + u(rng);
            packet->set_ray(lane, r);
        }
        const auto single = std::make_unique<SingleRay>(a.binary, *packet);
        for (const PacketConfig& config : all_configs()) {
            SCOPED_TRACE(describe(config) + ", round " + std::to_string(round));
            intersect_closest(a.bvh, *packet, *hits, config);
            ASSERT_TRUE(closest_agrees(*single, *packet, *hits));
            LaneMask occluded;
            intersect_any(a.bvh, *packet, occluded, config);
            ASSERT_TRUE(any_agrees(*single, occluded));
        }
        for (int lane = 0; lane < kPacketRays; ++lane) hit_count += hits->hit(lane).is_hit();
    }
    EXPECT_GT(hit_count, 100u);
}

/// Two copies of every triangle: every hit is a tie at exactly the same t, which both tracers
/// must break the same way (the lower primitive index), whatever order they visit leaves in.
TEST(PacketTraversal, TiesGoToTheLowerPrimitiveInBothTracers) {
    Scene scene = load_scene("sphere:2000+plane:4@0,-1.2,0,2");
    const std::size_t objects = scene.objects.size();
    for (std::size_t i = 0; i < objects; ++i) scene.objects.push_back(scene.objects[i]);
    // Reversed order in the second half, so the lower index is not simply the first found.
    std::reverse(scene.objects.begin() + std::ptrdiff_t(objects), scene.objects.end());
    const Accel a = build_accel(scene);
    const std::size_t half = a.tris.size() / 2;
    const Tiling tiling(40, 40);
    auto packet = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    int hit_count = 0;
    // The default view, and one straight down onto the plane: there every triangle of the
    // plane is perpendicular to the rays' dominant axis, so the near/far stage's bound on t is
    // as tight as it gets (all three vertices at the hit's depth).
    const glm::vec3 c = a.bounds.center();
    for (const Camera& camera : {default_camera(a.bounds),
                                 look(c + glm::vec3(0.1f, 3.0f, 0.2f), c, 50.0f, glm::vec3(0, 0, 1))}) {
    const packet::PinholeRays rays(camera, 40, 40);
    for (int i = 0; i < tiling.count(); ++i) {
        fill_tile(tiling.tile(i), [&](int x, int y) { return rays.ray(x, y); }, *packet);
        const auto single = std::make_unique<SingleRay>(a.binary, *packet);
        for (const PacketConfig& config : all_configs()) {
            intersect_closest(a.bvh, *packet, *hits, config);
            ASSERT_TRUE(closest_agrees(*single, *packet, *hits)) << describe(config);
        }
        for (int lane = 0; lane < kPacketRays; ++lane) {
            if (!hits->hit(lane).is_hit()) continue;
            ++hit_count;
            EXPECT_LT(hits->prim[lane], half) << "a tie must go to the lower primitive index";
        }
        // One ray per packet: the leaf culling stages then bound exactly that ray, whose
        // current hit ties with the next copy's t, so any culling bound that is not
        // conservative to the last rounding would throw the winning copy away.
        if (i % 3 != 0) continue;
        auto lone = std::make_unique<RayPacket>();
        for (int lane = 0; lane < kPacketRays; ++lane) {
            if (!packet->active.test(lane)) continue;
            lone->clear();
            lone->set_ray(lane, packet->ray(lane));
            for (int lanes : {simd::kNativeLanes, 1}) {
                PacketConfig config;
                config.lanes = lanes;
                config.cull_min_steps = 1;
                config.single_ray_max = 0;
                intersect_closest(a.bvh, *lone, *hits, config);
                ASSERT_EQ(hits->prim[lane], single->closest[lane].prim) << "lane " << lane;
                ASSERT_EQ(hits->t[lane], single->closest[lane].t) << "lane " << lane;
            }
        }
    }
    }
    EXPECT_GT(hit_count, 100);
}

/// The comparison itself can fail: a packet result altered in one lane is caught.
TEST(PacketTraversal, ComparisonDetectsADifference) {
    const Accel a = build_accel(load_scene("sphere:2000"));
    const packet::PinholeRays rays(default_camera(a.bounds), 16, 16);
    auto packet = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    fill_tile(Tile{0, 0, 16, 16}, [&](int x, int y) { return rays.ray(x, y); }, *packet);
    intersect_closest(a.bvh, *packet, *hits);
    const auto single = std::make_unique<SingleRay>(a.binary, *packet);
    ASSERT_TRUE(closest_agrees(*single, *packet, *hits));
    const int lane = 8 * 16 + 8;  // the image centre sees the sphere
    ASSERT_TRUE(hits->hit(lane).is_hit());
    hits->t[lane] = std::nextafter(hits->t[lane], kInf);
    EXPECT_FALSE(closest_agrees(*single, *packet, *hits));
}

TEST(PacketTraversal, EmptyTreeAndEmptyPacket) {
    const bvh::TriangleBvh empty;
    auto packet = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    packet->clear();
    packet->set_ray(3, bvh::Ray{});
    intersect_closest(empty, *packet, *hits);
    for (int lane = 0; lane < kPacketRays; ++lane) EXPECT_FALSE(hits->hit(lane).is_hit());
    EXPECT_EQ(hits->t[3], kInf);
    LaneMask occluded;
    occluded.set(7);
    intersect_any(empty, *packet, occluded);
    EXPECT_FALSE(occluded.any());

    const Accel a = build_accel(load_scene("sphere:200"));
    packet->clear();
    intersect_closest(a.bvh, *packet, *hits);
    for (int lane = 0; lane < kPacketRays; ++lane) EXPECT_FALSE(hits->hit(lane).is_hit());
}

TEST(PacketCulling, ParsesAndPrintsTheStageList) {
    EXPECT_EQ(PacketCulling::parse("all"), PacketCulling{});
    EXPECT_EQ(PacketCulling::parse("none"), PacketCulling::none());
    EXPECT_EQ(PacketCulling::parse("ab,nf"), (PacketCulling{true, false, false, true}));
    EXPECT_EQ(PacketCulling::parse("edge,bp"), (PacketCulling{false, true, true, false}));
    EXPECT_EQ(PacketCulling{}.to_string(), "ab,bp,edge,nf");
    EXPECT_EQ(PacketCulling::none().to_string(), "none");
    for (const PacketCulling& c : all_cullings()) EXPECT_EQ(PacketCulling::parse(c.to_string()), c);
    EXPECT_THROW(PacketCulling::parse("ab,frustum"), std::invalid_argument);
    EXPECT_THROW(PacketCulling::parse("ab,"), std::invalid_argument);
}

TEST(PacketConfig, RejectsOtherLaneWidths) {
    const bvh::TriangleBvh empty;
    auto packet = std::make_unique<RayPacket>();
    auto hits = std::make_unique<PacketHits>();
    packet->clear();
    PacketConfig config;
    config.lanes = 3;
    EXPECT_THROW(intersect_closest(empty, *packet, *hits, config), std::invalid_argument);
}

TEST(RayPacket, TileLanesAreRowMajorAndEdgeLanesInactive) {
    auto packet = std::make_unique<RayPacket>();
    const Tile tile{32, 16, 37, 23};  // a clipped edge tile: 5 x 7 pixels
    fill_tile(tile, [](int x, int y) {
        bvh::Ray r;
        r.org = glm::vec3(float(x), float(y), 0.0f);
        return r;
    }, *packet);
    EXPECT_EQ(packet->active.count(), 35);
    EXPECT_TRUE(packet->active.test(tile_lane(tile, 36, 22)));
    EXPECT_FALSE(packet->active.test(5));
    EXPECT_EQ(packet->org_x[tile_lane(tile, 34, 20)], 34.0f);
    EXPECT_EQ(packet->org_y[tile_lane(tile, 34, 20)], 20.0f);
    EXPECT_EQ(tile_lane(tile, 33, 17), 17);
    for (int lane = 0; lane < kPacketRays; ++lane) {
        const LanePixel p = tile_pixel(tile, lane);
        EXPECT_EQ(p.inside, packet->active.test(lane));
        if (p.inside) {
            EXPECT_EQ(tile_lane(tile, p.x, p.y), lane);
        }
    }
}

}  // namespace
}  // namespace dynrt::packet
