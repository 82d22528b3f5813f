// Engine::intersect and Engine::occluded against the exact reference (tests/reference), over
// several steps of a scene holding a mesh of every motion class (static, rigid moved by
// set_transform, deformable moved by set_positions with copied and with borrowed positions,
// exploding, automatic), through both ray paths: coherent runs of 256 rays (traced as
// packets) and incoherent ones (ray by ray), which must also agree with each other bit for bit.

#include "api_test_world.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr Vec3 kCentre{0.0f, 0.0f, 0.0f};
constexpr float kHalf = 1.8f;  // half-size of the box the scene's meshes stay in

/// A scene with one mesh of each class, moved step by step; `mirror` follows it.
class World {
public:
    explicit World(Engine& engine) : engine_(engine), rng_(7) {
        static_id = mirror.add(engine, "still", sphere({-1.2f, 0.0f, 0.0f}, 0.6f), Motion::static_,
                               Transform::translation({0.0f, 0.3f, 0.0f}));
        rigid_id = mirror.add(engine, "arm", sphere({0.0f, 0.0f, 0.0f}, 0.5f, 10, 20), Motion::rigid,
                              rigid_pose(0));
        cloth_ = sheet(0.0f, 0.0f, -1.2f, 3.0f);
        cloth_id = mirror.add(engine, "cloth", cloth_, Motion::deformable);
        balloon_ = sphere({0.0f, 1.1f, 0.0f}, 0.45f);
        balloon_positions_ = balloon_.positions;
        balloon_id = mirror.add(engine, "balloon", balloon_, Motion::deformable,
                                Transform::rotation({0.0f, 0.0f, 1.0f}, 0.3f, {0.1f, 0.0f, 0.2f}),
                                Ownership::borrow, balloon_positions_);
        debris_id = mirror.add(engine, "debris", soup(rng_, 150, {0.6f, -0.6f, 0.6f}, 0.6f, 0.12f),
                               Motion::exploding);
        auto_id = mirror.add(engine, "auto", sphere({0.0f, -1.1f, 0.6f}, 0.4f), Motion::automatic);
    }

    static Transform rigid_pose(int step) {
        return Transform::rotation({0.0f, 0.6f, 0.8f}, 0.4f * float(step), {1.2f, 0.1f * float(step), 0.0f});
    }

    /// Moves every movable mesh to step `step` (> 0) and checks the automatic mesh's class.
    void move_to(int step) {
        mirror.set_transform(engine_, rigid_id, rigid_pose(step));
        mirror.set_positions(engine_, cloth_id, waved(cloth_, 0.7f * float(step)));
        // Borrowed: new values written into the same buffer, then announced.
        balloon_positions_ = scaled(balloon_, {0.0f, 1.1f, 0.0f}, 1.0f + 0.1f * float(step));
        mirror.set_positions(engine_, balloon_id, balloon_positions_);
        mirror.set_positions(engine_, debris_id,
                             soup(rng_, 150, {0.6f, -0.6f, 0.6f}, 0.6f, 0.12f).positions);
        if (step == 1 || step == 4) {
            mirror.set_transform(engine_, auto_id, Transform::translation({0.05f * float(step), 0.0f, 0.0f}));
        }
        if (step == 3) {
            const MeshData base = sphere({0.0f, -1.1f, 0.6f}, 0.4f);
            mirror.set_positions(engine_, auto_id, scaled(base, {0.0f, -1.1f, 0.6f}, 0.8f));
        }
    }

    Motion expected_auto_motion(int step) const {
        return step == 0 ? Motion::static_ : step < 3 ? Motion::rigid : Motion::deformable;
    }

    Mirror mirror;
    MeshId static_id, rigid_id, cloth_id, balloon_id, debris_id, auto_id;

private:
    Engine& engine_;
    std::mt19937 rng_;
    MeshData cloth_, balloon_;
    std::vector<float> balloon_positions_;
};

