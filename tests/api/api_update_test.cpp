// Engine::update's bookkeeping, read through the FrameStats it returns: what each motion class
// costs per step (built once, skipped, refitted, rebuilt and why), how automatic meshes are
// raised from class to class, and meshes added and removed between updates.

#include "api_test_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

/// The reasons of the step's rebuilds of mesh `id`.
std::vector<std::string> rebuild_reasons(const FrameStats& stats, MeshId id) {
    std::vector<std::string> reasons;
    for (const TreeRebuild& r : stats.rebuilds) {
        if (r.object == id.value) reasons.push_back(rebuild_reason_name(r.reason));
    }
    return reasons;
}

using Reasons = std::vector<std::string>;

/// The first hit of a ray straight down -z through (x, y).
RayHit down_at(const Engine& engine, float x, float y) {
    const Ray ray{{x, y, 10.0f}, {0.0f, 0.0f, -1.0f}};
    RayHit hit;
    engine.intersect(std::span<const Ray>(&ray, 1), std::span<RayHit>(&hit, 1));
    return hit;
}

TEST(ApiUpdate, EachClassCostsWhatItShould) {
    Engine engine;
    std::mt19937 rng(5);
    Mirror m;
    const MeshId still = m.add(engine, "still", sphere({-3.0f, 0.0f, 0.0f}, 0.5f), Motion::static_);
    const MeshId arm = m.add(engine, "arm", sphere({0.0f, 0.0f, 0.0f}, 0.5f), Motion::rigid);
    const MeshData cloth_base = sheet(3.0f, 0.0f, 0.0f, 2.0f);
    const MeshId cloth = m.add(engine, "cloth", cloth_base, Motion::deformable);
    const MeshId debris = m.add(engine, "debris", soup(rng, 100, {0.0f, 3.0f, 0.0f}, 0.5f, 0.1f),
                                Motion::exploding);
    EXPECT_EQ(engine.mesh_count(), 4u);

    // ---- First update: everything built, once ----
    FrameStats s = engine.update();
    EXPECT_EQ(s.frame, 0);
    EXPECT_EQ(s.objects_rebuilt, 4u);
    EXPECT_EQ(s.objects_skipped, 0u);
    EXPECT_EQ(s.objects_refitted, 0u);
    for (const MeshId id : {still, arm, cloth, debris}) {
        EXPECT_EQ(rebuild_reasons(s, id), Reasons{"first build"}) << "mesh " << id.value;
    }
    EXPECT_EQ(s.static_objects, 1u);
    EXPECT_EQ(s.rigid_objects, 1u);
    EXPECT_EQ(s.deformable_objects, 1u);
    EXPECT_EQ(s.exploding_objects, 1u);
    EXPECT_EQ(s.triangles, 528u * 2 + 512u + 100u);

    // ---- Nothing changed: nothing done ----
    s = engine.update();
    EXPECT_EQ(s.frame, 1);
    EXPECT_EQ(s.objects_skipped, 4u);
    EXPECT_EQ(s.objects_rebuilt + s.objects_refitted, 0u);

    // ---- Rigid: only its instance moves, its tree is never rebuilt ----
    EXPECT_TRUE(down_at(engine, 0.0f, 0.0f).hit());
    for (int step = 1; step <= 3; ++step) {
        m.set_transform(engine, arm, Transform::rotation({0.0f, 0.0f, 1.0f}, 0.5f * float(step),
                                                          {0.0f, -1.5f * float(step), 0.0f}));
        s = engine.update();
        EXPECT_EQ(s.objects_skipped, 4u) << "step " << step;
        EXPECT_EQ(s.objects_rebuilt + s.objects_refitted, 0u) << "step " << step;
        EXPECT_EQ(engine.motion(arm), Motion::rigid);
        // The queries see it where it went.
        const RayHit moved = down_at(engine, 0.0f, -1.5f * float(step));
        EXPECT_TRUE(moved.hit() && moved.mesh == arm) << "step " << step;
    }
    EXPECT_FALSE(down_at(engine, 0.0f, 0.0f).hit());

    // ---- Deformable: refitted while its SAH cost holds, rebuilt when it degrades ----
    m.set_positions(engine, cloth, waved(cloth_base, 0.3f, 0.05f));
    s = engine.update();
    EXPECT_EQ(s.objects_refitted, 1u);
    EXPECT_EQ(s.objects_rebuilt, 0u);
    EXPECT_EQ(s.objects_skipped, 3u);
    m.set_positions(engine, cloth, scrambled(cloth_base, rng));
    s = engine.update();
    EXPECT_EQ(s.objects_refitted, 1u);
    ASSERT_EQ(rebuild_reasons(s, cloth), Reasons{"sah degraded"});
    EXPECT_GT(s.rebuilds[0].sah_refitted, 1.3 * s.rebuilds[0].sah_at_last_build);
    EXPECT_EQ(engine.motion(cloth), Motion::deformable);  // declared classes never change

    // ---- Exploding: rebuilt whenever it changed, never refitted ----
    m.set_positions(engine, debris, soup(rng, 100, {0.0f, 3.0f, 0.0f}, 0.5f, 0.1f).positions);
    s = engine.update();
    EXPECT_EQ(rebuild_reasons(s, debris), Reasons{"exploding"});
    EXPECT_EQ(s.objects_refitted, 0u);
    EXPECT_EQ(s.objects_skipped, 3u);
}

