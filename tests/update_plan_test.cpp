// The update planner (dynrt/engine/update_plan.h) as an update matrix, in the spirit of
// Embree's verify update tests: which objects moved x their class x what their trees were x the
// policy, first without any tree (the plan alone), then carried out by SceneAccel on real
// trees, whose hits must equal those of trees built from scratch for the same frame.

#include "dynrt/engine/update_plan.h"

#include "update/scene_accel.h"

#include "dynrt/bvh/ray.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/scene/scene.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace dynrt {
namespace {

using anim::MotionClass;

constexpr std::array<MotionClass, 4> kClasses = {MotionClass::static_, MotionClass::rigid,
                                                 MotionClass::deformable, MotionClass::exploding};

std::string name(MotionClass c) { return anim::motion_class_name(c); }

ObjectState state(MotionClass c, bool changed) {
    ObjectState s;
    s.motion_class = c;
    s.changed = changed;
    return s;
}

/// The trees after a normal update of an object of class `c`: static objects have none of
/// their own, every other class has a built tree.
TreeHistory settled(MotionClass c) { return TreeHistory{true, c, c != MotionClass::static_}; }

constexpr StaticGroupHistory kGroupBuilt{true, true};

// ---- The plan alone -----------------------------------------------------------------------

TEST(UpdatePlan, FirstUpdateBuildsEveryTreeAndTheStaticGroup) {
    std::vector<ObjectState> now;
    for (MotionClass c : kClasses) now.push_back(state(c, true));
    const UpdatePlan plan = plan_update({}, StaticGroupHistory{}, now);
    EXPECT_TRUE(plan.rebuild_static_group);
    EXPECT_EQ(plan.static_group_reason, RebuildReason::first_build);
    ASSERT_EQ(plan.objects.size(), now.size());
    EXPECT_EQ(plan.objects[0].action, TreeAction::build_in_static_group);
    for (std::size_t i = 0; i < now.size(); ++i) {
        if (i > 0) {
            EXPECT_EQ(plan.objects[i].action, TreeAction::rebuild) << name(kClasses[i]);
        }
        EXPECT_EQ(plan.objects[i].reason, RebuildReason::first_build) << name(kClasses[i]);
        EXPECT_FALSE(plan.objects[i].joins_static_group);
        EXPECT_FALSE(plan.objects[i].leaves_static_group);
    }
}

TEST(UpdatePlan, ASceneWithoutStaticObjectsStillBuildsItsEmptyGroupOnce) {
    const std::vector<ObjectState> now = {state(MotionClass::rigid, true)};
    EXPECT_TRUE(plan_update({}, StaticGroupHistory{}, now).rebuild_static_group);
    const std::vector<TreeHistory> before = {settled(MotionClass::rigid)};
    EXPECT_FALSE(plan_update(before, kGroupBuilt, now).rebuild_static_group);
}

/// What a settled object of class `c` gets when it did or did not change this frame.
ObjectPlan expected_settled(MotionClass c, bool changed) {
    ObjectPlan p;
    if (!changed) return p;  // keep, whatever the class
    switch (c) {
        case MotionClass::static_: break;  // keep: a changed flag on a static object moves nothing
        case MotionClass::rigid: p.action = TreeAction::move_instance; break;
        case MotionClass::deformable: p.action = TreeAction::refit; break;
        case MotionClass::exploding:
            p.action = TreeAction::rebuild;
            p.reason = RebuildReason::exploding;
            break;
    }
    return p;
}

// Four objects, one per class, settled; every subset of them moved. Each object's action
// depends on its own class and whether it moved, never on the others, and the static group is
// kept (nobody joined or left it).
TEST(UpdatePlan, MovedSubsetsTimesClasses) {
    std::vector<TreeHistory> before;
    for (MotionClass c : kClasses) before.push_back(settled(c));
    for (unsigned moved = 0; moved < 16; ++moved) {
        std::vector<ObjectState> now;
        for (std::size_t i = 0; i < kClasses.size(); ++i) {
            now.push_back(state(kClasses[i], (moved >> i) & 1u));
        }
        const UpdatePlan plan = plan_update(before, kGroupBuilt, now);
        EXPECT_FALSE(plan.rebuild_static_group) << "moved mask " << moved;
        for (std::size_t i = 0; i < kClasses.size(); ++i) {
            const ObjectPlan want = expected_settled(kClasses[i], now[i].changed);
            EXPECT_EQ(plan.objects[i].action, want.action)
                << name(kClasses[i]) << ", moved mask " << moved << ": "
                << tree_action_name(plan.objects[i].action);
            if (want.action == TreeAction::rebuild) {
                EXPECT_EQ(plan.objects[i].reason, want.reason);
            }
        }
    }
}

// Every class change of a settled object, moved or not: when its tree's space changes (rigid
// trees are in object space, the others in world space) or it leaves the static group it is
// built afresh for "class changed"; deformable <-> exploding keep their tree; joining or
// leaving the group rebuilds the group, and its static members with it.
TEST(UpdatePlan, ClassChangesTimesMoved) {
    const auto world = [](MotionClass c) { return c != MotionClass::rigid; };
    for (MotionClass from : kClasses) {
        for (MotionClass to : kClasses) {
            if (from == to) continue;
            for (bool changed : {false, true}) {
                // The object, and a static bystander that is in the group throughout.
                const std::vector<TreeHistory> before = {settled(from), settled(MotionClass::static_)};
                const std::vector<ObjectState> now = {state(to, changed),
                                                      state(MotionClass::static_, false)};
                const UpdatePlan plan = plan_update(before, kGroupBuilt, now);
                const ObjectPlan& object = plan.objects[0];
                const std::string what = name(from) + " -> " + name(to) +
                                         (changed ? ", moved" : ", not moved");
                const bool joins = to == MotionClass::static_;
                const bool leaves = from == MotionClass::static_;
                EXPECT_EQ(object.joins_static_group, joins) << what;
                EXPECT_EQ(object.leaves_static_group, leaves) << what;
                EXPECT_EQ(plan.rebuild_static_group, joins || leaves) << what;
                if (joins || leaves) {
                    EXPECT_EQ(plan.static_group_reason, RebuildReason::static_group_changed);
                    EXPECT_EQ(plan.objects[1].action, TreeAction::build_in_static_group) << what;
                    EXPECT_EQ(plan.objects[1].reason, RebuildReason::static_group_changed);
                } else {
                    EXPECT_EQ(plan.objects[1].action, TreeAction::keep) << what;
                }
                if (joins) {
                    EXPECT_EQ(object.action, TreeAction::build_in_static_group) << what;
                } else if (leaves || world(from) != world(to)) {
                    EXPECT_EQ(object.action, TreeAction::rebuild) << what;
                    EXPECT_EQ(object.reason, RebuildReason::class_changed) << what;
                } else {
                    // deformable <-> exploding: the world-space tree is kept, and treated as
                    // the new class treats a settled tree.
                    const ObjectPlan want = expected_settled(to, changed);
                    EXPECT_EQ(object.action, want.action) << what;
                    if (want.action == TreeAction::rebuild) {
                        EXPECT_EQ(object.reason, want.reason);
                    }
                }
            }
        }
    }
}

// A tree that was lost (its triangles replaced: SceneAccel::invalidate) is rebuilt for
// "first build" whatever moved; a lost static group is rebuilt for "static group changed".
TEST(UpdatePlan, LostTreesAreRebuilt) {
    for (MotionClass c : kClasses) {
        if (c == MotionClass::static_) continue;
        for (bool changed : {false, true}) {
            const std::vector<TreeHistory> before = {TreeHistory{true, c, false}};
            const std::vector<ObjectState> now = {state(c, changed)};
            const UpdatePlan plan = plan_update(before, kGroupBuilt, now);
            EXPECT_EQ(plan.objects[0].action, TreeAction::rebuild) << name(c);
            EXPECT_EQ(plan.objects[0].reason, RebuildReason::first_build) << name(c);
        }
    }
    const std::vector<TreeHistory> before = {settled(MotionClass::static_)};
    const std::vector<ObjectState> now = {state(MotionClass::static_, false)};
    const UpdatePlan plan = plan_update(before, StaticGroupHistory{true, false}, now);
    EXPECT_TRUE(plan.rebuild_static_group);
    EXPECT_EQ(plan.static_group_reason, RebuildReason::static_group_changed);
    EXPECT_EQ(plan.objects[0].action, TreeAction::build_in_static_group);
}

// Objects added at the end of a scene are new to the planner: built, and a static newcomer
// joins (and so rebuilds) the static group; the settled objects before them keep their trees.
TEST(UpdatePlan, ObjectsAddedAtTheEnd) {
    for (MotionClass c : kClasses) {
        const std::vector<TreeHistory> before = {settled(MotionClass::deformable)};
        const std::vector<ObjectState> now = {state(MotionClass::deformable, false), state(c, true)};
        const UpdatePlan plan = plan_update(before, kGroupBuilt, now);
        EXPECT_EQ(plan.objects[0].action, TreeAction::keep) << name(c);
        EXPECT_EQ(plan.rebuild_static_group, c == MotionClass::static_) << name(c);
        EXPECT_EQ(plan.objects[1].action, c == MotionClass::static_ ? TreeAction::build_in_static_group
                                                                     : TreeAction::rebuild)
            << name(c);
    }
}

// The policy: a refit stands while its SAH cost is within (1 + threshold) of the last
// build's; a refit that could not keep the tree correct is always rebuilt.
TEST(UpdatePlan, JudgeRefitAgainstThePolicy) {
    bvh::RefitResult refit;
    refit.sah_cost = 13.0;  // 30% above the last build's 10
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<std::pair<double, bool>> thresholds = {
        {0.0, true}, {0.29, true}, {0.31, false}, {inf, false}};
    for (const auto& [threshold, rebuilds] : thresholds) {
        UpdatePolicy policy;
        policy.rebuild_threshold = threshold;
        const std::optional<RebuildReason> verdict = judge_refit(refit, 10.0, policy);
        EXPECT_EQ(verdict.has_value(), rebuilds) << "threshold " << threshold;
        if (verdict) {
            EXPECT_EQ(*verdict, RebuildReason::sah_degraded);
        }
    }
    UpdatePolicy never;
    never.rebuild_threshold = inf;
    refit.status = bvh::RefitStatus::skipped_triangle_has_area;
    EXPECT_EQ(judge_refit(refit, 10.0, never), RebuildReason::degenerate_gained_area);
}

TEST(UpdatePlan, AutomaticClassesOnlyRise) {
    for (MotionClass c : kClasses) {
        for (int t = 0; t < 2; ++t) {
            for (int p = 0; p < 2; ++p) {
                const MotionClass raised = raise_automatic_class(c, t, p);
                EXPECT_GE(raised, c);
                EXPECT_GE(raised, t ? MotionClass::rigid : MotionClass::static_);
                EXPECT_GE(raised, p ? MotionClass::deformable : MotionClass::static_);
                EXPECT_TRUE(t || p || raised == c);
            }
        }
    }
}

TEST(UpdatePlan, DegradingRefitsInARowMakeAnAutomaticMeshExploding) {
    int streak = 0;
    MotionClass c = MotionClass::deformable;
    for (int step = 1; step < kDegradedStepsToExploding; ++step) {
        c = class_after_update(c, true, true, streak);
        EXPECT_EQ(c, MotionClass::deformable) << "step " << step;
    }
    // An unmoved update neither extends nor breaks the streak; a good refit breaks it.
    EXPECT_EQ(class_after_update(c, false, false, streak), MotionClass::deformable);
    EXPECT_EQ(streak, kDegradedStepsToExploding - 1);
    EXPECT_EQ(class_after_update(c, true, false, streak), MotionClass::deformable);
    EXPECT_EQ(streak, 0);
    for (int step = 0; step < kDegradedStepsToExploding; ++step) {
        c = class_after_update(c, true, true, streak);
    }
    EXPECT_EQ(c, MotionClass::exploding);
    // Other classes are left alone.
    int other = 0;
    EXPECT_EQ(class_after_update(MotionClass::rigid, true, true, other), MotionClass::rigid);
    EXPECT_EQ(other, 0);
}

// ---- The plan carried out: SceneAccel on real trees ------------------------------------------

/// A grid of small quads (two triangles each) around `center`, `n` x `n`.
Mesh grid(glm::vec3 center, int n, float size) {
    Mesh mesh;
    for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) {
            mesh.positions.push_back(center + glm::vec3((float(x) / float(n) - 0.5f) * size,
                                                        (float(y) / float(n) - 0.5f) * size, 0.0f));
        }
    }
    const auto at = [n](int x, int y) { return unsigned(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            mesh.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            mesh.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
        }
    }
    return mesh;
}