/// Both query kinds over one batch, each checked against the reference; returns the hits.
std::vector<RayHit> query_and_check(const Engine& engine, const Reference& ref, std::span<const Ray> rays,
                                    const std::string& what, Agreement& closest, Agreement& any,
                                    QueryStats* stats = nullptr) {
    std::vector<RayHit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size(), 7);
    const QueryStats s = engine.intersect(rays, hits);
    const QueryStats o = engine.occluded(rays, occluded);
    EXPECT_EQ(s.rays, rays.size());
    EXPECT_EQ(o.rays, rays.size());
    EXPECT_EQ(s.packet_rays + s.single_rays, rays.size());
    EXPECT_EQ(o.packet_rays, s.packet_rays);
    std::size_t hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hit_count += hits[i].hit();
        // Any hit within [tmin, tmax] exists exactly when a closest hit does.
        EXPECT_EQ(occluded[i], std::uint8_t(hits[i].hit())) << what << " ray " << i;
        if (!hits[i].hit()) {
            EXPECT_TRUE(std::isinf(hits[i].t) && hits[i].primitive == ~0u) << what << " ray " << i;
        }
    }
    EXPECT_EQ(s.hits, hit_count);
    EXPECT_EQ(o.hits, hit_count);
    const std::vector<Verdict> verdicts = verdicts_for(*ref.tracer, rays);
    const Agreement c = check_closest(*ref.tracer, rays, verdicts, hits, what + " intersect");
    const Agreement a = check_occluded(rays, verdicts, occluded, what + " occluded");
    for (auto [sum, part] : {std::pair{&closest, c}, std::pair{&any, a}}) {
        sum->checked += part.checked;
        sum->hits += part.hits;
        sum->ambiguous += part.ambiguous;
        sum->mismatches += part.mismatches;
    }
    if (stats) *stats = s;
    return hits;
}

TEST(ApiQueries, EveryMotionClassAgreesWithTheReferenceOnBothRayPaths) {
    Engine engine;
    World world(engine);
    std::mt19937 rng(11);
    Agreement closest, any;
    for (int step = 0; step < 5; ++step) {
        SCOPED_TRACE("step " + std::to_string(step));
        if (step > 0) world.move_to(step);
        engine.update();
        EXPECT_EQ(engine.motion(world.auto_id), world.expected_auto_motion(step));
        const Reference ref(world.mirror);

        // ---- Coherent: three runs of 256 rays in narrow cones, traced as packets ----
        std::vector<Ray> coherent;
        for (const Vec3 eye : {Vec3{4.0f, 3.0f, 5.0f}, Vec3{-3.0f, 2.5f, 4.5f}, Vec3{2.5f, -4.0f, 3.5f}}) {
            const std::vector<Ray> run = coherent_rays(rng, eye, kCentre, 0.2f, 256);
            coherent.insert(coherent.end(), run.begin(), run.end());
        }
        QueryStats stats;
        const std::vector<RayHit> packet_hits =
            query_and_check(engine, ref, coherent, "coherent", closest, any, &stats);
        EXPECT_EQ(stats.packet_rays, coherent.size());
        EXPECT_EQ(stats.single_rays, 0u);

        // ---- The same rays interleaved with incoherent ones: traced one by one ----
        const std::vector<Ray> filler = incoherent_rays(rng, kCentre, 4.0f, kHalf, coherent.size());
        std::vector<Ray> mixed;
        for (std::size_t i = 0; i < coherent.size(); ++i) {
            mixed.push_back(coherent[i]);
            mixed.push_back(filler[i]);
        }
        const std::vector<RayHit> mixed_hits = query_and_check(engine, ref, mixed, "mixed", closest, any, &stats);
        EXPECT_EQ(stats.packet_rays, 0u);
        EXPECT_EQ(stats.single_rays, mixed.size());
        int differ = 0;
        for (std::size_t i = 0; i < coherent.size(); ++i) {
            if (!identical(packet_hits[i], mixed_hits[2 * i]) && ++differ <= 5) {
                ADD_FAILURE() << "ray " << i << ": packet " << describe(packet_hits[i]) << ", single "
                              << describe(mixed_hits[2 * i]);
            }
        }

        // ---- Incoherent, and with tmin / tmax clipping (both paths) ----
        const std::vector<Ray> incoherent = incoherent_rays(rng, kCentre, 4.0f, kHalf, 500);
        query_and_check(engine, ref, incoherent, "incoherent", closest, any, &stats);
        EXPECT_EQ(stats.single_rays, incoherent.size());
        std::uniform_real_distribution<float> near(0.0f, 2.5f), span(0.0f, 3.0f);
        for (std::vector<Ray> clipped : {incoherent, coherent}) {
            for (std::size_t i = 0; i < clipped.size(); ++i) {
                const float len = std::sqrt(clipped[i].direction.x * clipped[i].direction.x +
                                            clipped[i].direction.y * clipped[i].direction.y +
                                            clipped[i].direction.z * clipped[i].direction.z);
                clipped[i].tmin = near(rng) / len;  // t is in units of the direction
                if (i % 5 != 0) clipped[i].tmax = clipped[i].tmin + span(rng) / len;
                if (i % 7 == 0) clipped[i].tmax = clipped[i].tmin;
            }
            query_and_check(engine, ref, clipped, "clipped", closest, any);
        }
    }
    EXPECT_EQ(closest.mismatches, 0u);
    EXPECT_EQ(any.mismatches, 0u);
    // The comparison must have teeth: most rays determined, many hits among them.
    EXPECT_GT(closest.checked, 20 * closest.ambiguous) << closest.ambiguous << " ambiguous";
    EXPECT_GT(closest.hits, closest.checked / 4);
    EXPECT_LT(closest.hits, closest.checked);
}