TEST(ApiUpdate, RebuildThresholdDecidesBetweenRefitAndRebuild) {
    std::mt19937 rng(9);
    const MeshData base = sheet(0.0f, 0.0f, 0.0f, 2.0f);
    const std::vector<float> scramble = scrambled(base, rng);
    for (const double threshold : {0.3, std::numeric_limits<double>::infinity()}) {
        EngineOptions options;
        options.rebuild_threshold = threshold;
        Engine engine(options);
        Mirror m;
        const MeshId cloth = m.add(engine, "cloth", base, Motion::deformable);
        engine.update();
        m.set_positions(engine, cloth, scramble);
        const FrameStats s = engine.update();
        EXPECT_EQ(s.objects_refitted, 1u);
        EXPECT_EQ(s.objects_rebuilt, std::isinf(threshold) ? 0u : 1u) << "threshold " << threshold;
        // Either way the queries see the new shape exactly.
        const Reference ref(m);
        std::mt19937 ray_rng(1);
        const std::vector<Ray> rays = incoherent_rays(ray_rng, {0.0f, 0.0f, 0.0f}, 3.0f, 1.0f, 300);
        std::vector<RayHit> hits(rays.size());
        engine.intersect(rays, hits);
        const std::vector<Verdict> verdicts = verdicts_for(*ref.tracer, rays);
        EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts, hits, "scrambled").mismatches, 0u);
    }
}

TEST(ApiUpdate, AutomaticMeshesAreRaisedByTheirCallsAndNeverLowered) {
    Engine engine;
    Mirror m;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 0.5f);
    const MeshId a = m.add(engine, "a", ball, Motion::automatic);
    const MeshId b = m.add(engine, "b", sphere({2.0f, 0.0f, 0.0f}, 0.5f), Motion::automatic);
    const MeshId c = m.add(engine, "c", sphere({-2.0f, 0.0f, 0.0f}, 0.5f), Motion::automatic);
    FrameStats s = engine.update();
    for (const MeshId id : {a, b, c}) EXPECT_EQ(engine.motion(id), Motion::static_);
    EXPECT_EQ(s.static_objects, 3u);

    // a: set_transform makes it rigid (from the update on); c: set_positions deformable.
    m.set_transform(engine, a, Transform::translation({0.0f, 1.0f, 0.0f}));
    m.set_positions(engine, c, scaled(sphere({-2.0f, 0.0f, 0.0f}, 0.5f), {-2.0f, 0.0f, 0.0f}, 1.2f));
    EXPECT_EQ(engine.motion(a), Motion::static_);
    s = engine.update();
    EXPECT_EQ(engine.motion(a), Motion::rigid);
    EXPECT_EQ(engine.motion(b), Motion::static_);
    EXPECT_EQ(engine.motion(c), Motion::deformable);
    EXPECT_EQ(s.static_objects, 1u);
    EXPECT_EQ(s.rigid_objects, 1u);
    EXPECT_EQ(s.deformable_objects, 1u);
    EXPECT_EQ(rebuild_reasons(s, a), Reasons{"class changed"});
    EXPECT_EQ(rebuild_reasons(s, c), Reasons{"class changed"});
    EXPECT_EQ(rebuild_reasons(s, b), Reasons{"static group changed"});

    // A rigid one moved again stays rigid and is not rebuilt.
    m.set_transform(engine, a, Transform::translation({0.0f, 1.5f, 0.0f}));
    s = engine.update();
    EXPECT_EQ(engine.motion(a), Motion::rigid);
    EXPECT_EQ(s.objects_rebuilt, 0u);

    // a: set_positions raises it to deformable (its tree goes from object to world space);
    // a later set_transform does not lower it.
    m.set_positions(engine, a, scaled(ball, {0.0f, 0.0f, 0.0f}, 0.9f));
    s = engine.update();
    EXPECT_EQ(engine.motion(a), Motion::deformable);
    EXPECT_EQ(rebuild_reasons(s, a), Reasons{"class changed"});
    m.set_transform(engine, a, Transform::translation({0.0f, 2.0f, 0.0f}));
    s = engine.update();
    EXPECT_EQ(engine.motion(a), Motion::deformable);
    EXPECT_EQ(s.objects_refitted, 1u);  // a moved, through its world positions
    s = engine.update();
    EXPECT_EQ(engine.motion(a), Motion::deformable);
    EXPECT_EQ(engine.motion(b), Motion::static_);

    // Where it is now, as the reference sees the mirror.
    const Reference ref(m);
    std::mt19937 rng(2);
    const std::vector<Ray> rays = incoherent_rays(rng, {0.0f, 0.5f, 0.0f}, 5.0f, 2.0f, 400);
    std::vector<RayHit> hits(rays.size());
    engine.intersect(rays, hits);
    const std::vector<Verdict> verdicts = verdicts_for(*ref.tracer, rays);
    EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts, hits, "raised").mismatches, 0u);
}