/// `mesh` with three vertices of its own per triangle, in order (a soup, which SceneAccel
/// reads in place rather than through a copy).
Mesh soup_of(const Mesh& mesh) {
    Mesh soup;
    for (const glm::uvec3& t : mesh.triangles) {
        const unsigned v = unsigned(soup.positions.size());
        for (const unsigned corner : {t.x, t.y, t.z}) soup.positions.push_back(mesh.positions[corner]);
        soup.triangles.push_back({v, v + 1, v + 2});
    }
    return soup;
}

/// Four objects side by side, one per class in kClasses' order, each with a frame-dependent
/// pose: a rigid one slides, a deformable one ripples, an exploding one scatters its triangles.
/// Grids with shared vertices, or the same as soups.
struct MatrixWorld final : FixedPositions {
    Scene scene;
    std::vector<std::vector<glm::vec3>> posed;  ///< per object, world positions this frame
    std::vector<glm::dmat4> transforms;

    explicit MatrixWorld(bool soups = false) {
        for (std::size_t i = 0; i < kClasses.size(); ++i) {
            Object object;
            object.name = name(kClasses[i]);
            object.mesh = grid(glm::vec3(2.5f * float(i), 0.0f, 0.0f), 6, 2.0f);
            if (soups) object.mesh = soup_of(object.mesh);
            scene.objects.push_back(object);
        }
        scene.materials.push_back(Material{});
        posed.resize(kClasses.size());
        transforms.assign(kClasses.size(), glm::dmat4(1.0));
        for (std::size_t i = 0; i < kClasses.size(); ++i) posed[i] = scene.objects[i].mesh.positions;
    }