TEST(ApiQueries, ARayAloneOrInAnyBatchSizeGetsTheSameAnswer) {
    Engine engine;
    World world(engine);
    world.move_to(1);
    engine.update();
    std::mt19937 rng(3);
    // 300 coherent rays (one packet run and a tail of 44), 300 incoherent.
    std::vector<Ray> rays = coherent_rays(rng, {3.5f, 3.0f, 4.0f}, kCentre, 0.15f, 300);
    const std::vector<Ray> incoherent = incoherent_rays(rng, kCentre, 4.0f, kHalf, 300);
    rays.insert(rays.end(), incoherent.begin(), incoherent.end());
    std::vector<RayHit> all(rays.size());
    std::vector<std::uint8_t> all_occluded(rays.size());
    engine.intersect(rays, all);
    engine.occluded(rays, all_occluded);

    // Batches of 0, 1, 255 and 257 rays, taken from every offset class.
    for (const std::size_t size : {std::size_t(0), std::size_t(1), std::size_t(255), std::size_t(257)}) {
        for (const std::size_t first : {std::size_t(0), std::size_t(3), std::size_t(200), std::size_t(343)}) {
            if (first + size > rays.size()) continue;
            SCOPED_TRACE("batch of " + std::to_string(size) + " from " + std::to_string(first));
            std::vector<RayHit> hits(size);
            std::vector<std::uint8_t> occluded(size);
            const std::span<const Ray> batch(rays.data() + first, size);
            const QueryStats s = engine.intersect(batch, hits);
            const QueryStats o = engine.occluded(batch, occluded);
            EXPECT_EQ(s.rays, size);
            EXPECT_EQ(o.rays, size);
            EXPECT_EQ(s.packet_rays + s.single_rays, size);
            for (std::size_t i = 0; i < size; ++i) {
                EXPECT_TRUE(identical(hits[i], all[first + i]))
                    << "ray " << first + i << ": " << describe(hits[i]) << " vs " << describe(all[first + i]);
                EXPECT_EQ(occluded[i], all_occluded[first + i]) << "ray " << first + i;
            }
        }
    }
    // Every ray alone.
    for (std::size_t i = 0; i < rays.size(); i += 3) {
        RayHit hit;
        std::uint8_t occluded = 9;
        engine.intersect(std::span<const Ray>(&rays[i], 1), std::span<RayHit>(&hit, 1));
        engine.occluded(std::span<const Ray>(&rays[i], 1), std::span<std::uint8_t>(&occluded, 1));
        EXPECT_TRUE(identical(hit, all[i])) << "ray " << i << ": " << describe(hit) << " vs " << describe(all[i]);
        EXPECT_EQ(occluded, all_occluded[i]) << "ray " << i;
    }
    // An empty batch costs nothing and touches nothing.
    const QueryStats empty = engine.intersect(std::span<const Ray>{}, {});
    EXPECT_EQ(empty.rays, 0u);
    EXPECT_EQ(empty.hits, 0u);
}