TEST(ApiUpdate, AnAutomaticMeshWhoseRefitsKeepDegradingBecomesExploding) {
    EngineOptions options;
    options.rebuild_threshold = 0.0;
    Engine engine(options);
    std::mt19937 rng(4);
    Mirror m;
    // A sphere: any three of its vertices span a triangle, so no scramble makes a degenerate
    // one (whose regaining area would force a rebuild for another reason).
    const MeshData base = sphere({0.0f, 0.0f, 0.0f}, 1.0f);
    const MeshId cloth = m.add(engine, "cloth", base, Motion::automatic);
    engine.update();
    // Step 1 raises it to deformable (its own tree, out of the static group); steps 2, 3, 4
    // refit and degrade.
    const Motion after[] = {Motion::deformable, Motion::deformable, Motion::deformable, Motion::exploding};
    for (int step = 1; step <= 4; ++step) {
        m.set_positions(engine, cloth, scrambled(base, rng));
        const FrameStats s = engine.update();
        EXPECT_EQ(engine.motion(cloth), after[step - 1]) << "step " << step;
        EXPECT_EQ(rebuild_reasons(s, cloth), Reasons{step == 1 ? "class changed" : "sah degraded"})
            << "step " << step;
    }
    // From then on rebuilt without a refit first; its world-space tree is kept across the
    // change of class, so an unchanged step costs nothing.
    EXPECT_EQ(engine.update().objects_rebuilt, 0u);
    for (int step = 6; step <= 7; ++step) {
        m.set_positions(engine, cloth, scrambled(base, rng));
        const FrameStats s = engine.update();
        EXPECT_EQ(rebuild_reasons(s, cloth), Reasons{"exploding"});
        EXPECT_EQ(s.objects_refitted, 0u);
        EXPECT_EQ(s.exploding_objects, 1u);
        EXPECT_EQ(engine.motion(cloth), Motion::exploding);
    }
}