    /// Poses object i at `step` (a step of 0 is the rest pose).
    void pose(std::size_t i, int step) {
        const std::vector<glm::vec3>& rest = scene.objects[i].mesh.positions;
        switch (kClasses[i]) {
            case MotionClass::static_: break;
            case MotionClass::rigid:
                transforms[i] = glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.1 * step, 0.0));
                break;
            case MotionClass::deformable:
                for (std::size_t v = 0; v < rest.size(); ++v) {
                    posed[i][v] = rest[v] + glm::vec3(0.0f, 0.0f, 0.2f * std::sin(float(step) + rest[v].x * 3.0f));
                }
                break;
            case MotionClass::exploding: {
                // Each triangle's vertices pushed along a pseudo-random direction per vertex.
                std::mt19937 rng{unsigned(step)};
                std::uniform_real_distribution<float> d(-0.3f, 0.3f);
                for (std::size_t v = 0; v < rest.size(); ++v) {
                    posed[i][v] = rest[v] + float(step) * glm::vec3(d(rng), d(rng), d(rng));
                }
                break;
            }
        }
    }

    std::vector<ObjectState> states(unsigned moved) const {
        std::vector<ObjectState> s;
        for (std::size_t i = 0; i < kClasses.size(); ++i) {
            ObjectState o = state(kClasses[i], (moved >> i) & 1u);
            o.transform = transforms[i];
            if (kClasses[i] == MotionClass::deformable || kClasses[i] == MotionClass::exploding) {
                o.world_positions = posed[i];
            }
            s.push_back(o);
        }
        return s;
    }

    std::span<const glm::vec3> object_space(std::size_t object) const override {
        return scene.objects[object].mesh.positions;
    }
    std::span<const glm::vec3> world(std::size_t object, std::vector<glm::vec3>&) const override {
        return scene.objects[object].mesh.positions;
    }
};