TEST(ApiQueries, ManySmallStaticMeshesEachReportTheirOwnMeshAndTriangle) {
    // Static meshes share one tree of their concatenated triangles, and a hit on it is traced
    // back to its mesh and triangle (SceneAccel::resolve): 200 meshes of 1 to 4 triangles,
    // so that many start within one bucket of its lookup table and others straddle two.
    Engine engine;
    struct Placed {
        MeshId id;
        std::uint32_t triangle;
        float x, y;
    };
    std::vector<Placed> targets;
    float x = 0.0f;
    for (int m = 0; m < 200; ++m) {
        MeshData mesh;
        const int count = 1 + (m * 7) % 4;
        for (int k = 0; k < count; ++k, x += 1.0f) {
            // A small triangle in the plane z = 0, one unit apart along x.
            const auto first = std::uint32_t(mesh.vertices());
            for (const float v : {x, 0.0f, 0.0f, x + 0.5f, 0.0f, 0.0f, x, 0.5f, 0.0f}) mesh.positions.push_back(v);
            for (std::uint32_t i = 0; i < 3; ++i) mesh.indices.push_back(first + i);
        }
        MeshDesc desc;
        desc.name = "piece" + std::to_string(m);
        desc.positions = mesh.positions;
        desc.indices = mesh.indices;
        desc.motion = Motion::static_;
        const MeshId id = engine.add_mesh(desc);
        for (int k = 0; k < count; ++k) {
            targets.push_back(Placed{id, std::uint32_t(k), x - float(count - k) + 0.15f, 0.15f});
        }
    }
    engine.update();
    std::vector<Ray> rays;
    for (const Placed& t : targets) rays.push_back(Ray{{t.x, t.y, 1.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 2.0f});
    std::vector<RayHit> hits(rays.size());
    engine.intersect(rays, hits);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(hits[i].mesh.value, targets[i].id.value) << "ray " << i << ": " << describe(hits[i]);
        ASSERT_EQ(hits[i].primitive, targets[i].triangle) << "ray " << i << ": " << describe(hits[i]);
    }
}

TEST(ApiQueries, DirectionLengthOnlyScalesT) {
    Engine engine;
    Mirror mirror;
    mirror.add(engine, "ball", sphere({0.0f, 0.0f, 0.0f}, 1.0f), Motion::static_);
    engine.update();
    // Straight down the z axis onto the pole-free equator region: t = 4 / |d| exactly enough.
    for (const float scale : {1.0f, 0.25f, 8.0f}) {
        const Ray ray{{0.1f, 0.05f, 5.0f}, {0.0f, 0.0f, -scale}};
        RayHit hit;
        engine.intersect(std::span<const Ray>(&ray, 1), std::span<RayHit>(&hit, 1));
        ASSERT_TRUE(hit.hit());
        EXPECT_NEAR(hit.t * scale, 4.0f, 0.02f) << "scale " << scale;
        // tmax just short of the hit: a miss; tmin past the front: the back of the sphere.
        Ray short_ray = ray;
        short_ray.tmax = 3.9f / scale;
        engine.intersect(std::span<const Ray>(&short_ray, 1), std::span<RayHit>(&hit, 1));
        EXPECT_FALSE(hit.hit());
        Ray inside = ray;
        inside.tmin = 5.0f / scale;
        engine.intersect(std::span<const Ray>(&inside, 1), std::span<RayHit>(&hit, 1));
        ASSERT_TRUE(hit.hit());
        EXPECT_NEAR(hit.t * scale, 6.0f, 0.02f) << "scale " << scale;
    }
}