TEST(ApiUpdate, MeshesAddedAndRemovedBetweenUpdates) {
    Engine engine;
    Mirror m;
    const MeshId left = m.add(engine, "left", sphere({-1.0f, 0.0f, 0.0f}, 0.5f), Motion::static_);
    const MeshId right = m.add(engine, "right", sphere({1.0f, 0.0f, 0.0f}, 0.5f), Motion::deformable);
    engine.update();
    engine.update();

    // Added after updates: built at the next one, the others untouched.
    const MeshId top = m.add(engine, "top", sphere({0.0f, 0.0f, 3.0f}, 0.5f), Motion::rigid);
    EXPECT_EQ(top.value, 2u);
    EXPECT_EQ(engine.mesh_count(), 3u);
    EXPECT_FALSE(down_at(engine, 0.0f, 0.0f).hit());  // not before the update
    FrameStats s = engine.update();
    EXPECT_EQ(rebuild_reasons(s, top), Reasons{"first build"});
    EXPECT_EQ(s.objects_rebuilt, 1u);
    EXPECT_EQ(s.objects_skipped, 2u);
    RayHit hit = down_at(engine, 0.0f, 0.0f);
    EXPECT_TRUE(hit.hit() && hit.mesh == top);
    const MeshId late_static = m.add(engine, "late", sphere({0.0f, 2.0f, 0.0f}, 0.4f), Motion::static_);
    s = engine.update();
    hit = down_at(engine, 0.0f, 2.0f);
    EXPECT_TRUE(hit.hit() && hit.mesh == late_static);
    EXPECT_TRUE(down_at(engine, -1.0f, 0.0f).mesh == left);

    // Removed: its rays miss it from the next update on; its id is never reused.
    for (const MeshId gone : {right, left, top}) {
        m.remove(engine, gone);
        engine.update();
        const Reference ref(m);
        std::mt19937 rng(gone.value);
        const std::vector<Ray> rays = incoherent_rays(rng, {0.0f, 0.5f, 1.0f}, 5.0f, 2.0f, 300);
        std::vector<RayHit> hits(rays.size());
        engine.intersect(rays, hits);
        for (const RayHit& h : hits) EXPECT_NE(h.mesh, gone);
        const std::vector<Verdict> verdicts = verdicts_for(*ref.tracer, rays);
        EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts, hits, "after remove").mismatches, 0u);
    }
    EXPECT_FALSE(down_at(engine, 0.0f, 0.0f).hit());
    EXPECT_FALSE(down_at(engine, -1.0f, 0.0f).hit());
    EXPECT_EQ(engine.mesh_count(), 1u);
    const MeshId again = m.add(engine, "again", sphere({1.0f, 0.0f, 0.0f}, 0.5f), Motion::automatic);
    EXPECT_EQ(again.value, 4u);
    engine.update();
    hit = down_at(engine, 1.0f, 0.0f);
    EXPECT_TRUE(hit.hit() && hit.mesh == again);

    // Every call with a removed id is refused, naming the id.
    const std::vector<float> positions = sphere({1.0f, 0.0f, 0.0f}, 0.5f).positions;
    const std::string id = "id " + std::to_string(right.value);
    expect_error([&] { engine.set_positions(right, positions); }, Error::Code::invalid_argument, {id, "removed"});
    expect_error([&] { engine.set_transform(right, {}); }, Error::Code::invalid_argument, {id, "removed"});
    expect_error([&] { engine.set_surface(right, {}); }, Error::Code::invalid_argument, {id, "removed"});
    expect_error([&] { engine.remove_mesh(right); }, Error::Code::invalid_argument, {id, "removed"});
    expect_error([&] { engine.motion(right); }, Error::Code::invalid_argument, {id, "removed"});
    expect_error([&] { engine.motion(MeshId{77}); }, Error::Code::invalid_argument, {"id 77"});
    expect_error([&] { engine.motion(MeshId{}); }, Error::Code::invalid_argument, {"no mesh"});
}

TEST(ApiUpdate, AnEmptyEngineUpdatesAndMissesEverything) {
    Engine engine;
    FrameStats s = engine.update();
    EXPECT_EQ(s.triangles, 0u);
    std::mt19937 rng(1);
    const std::vector<Ray> rays = incoherent_rays(rng, {0.0f, 0.0f, 0.0f}, 3.0f, 1.0f, 300);
    std::vector<RayHit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size(), 1);
    EXPECT_EQ(engine.intersect(rays, hits).hits, 0u);
    EXPECT_EQ(engine.occluded(rays, occluded).hits, 0u);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_FALSE(hits[i].hit());
        EXPECT_EQ(occluded[i], 0);
    }
    std::vector<float> rgb(8 * 6 * 3);
    engine.render(View{}, ImageView{8, 6, rgb});
    // Every mesh removed again: the same.
    Mirror m;
    const MeshId only = m.add(engine, "only", sphere({0.0f, 0.0f, 0.0f}, 1.0f), Motion::static_);
    engine.update();
    EXPECT_GT(engine.intersect(rays, hits).hits, 0u);
    m.remove(engine, only);
    s = engine.update();
    EXPECT_EQ(engine.intersect(rays, hits).hits, 0u);
    EXPECT_EQ(engine.mesh_count(), 0u);
}

}  // namespace
}  // namespace dynrt::api_test