/// Closest hits of a fan of rays from above through both accelerations: equal object,
/// triangle and distance, ray by ray.
void expect_same_hits(const SceneAccel& updated, const SceneAccel& fresh, const std::string& what) {
    int hits = 0;
    for (int k = 0; k < 400; ++k) {
        bvh::Ray ray;
        ray.org = glm::vec3(-1.2f + 0.026f * float(k), 0.3f * std::sin(float(k)), 5.0f);
        ray.dir = glm::vec3(0.0f, 0.0f, -1.0f);
        bvh::InstanceHit a = bvh::intersect_closest(updated.top_level(), ray);
        bvh::InstanceHit b = bvh::intersect_closest(fresh.top_level(), ray);
        updated.resolve(a);
        fresh.resolve(b);
        ASSERT_EQ(a.hit.is_hit(), b.hit.is_hit()) << what << ", ray " << k;
        if (!a.hit.is_hit()) continue;
        ++hits;
        ASSERT_EQ(a.object, b.object) << what << ", ray " << k;
        ASSERT_EQ(a.hit.prim, b.hit.prim) << what << ", ray " << k;
        ASSERT_EQ(a.hit.t, b.hit.t) << what << ", ray " << k;
    }
    EXPECT_GT(hits, 100) << what;  // the fan does cross the objects
}