/// Rays held as arrays (RayArrays) get the answers of the same rays as dynrt::Ray structs, bit
/// for bit, with per-ray and with shared tmin / tmax, on both the packet and the single path.
TEST(ApiQueries, RayArraysGetTheAnswersOfTheSameRayStructs) {
    Engine engine;
    World world(engine);
    world.move_to(2);
    engine.update();
    std::mt19937 rng(5);
    std::vector<Ray> rays = coherent_rays(rng, {3.5f, 3.0f, 4.0f}, kCentre, 0.15f, 600);
    const std::vector<Ray> incoherent = incoherent_rays(rng, kCentre, 4.0f, kHalf, 300);
    rays.insert(rays.end(), incoherent.begin(), incoherent.end());
    std::uniform_real_distribution<float> near(0.0f, 1.5f), span(0.5f, 6.0f);
    for (std::size_t i = 0; i < rays.size(); i += 2) {
        rays[i].tmin = near(rng);
        rays[i].tmax = rays[i].tmin + span(rng);
    }
    std::vector<float> origins, directions, tmin, tmax;
    for (const Ray& r : rays) {
        origins.insert(origins.end(), {r.origin.x, r.origin.y, r.origin.z});
        directions.insert(directions.end(), {r.direction.x, r.direction.y, r.direction.z});
        tmin.push_back(r.tmin);
        tmax.push_back(r.tmax);
    }
    const auto compare = [&](const std::vector<Ray>& structs, const RayArrays& arrays) {
        std::vector<RayHit> expected(structs.size()), hits(structs.size());
        std::vector<std::uint8_t> expected_occluded(structs.size()), occluded(structs.size(), 7);
        const QueryStats e = engine.intersect(structs, expected);
        engine.occluded(structs, expected_occluded);
        const QueryStats s = engine.intersect(arrays, hits);
        engine.occluded(arrays, occluded);
        EXPECT_EQ(s.packet_rays, e.packet_rays);
        EXPECT_EQ(s.hits, e.hits);
        EXPECT_GT(e.packet_rays, 0u);
        EXPECT_GT(e.single_rays, 0u);
        for (std::size_t i = 0; i < structs.size(); ++i) {
            EXPECT_TRUE(identical(hits[i], expected[i]))
                << "ray " << i << ": " << describe(hits[i]) << " vs " << describe(expected[i]);
            EXPECT_EQ(occluded[i], expected_occluded[i]) << "ray " << i;
        }
    };
    compare(rays, RayArrays{origins, directions, tmin, tmax});
    // Shared limits.
    std::vector<Ray> shared = rays;
    for (Ray& r : shared) {
        r.tmin = 0.25f;
        r.tmax = 5.0f;
    }
    compare(shared, RayArrays{origins, directions, {}, {}, 0.25f, 5.0f});

    // Sizes that disagree, and a bad ray, are refused with the Ray path's messages.
    std::vector<RayHit> hits(rays.size());
    const auto refused = [&](const RayArrays& arrays, const std::string& expected) {
        try {
            engine.intersect(arrays, std::span<RayHit>(hits.data(), arrays.size()));
            ADD_FAILURE() << "accepted; expected " << expected;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), Error::Code::invalid_argument);
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
    };
    const std::span<const float> o(origins), d(directions);
    refused(RayArrays{o.first(7), d.first(7)}, "7 origin floats, not 3 per ray");
    refused(RayArrays{o.first(9), d.first(6)}, "3 origins but 6 direction floats");
    refused(RayArrays{o.first(9), d.first(9), std::span<const float>(tmin).first(2)}, "3 rays but 2 tmin values");
    refused(RayArrays{o.first(9), d.first(9), {}, std::span<const float>(tmax).first(4)}, "3 rays but 4 tmax values");
    std::vector<float> bad = directions;
    bad[3 * 17 + 1] = std::numeric_limits<float>::quiet_NaN();
    refused(RayArrays{o, bad}, "ray 17: direction is not finite");
    refused(RayArrays{o, d, {}, {}, 2.0f, 1.0f}, ": tmax is not >= tmin");
}

}  // namespace
}  // namespace dynrt::api_test
