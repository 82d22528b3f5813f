// Two-level BVH, packets: every lane of packet::intersect_closest / intersect_any on a
// TwoLevelBvh must equal the single-ray two-level tracer bit for bit (t, u, v, prim, object;
// any-hit verdicts), over the mixed instance scene (identity and transformed instances, shared
// trees, empty ones), near the origin and far from it, for camera packets (common origin, eyes
// inside and outside the objects), partially active packets, incoherent packets and shadow
// packets, at both lane widths with all culling and none. A single identity instance must give
// exactly the plain packet tracer's hits.

#include "two_level_test_world.h"

#include "dynrt/engine/camera.h"
#include "dynrt/packet/packet_traversal.h"
#include "dynrt/packet/simd.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/packet/two_level_packet.h"

#include <gtest/gtest.h>

#include <bit>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace dynrt::packet {
namespace {

using bvh::testing::TwoLevelWorld;

std::vector<PacketConfig> configs() {
    std::vector<PacketConfig> out;
    for (int lanes : {simd::kNativeLanes, 1}) {
        for (bool all : {true, false}) {
            PacketConfig c;
            c.lanes = lanes;
            c.culling = all ? PacketCulling{} : PacketCulling::none();
            out.push_back(c);
        }
        if (simd::kNativeLanes == 1) break;
    }
    return out;
}

std::string describe(const PacketConfig& c) {
    return "lanes " + std::to_string(c.lanes) + " culling " + c.culling.to_string();
}

/// Compares every lane of `packet` traced by both tracers under every config; returns the
/// number of hits.
int check_packet(const bvh::TwoLevelBvh& tlas, const RayPacket& packet) {
    auto hits = std::make_unique<InstanceHits>();
    int hit_count = 0;
    std::vector<bvh::InstanceHit> want(kPacketRays);
    std::vector<bool> want_any(kPacketRays);
    for (int lane = 0; lane < kPacketRays; ++lane) {
        if (!packet.active.test(lane)) continue;
        want[lane] = bvh::intersect_closest(tlas, packet.ray(lane));
        want_any[lane] = bvh::intersect_any(tlas, packet.ray(lane));
        hit_count += want[lane].is_hit();
    }
    for (const PacketConfig& config : configs()) {
        PacketStats stats;
        intersect_closest(tlas, packet, *hits, config, &stats);
        LaneMask occluded;
        intersect_any(tlas, packet, occluded, config);
        for (int lane = 0; lane < kPacketRays; ++lane) {
            const bvh::InstanceHit got = hits->hit(lane);
            if (!bvh::testing::same_bits(got, want[lane])) {
                ADD_FAILURE() << describe(config) << " lane " << lane << " "
                              << (packet.active.test(lane) ? bvh::testing::describe(packet.ray(lane)) : "inactive")
                              << ": packet " << bvh::testing::describe(got) << ", single ray "
                              << bvh::testing::describe(want[lane]);
                return hit_count;
            }
            if (occluded.test(lane) != want_any[lane]) {
                ADD_FAILURE() << describe(config) << " lane " << lane << ": any-hit packet "
                              << occluded.test(lane) << ", single ray " << want_any[lane];
                return hit_count;
            }
        }
    }
    return hit_count;
}

/// Camera packets of a width x height image (every tile) from `camera`, with every other tile
/// also traced with a random half of its lanes inactive.
int check_camera(const bvh::TwoLevelBvh& tlas, const Camera& camera, int width, int height,
                 std::mt19937& rng) {
    const packet::PinholeRays rays(camera, width, height);
    const Tiling tiling(width, height);
    auto packet = std::make_unique<RayPacket>();
    int hits = 0;
    for (int i = 0; i < tiling.count(); ++i) {
        fill_tile(tiling.tile(i), [&](int x, int y) { return rays.ray(x, y); }, *packet);
        hits += check_packet(tlas, *packet);
        if (i % 2 == 0) {
            for (int lane = 0; lane < kPacketRays; ++lane) {
                if (rng() % 2 == 0) packet->active.reset(lane);
            }
            hits += check_packet(tlas, *packet);
        }
        if (::testing::Test::HasFailure()) return hits;
    }
    return hits;
}

void check_world(const TwoLevelWorld& w, std::uint32_t seed, int cameras) {
    std::mt19937 rng(seed);
    const bvh::Aabb bounds = w.world_bounds();
    const glm::vec3 c = bounds.center();
    const float radius = 0.5f * glm::length(bounds.extent());
    int hits = 0;
    for (int k = 0; k < cameras; ++k) {
        Camera camera;
        // Half the eyes inside the scene (often inside objects), half outside it.
        const float distance = k % 2 == 0 ? 0.3f * radius : 2.5f * radius;
        camera.eye = c + distance * bvh::testing::random_direction(rng);
        camera.target = c + 0.3f * radius * bvh::testing::random_direction(rng);
        camera.fov_y_deg = k % 3 == 0 ? 120.0f : 40.0f;
        hits += check_camera(w.tlas, camera, 40, 24, rng);
        ASSERT_FALSE(::testing::Test::HasFailure()) << "camera " << k;
    }
    EXPECT_GT(hits, cameras * 100);
}

TEST(TwoLevelPacket, CameraPacketsEqualSingleRays) {
    TwoLevelWorld w = bvh::testing::mixed_world();
    w.build();
    check_world(w, 1, 16);
}

TEST(TwoLevelPacket, CameraPacketsFarFromOriginEqualSingleRays) {
    TwoLevelWorld w = bvh::testing::mixed_world(glm::dvec3(1.0e4, -2.0e4, 3.0e4));
    w.build();
    check_world(w, 2, 8);
}

TEST(TwoLevelPacket, IncoherentAndShadowPacketsEqualSingleRays) {
    TwoLevelWorld w = bvh::testing::mixed_world();
    w.build();
    const bvh::Aabb bounds = w.world_bounds();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto packet = std::make_unique<RayPacket>();
    const glm::vec3 light = bounds.hi + bounds.extent();
    int hits = 0;
    for (int p = 0; p < 24; ++p) {
        packet->clear();
        for (int lane = 0; lane < kPacketRays; ++lane) {
            bvh::Ray r;
            r.org = bvh::testing::random_point(rng, bounds.lo, bounds.hi);
            if (p % 2 == 0) {
                // Incoherent: random directions, some segments.
                r.dir = bvh::testing::random_direction(rng);
                if (lane % 3 == 0) r.tmax = 4.0f * u(rng);
            } else {
                // Shadow-like: distinct origins toward one light, t in [0, 1].
                r.dir = light - r.org;
                r.tmax = 1.0f;
            }
            packet->set_ray(lane, r);
        }
        hits += check_packet(w.tlas, *packet);
        ASSERT_FALSE(::testing::Test::HasFailure()) << "packet " << p;
    }
    EXPECT_GT(hits, 1000);
}

/// Shadow packets from one light, outside the scene's bounds, toward random points of `w`.
std::vector<RayPacket> light_packets(const TwoLevelWorld& w, std::uint32_t seed, int count) {
    const bvh::Aabb bounds = w.world_bounds();
    std::mt19937 rng(seed);
    const glm::vec3 light = bounds.hi + 0.25f * bounds.extent();
    std::vector<RayPacket> out;
    out.resize(static_cast<std::size_t>(count));
    for (RayPacket& packet : out) {
        packet.clear();
        const glm::vec3 focus = bvh::testing::random_point(rng, bounds.lo, bounds.hi);
        for (int lane = 0; lane < kPacketRays; ++lane) {
            const glm::vec3 end = focus + 0.2f * bounds.extent() * (bvh::testing::random_point(rng, glm::vec3(-1.0f), glm::vec3(1.0f)));
            packet.set_ray(lane, bvh::Ray{light, end - light, 0.0f, 1.0f});
        }
    }
    return out;
}

/// Whether triangle `prim` of instance `instance` blocks `ray` (in its object space, as the
/// tracers carry it).
bool blocks(const TwoLevelWorld& w, std::uint32_t instance, std::uint32_t prim, const bvh::Ray& ray) {
    const bvh::Instance& inst = w.tlas.instances[instance];
    const bvh::Triangle& tri = w.meshes[w.objects[inst.object].mesh][prim];
    const bvh::Ray local = bvh::to_object_space(inst, ray);
    bvh::Hit hit;
    return bvh::intersect_watertight(bvh::WatertightRay(local), tri, local.tmin, local.tmax, hit);
}

// The occluder search (an occluder cache's questions): the occluders a trace reports block
// their rays; their triangles, tested first by later packets, answer rays without changing any
// verdict; and a triangle that is not the tree's would change verdicts, so the check can fail.
TEST(TwoLevelPacket, OccluderSearchKeepsEveryVerdictAndNamesRealOccluders) {
    TwoLevelWorld w = bvh::testing::mixed_world();
    w.build();
    const std::vector<RayPacket> packets = light_packets(w, 11, 32);
    std::vector<InstanceTriangle> guesses;  // learnt from the packets traced so far
    int answered_first = 0, named = 0;
    for (const PacketConfig& config : configs()) {
        for (const RayPacket& packet : packets) {
            InstanceOccluderSearch search;
            search.test_first = guesses;
            alignas(64) std::uint32_t instance[kPacketRays], prim[kPacketRays];
            search.occluder_instance = instance;
            search.occluder_prim = prim;
            LaneMask occluded;
            intersect_any(w.tlas, packet, occluded, config, nullptr, &search);
            answered_first += search.blocked_first.count();
            EXPECT_EQ(search.blocked_first & ~occluded, LaneMask{});
            for (int lane = 0; lane < kPacketRays; ++lane) {
                const bvh::Ray ray = packet.ray(lane);
                ASSERT_EQ(occluded.test(lane), bvh::intersect_any(w.tlas, ray)) << describe(config) << " lane " << lane;
                if (!occluded.test(lane) || prim[lane] == bvh::kInvalidId) continue;
                ASSERT_LT(instance[lane], w.tlas.instances.size());
                ASSERT_TRUE(blocks(w, instance[lane], prim[lane], ray)) << describe(config) << " lane " << lane;
                ++named;
                if (guesses.size() < 6 && lane % 64 == 0) {
                    const bvh::Instance& inst = w.tlas.instances[instance[lane]];
                    guesses.push_back({instance[lane], {w.meshes[w.objects[inst.object].mesh][prim[lane]], prim[lane]}});
                }
            }
        }
    }
    EXPECT_GT(named, 1000);
    EXPECT_GT(answered_first, 100);  // the triangles tested first did answer rays

    // A triangle that is not the tree's, huge and through the light (in instance 0's object
    // space, where the rays start on it): intersect_first believes it blocks every ray that
    // leaves its plane, and the verdicts then differ from the single-ray tracer's.
    const bvh::Ray from_light = bvh::to_object_space(w.tlas.instances[0], packets[0].ray(0));
    const glm::vec3 o = from_light.org;
    const float r = 100.0f * glm::length(w.world_bounds().extent());
    const std::vector<InstanceTriangle> foreign{
        {0, {bvh::Triangle{o + glm::vec3(-r, -r, 0.0f), o + glm::vec3(3.0f * r, -r, 0.0f), o + glm::vec3(-r, 3.0f * r, 0.0f)}, 0}}};
    int differ = 0;
    for (const RayPacket& packet : packets) {
        InstanceOccluderSearch search;
        search.test_first = foreign;
        LaneMask occluded;
        intersect_any(w.tlas, packet, occluded, PacketConfig{}, nullptr, &search);
        for (int lane = 0; lane < kPacketRays; ++lane) differ += occluded.test(lane) != bvh::intersect_any(w.tlas, packet.ray(lane));
    }
    EXPECT_GT(differ, 0);
}

TEST(TwoLevelPacket, CoincidentInstancesTieToTheLowestObjectAsSingleRays) {
    // One closed mesh placed three times at the same spot (identity, identity, and transformed
    // by the identity matrix, so the same bits): every hit is a three-way tie in t that the
    // object id must break, in both tracers, whatever the instance order.
    const std::vector<bvh::Triangle> mesh = bvh::testing::icosphere_mesh(2, 1.0f).triangles();
    const bvh::TriangleBvh tree = bvh::build_triangle_bvh(mesh, bvh::BuildConfig{});
    std::vector<bvh::Instance> instances(3);
    const std::uint32_t ids[3] = {9, 2, 5};
    for (int i = 0; i < 3; ++i) {
        instances[i].blas = &tree;
        instances[i].object = ids[i];
        instances[i].identity = i != 1;
    }
    bvh::TwoLevelBvh tlas;
    bvh::build_top_level(tlas, instances);
    std::mt19937 rng(6);
    int hits = 0;
    for (int k = 0; k < 4; ++k) {
        Camera camera;
        camera.eye = (k % 2 == 0 ? 0.5f : 4.0f) * bvh::testing::random_direction(rng);
        camera.target = 0.2f * bvh::testing::random_direction(rng);
        hits += check_camera(tlas, camera, 32, 32, rng);
        ASSERT_FALSE(::testing::Test::HasFailure()) << "camera " << k;
    }
    EXPECT_GT(hits, 1000);
    auto packet = std::make_unique<RayPacket>();
    auto out = std::make_unique<InstanceHits>();
    const packet::PinholeRays rays(Camera{}, 16, 16);
    fill_tile(Tile{0, 0, 16, 16}, [&](int x, int y) { return rays.ray(x, y); }, *packet);
    intersect_closest(tlas, *packet, *out);
    for (int lane = 0; lane < kPacketRays; ++lane) {
        if (out->hits.prim[lane] != bvh::kInvalidId) {
            EXPECT_EQ(out->object[lane], 2u) << lane;
        }
    }
}

TEST(TwoLevelPacket, SingleIdentityInstanceEqualsPlainPacketTracer) {
    std::vector<bvh::Triangle> tris = bvh::testing::icosphere_mesh(4, 2.0f).triangles();
    const std::vector<bvh::Triangle> soup = bvh::testing::random_soup(4, 3000, 4.0f, 0.1f, glm::vec3(-2.0f));
    tris.insert(tris.end(), soup.begin(), soup.end());
    const bvh::TriangleBvh tree = bvh::build_triangle_bvh(tris, bvh::BuildConfig{});
    bvh::Instance instance;
    instance.blas = &tree;
    instance.object = 0;
    bvh::TwoLevelBvh tlas;
    bvh::build_top_level(tlas, {instance});

    auto packet = std::make_unique<RayPacket>();
    auto plain = std::make_unique<PacketHits>();
    auto two_level = std::make_unique<InstanceHits>();
    std::mt19937 rng(5);
    int hits = 0;
    for (int k = 0; k < 6; ++k) {
        Camera camera;
        camera.eye = glm::vec3(0.0f) + (k % 2 == 0 ? 1.0f : 8.0f) * bvh::testing::random_direction(rng);
        camera.target = glm::vec3(0.0f);
        const packet::PinholeRays rays(camera, 64, 48);
        const Tiling tiling(64, 48);
        for (int i = 0; i < tiling.count(); ++i) {
            fill_tile(tiling.tile(i), [&](int x, int y) { return rays.ray(x, y); }, *packet);
            for (const PacketConfig& config : configs()) {
                intersect_closest(tree, *packet, *plain, config);
                intersect_closest(tlas, *packet, *two_level, config);
                for (int lane = 0; lane < kPacketRays; ++lane) {
                    const bvh::Hit want = plain->hit(lane);
                    const bvh::InstanceHit got = two_level->hit(lane);
                    ASSERT_TRUE(bvh::testing::same_bits(got, bvh::InstanceHit{want, want.is_hit() ? 0u : bvh::kInvalidId}))
                        << "lane " << lane << ": " << bvh::testing::describe(got);
                    hits += want.is_hit();
                }
                LaneMask plain_any, two_level_any;
                intersect_any(tree, *packet, plain_any, config);
                intersect_any(tlas, *packet, two_level_any, config);
                ASSERT_EQ(plain_any, two_level_any);
            }
        }
    }
    EXPECT_GT(hits, 10000);
}

TEST(TwoLevelPacket, EmptyTopLevelAndEmptyPacketMiss) {
    bvh::TwoLevelBvh tlas;
    bvh::build_top_level(tlas, {});
    auto packet = std::make_unique<RayPacket>();
    packet->clear();
    for (int lane = 0; lane < kPacketRays; lane += 3) {
        packet->set_ray(lane, bvh::testing::make_ray(glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f)));
    }
    auto hits = std::make_unique<InstanceHits>();
    for (int lane = 0; lane < kPacketRays; ++lane) hits->object[lane] = 3;  // must be overwritten
    intersect_closest(tlas, *packet, *hits);
    LaneMask occluded;
    occluded.set(5);
    intersect_any(tlas, *packet, occluded);
    EXPECT_FALSE(occluded.any());
    for (int lane = 0; lane < kPacketRays; ++lane) {
        ASSERT_TRUE(bvh::testing::same_bits(hits->hit(lane), bvh::InstanceHit{})) << lane;
    }
}

TEST(TwoLevelPacket, RejectsOtherLaneWidths) {
    bvh::TwoLevelBvh tlas;
    auto packet = std::make_unique<RayPacket>();
    packet->clear();
    auto hits = std::make_unique<InstanceHits>();
    PacketConfig config;
    config.lanes = 3;
    EXPECT_THROW(intersect_closest(tlas, *packet, *hits, config), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt::packet