// Every subset of the four objects moved, step after step: SceneAccel's work is what the plan
// says (moved objects refitted or rebuilt, the others skipped), and its trees hit exactly what
// trees built from scratch for the same frame hit.
TEST(UpdatePlan, SceneAccelCarriesOutThePlanOverMovedSubsets) {
    for (const bool soups : {false, true}) {
        SCOPED_TRACE(soups ? "soups (read in place)" : "shared vertices (read through a copy)");
        MatrixWorld world(soups);
        UpdatePolicy policy;
        policy.method = UpdateMethod::threshold;
        policy.rebuild_threshold = std::numeric_limits<double>::infinity();  // refits stand
        SceneAccel accel;
        FrameStats first;
        accel.update(world.scene, world.states(0xF), world, policy, first, first);
        EXPECT_EQ(first.objects_rebuilt, kClasses.size());
        for (const TreeRebuild& r : first.rebuilds) EXPECT_EQ(r.reason, RebuildReason::first_build);
        int step = 0;
        for (unsigned moved = 0; moved < 16; ++moved) {
            ++step;
            for (std::size_t i = 0; i < kClasses.size(); ++i) {
                if ((moved >> i) & 1u) world.pose(i, step);
            }
            const std::vector<ObjectState> states = world.states(moved);
            FrameStats stats;
            accel.update(world.scene, states, world, policy, stats, stats);
            const std::string what = "moved mask " + std::to_string(moved);
            const bool deformable_moved = (moved >> 2) & 1u;
            const bool exploding_moved = (moved >> 3) & 1u;
            EXPECT_EQ(stats.objects_refitted, deformable_moved ? 1u : 0u) << what;
            EXPECT_EQ(stats.objects_rebuilt, exploding_moved ? 1u : 0u) << what;
            EXPECT_EQ(stats.objects_skipped, kClasses.size() - deformable_moved - exploding_moved)
                << what;
            if (exploding_moved) {
                ASSERT_EQ(stats.rebuilds.size(), 1u);
                EXPECT_EQ(stats.rebuilds[0].reason, RebuildReason::exploding);
            }
            SceneAccel fresh;
            FrameStats fresh_stats;
            fresh.update(world.scene, states, world, policy, fresh_stats, fresh_stats);
            expect_same_hits(accel, fresh, what);
        }
    }
}

// An object's parts (the boxes exact pixel reuse tests rays against) hold each of its
// triangles whole, in world space, whatever its class, and are tighter than its one box.
TEST(UpdatePlan, ObjectPartsHoldEveryTriangle) {
    MatrixWorld world;
    UpdatePolicy policy;
    SceneAccel accel;
    FrameStats stats;
    accel.update(world.scene, world.states(0xF), world, policy, stats, stats);
    for (std::size_t i = 0; i < kClasses.size(); ++i) world.pose(i, 3);
    // A rigid object's parts are its tree's boxes carried to world space: turn it too.
    world.transforms[1] = glm::rotate(world.transforms[1], 0.7, glm::dvec3(0.3, 1.0, 0.2));
    accel.update(world.scene, world.states(0xF), world, policy, stats, stats);
    for (std::size_t i = 0; i < kClasses.size(); ++i) {
        SCOPED_TRACE(name(kClasses[i]));
        std::vector<bvh::Aabb> one, parts;
        accel.object_world_parts(i, 1, one);
        ASSERT_EQ(one.size(), 1u);
        EXPECT_EQ(one[0].lo, accel.object_world_boxes()[i].lo);
        // As many parts as exact reuse asks for (ObjectVersions::kPartsPerObject).
        accel.object_world_parts(i, 16, parts);
        ASSERT_LE(parts.size(), 16u);
        // Static objects share the static group's tree: their box is all there is.
        if (kClasses[i] == MotionClass::static_) {
            ASSERT_EQ(parts.size(), 1u);
        } else {
            ASSERT_GT(parts.size(), 8u);
        }
        const auto in_box = [](const glm::vec3& v, const bvh::Aabb& p, float pad) {
            return glm::all(glm::greaterThanEqual(v, p.lo - pad)) && glm::all(glm::lessThanEqual(v, p.hi + pad));
        };
        if (kClasses[i] == MotionClass::rigid || kClasses[i] == MotionClass::deformable) {
            // The sheets' parts leave most of their box out: points of the box, at random.
            std::mt19937 rng(5);
            std::uniform_real_distribution<float> u(0.0f, 1.0f);
            int covered = 0;
            for (int k = 0; k < 2000; ++k) {
                const glm::vec3 q = one[0].lo + glm::vec3(u(rng), u(rng), u(rng)) * (one[0].hi - one[0].lo);
                covered += std::any_of(parts.begin(), parts.end(),
                                       [&](const bvh::Aabb& p) { return in_box(q, p, 0.0f); });
            }
            EXPECT_LT(covered, 1400) << parts.size() << " parts";
        }
        const std::size_t triangles = world.scene.objects[i].mesh.triangles.size();
        for (std::uint32_t prim = 0; prim < triangles; ++prim) {
            const bvh::Triangle t = accel.world_triangle(i, prim);
            // Rounding of the corner transform is what the changed space pads for.
            const float pad = 1e-5f;
            const bool held = std::any_of(parts.begin(), parts.end(), [&](const bvh::Aabb& p) {
                return in_box(t.v0, p, pad) && in_box(t.v1, p, pad) && in_box(t.v2, p, pad);
            });
            EXPECT_TRUE(held) << "triangle " << prim;
        }
    }
}

// A soup is found once per index array, not every frame: triples edited so that they are no
// longer a soup's (the scene's array copied on the edit, as the tree holds the old one) are
// read through from the next update on, and the tree holds the edited triangles.
TEST(UpdatePlan, ASoupWhoseTriplesAreEditedIsReadThroughThemAfterwards) {
    MatrixWorld world(/*soups=*/true);
    UpdatePolicy policy;
    SceneAccel accel;
    FrameStats stats;
    accel.update(world.scene, world.states(0xF), world, policy, stats, stats);
    const std::size_t exploding = 3;
    ASSERT_EQ(kClasses[exploding], MotionClass::exploding);
    Mesh& mesh = world.scene.objects[exploding].mesh;
    mesh.triangles.edit()[0] = glm::uvec3(3, 4, 5);  // triangle 1's corners: no longer a soup
    world.pose(exploding, 1);
    FrameStats edited;
    accel.update(world.scene, world.states(1u << exploding), world, policy, edited, edited);
    EXPECT_EQ(edited.objects_rebuilt, 1u);
    for (std::uint32_t t = 0; t < 3; ++t) {
        const glm::uvec3 corners = mesh.triangles[t];
        const bvh::Triangle tri = accel.world_triangle(exploding, t);
        EXPECT_EQ(tri.v0, world.posed[exploding][corners.x]) << "triangle " << t;
        EXPECT_EQ(tri.v1, world.posed[exploding][corners.y]) << "triangle " << t;
        EXPECT_EQ(tri.v2, world.posed[exploding][corners.z]) << "triangle " << t;
    }
}

// The plan says refit, the vertices say nothing moved: skipped, the tree untouched. And a
// refit past the threshold is rebuilt for "sah degraded" with both costs in the report.
TEST(UpdatePlan, SceneAccelChecksThePlanAgainstTheVertices) {
    for (const bool soups : {false, true}) {
        SCOPED_TRACE(soups ? "soups (read in place)" : "shared vertices (read through a copy)");
        MatrixWorld world(soups);
        UpdatePolicy policy;
        SceneAccel accel;
        FrameStats stats;
        accel.update(world.scene, world.states(0xF), world, policy, stats, stats);
        FrameStats same;
        accel.update(world.scene, world.states(0xF), world, policy, same, same);  // "moved", same vertices
        EXPECT_EQ(same.objects_refitted, 0u);
        EXPECT_EQ(same.objects_rebuilt, 0u);
        EXPECT_EQ(same.objects_skipped, kClasses.size());

        policy.method = UpdateMethod::threshold;
        policy.rebuild_threshold = 0.0;
        // Scatter the deformable object's vertices: its refitted tree degrades.
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> d(-1.0f, 1.0f);
        for (glm::vec3& p : world.posed[2]) p += glm::vec3(d(rng), d(rng), d(rng));
        FrameStats degraded;
        accel.update(world.scene, world.states(1u << 2), world, policy, degraded, degraded);
        ASSERT_EQ(degraded.rebuilds.size(), 1u);
        EXPECT_EQ(degraded.rebuilds[0].reason, RebuildReason::sah_degraded);
        EXPECT_GT(degraded.rebuilds[0].sah_refitted, degraded.rebuilds[0].sah_at_last_build);
        EXPECT_EQ(degraded.objects_refitted, 1u);
    }
}

}  // namespace
}  // namespace dynrt
