// The automatic update method's cost model (engine/update_cost.h) and the planner under each
// update method (engine/update_plan.h): pure functions, checked on hand-made figures.

#include "dynrt/engine/update_cost.h"
#include "dynrt/engine/update_plan.h"

#include <gtest/gtest.h>

#include <vector>

namespace dynrt {
namespace {

TEST(UpdateCost, MethodNamesRoundTrip) {
    for (UpdateMethod m : {UpdateMethod::automatic, UpdateMethod::threshold, UpdateMethod::refit,
                           UpdateMethod::fast, UpdateMethod::sah}) {
        EXPECT_EQ(parse_update_method(update_method_name(m)), m);
    }
    EXPECT_FALSE(parse_update_method("automatic").has_value());
    EXPECT_FALSE(parse_update_method("").has_value());
}

TEST(UpdateCost, FastRebuildWhenItsBuildAndPoorerTreeCostLess) {
    ObjectCosts costs;
    costs.fast_ms = 30.0;
    costs.sah_ms = 200.0;
    costs.fast_quality = 1.2;
    // Trace 100 ms, all of it in this object: the Morton tree costs 20 ms more to trace.
    RebuildChoice c = choose_rebuild(costs, 1000000, BuildRates{}, TraceCost{100.0, 1.0});
    EXPECT_EQ(c.method, bvh::BuildMethod::morton);
    EXPECT_DOUBLE_EQ(c.fast_trace_extra_ms, 20.0);
    EXPECT_DOUBLE_EQ(c.cost(), 50.0);
    // A trace so long that the poorer tree's 20% outweighs the faster build.
    c = choose_rebuild(costs, 1000000, BuildRates{}, TraceCost{1000.0, 1.0});
    EXPECT_EQ(c.method, bvh::BuildMethod::binned_sah);
    EXPECT_DOUBLE_EQ(c.cost(), 200.0);
    // The object's share scales the trace effect.
    c = choose_rebuild(costs, 1000000, BuildRates{}, TraceCost{1000.0, 0.1});
    EXPECT_EQ(c.method, bvh::BuildMethod::morton);
    // Unmeasured builds are estimated from the rates.
    c = choose_rebuild(ObjectCosts{}, 2000000, BuildRates{300.0, 50.0, 10.0}, TraceCost{});
    EXPECT_DOUBLE_EQ(c.sah_build_ms, 600.0);
    EXPECT_DOUBLE_EQ(c.fast_build_ms, 100.0);
    EXPECT_EQ(c.method, bvh::BuildMethod::morton);
}

TEST(UpdateCost, RefitsAreKeptUntilTheirExtraTraceAddsUpToARebuild) {
    ObjectCosts costs;
    costs.fast_ms = 30.0;
    costs.sah_ms = 200.0;
    costs.fast_quality = 1.2;
    const TraceCost trace{100.0, 0.5};
    // SAH 10% over the fresh tree's: 100 * 0.5 * 0.1 = 5 ms extra per frame; the cheaper
    // rebuild costs 30 + 100 * 0.5 * 0.2 = 40 ms, so the 8th such frame rebuilds.
    int frames = 0;
    RefitJudgement j;
    do {
        j = judge_refit_cost(110.0, 100.0, costs, 1000000, BuildRates{}, trace);
        EXPECT_NEAR(j.extra_ms, 5.0, 1e-9);
        costs.penalty_ms = j.penalty_ms;
        ++frames;
    } while (!j.rebuild && frames < 100);
    EXPECT_EQ(frames, 8);
    EXPECT_EQ(j.choice.method, bvh::BuildMethod::morton);
    EXPECT_NE(explain_refit(j).find(">= rebuild (fast)"), std::string::npos) << explain_refit(j);
    // A refit that improved the tree, or one without any trace time known, adds nothing.
    EXPECT_DOUBLE_EQ(judge_refit_cost(90.0, 100.0, ObjectCosts{}, 10, {}, trace).extra_ms, 0.0);
    costs.penalty_ms = 0.0;
    EXPECT_FALSE(judge_refit_cost(500.0, 100.0, costs, 10, {}, TraceCost{}).rebuild);
    EXPECT_FALSE(judge_refit_cost(500.0, 0.0, ObjectCosts{}, 10, {}, trace).rebuild);
}

TEST(UpdateCost, ARefitIsSkippedWhenTheLastOneAloneCostMoreThanARebuild) {
    ObjectCosts costs;
    costs.fast_ms = 30.0;
    costs.sah_ms = 200.0;
    costs.fast_quality = 1.0;
    const TraceCost trace{100.0, 1.0};
    // Nothing known of a refit since the build: refit.
    EXPECT_FALSE(rebuild_instead_of_refit(costs, 1000, {}, trace).has_value());
    costs.refit_ms = 5.0;
    costs.last_extra_ms = 24.0;  // < 30 - 5
    EXPECT_FALSE(rebuild_instead_of_refit(costs, 1000, {}, trace).has_value());
    costs.last_extra_ms = 25.0;  // >= 30 - 5
    const std::optional<RebuildChoice> skip = rebuild_instead_of_refit(costs, 1000, {}, trace);
    ASSERT_TRUE(skip.has_value());
    EXPECT_EQ(skip->method, bvh::BuildMethod::morton);
    EXPECT_NE(explain_skipped_refit(costs, *skip).find("last refit's extra trace 25.0 ms"),
              std::string::npos);
}

TEST(UpdateCost, APoorerFastTreeIsJudgedAgainstAFreshTreesTrace) {
    // The last frame traced a tree degraded to twice its fresh SAH cost: a fresh tree would
    // have taken half of this object's share, and the fast tree's 30% more is of that half.
    ObjectCosts costs;
    costs.fast_ms = 10.0;
    costs.sah_ms = 100.0;
    costs.fast_quality = 1.3;
    const RebuildChoice c = choose_rebuild(costs, 1000, {}, TraceCost{400.0, 1.0, 2.0});
    EXPECT_NEAR(c.fast_trace_extra_ms, 60.0, 1e-9);
}

TEST(UpdateCost, PlannerFollowsTheUpdateMethod) {
    using anim::MotionClass;
    const std::vector<TreeHistory> before(4, TreeHistory{true, MotionClass::deformable, true});
    std::vector<ObjectState> now(4);
    now[0].motion_class = MotionClass::deformable;
    now[1].motion_class = MotionClass::exploding;
    now[2].motion_class = MotionClass::deformable;
    now[2].changed = false;
    now[3].motion_class = MotionClass::rigid;
    std::vector<TreeHistory> history = before;
    history[1].motion_class = MotionClass::exploding;
    history[3].motion_class = MotionClass::rigid;
    const StaticGroupHistory group{true, true};
    UpdatePlan plan;
    for (UpdateMethod m : {UpdateMethod::automatic, UpdateMethod::threshold}) {
        plan_update(history, group, now, m, plan);
        EXPECT_EQ(plan.objects[0].action, TreeAction::refit);
        EXPECT_EQ(plan.objects[1].action, TreeAction::rebuild);
        EXPECT_EQ(plan.objects[1].reason, RebuildReason::exploding);
    }
    plan_update(history, group, now, UpdateMethod::refit, plan);
    EXPECT_EQ(plan.objects[0].action, TreeAction::refit);
    EXPECT_EQ(plan.objects[1].action, TreeAction::refit);
    for (UpdateMethod m : {UpdateMethod::fast, UpdateMethod::sah}) {
        plan_update(history, group, now, m, plan);
        for (int i : {0, 1}) {
            EXPECT_EQ(plan.objects[i].action, TreeAction::rebuild);
            EXPECT_EQ(plan.objects[i].reason, RebuildReason::update_method);
        }
    }
    // Under every method an unchanged object is kept and a rigid one only moves.
    for (UpdateMethod m : {UpdateMethod::automatic, UpdateMethod::threshold, UpdateMethod::refit,
                           UpdateMethod::fast, UpdateMethod::sah}) {
        plan_update(history, group, now, m, plan);
        EXPECT_EQ(plan.objects[2].action, TreeAction::keep);
        EXPECT_EQ(plan.objects[3].action, TreeAction::move_instance);
    }
}

}  // namespace
}  // namespace dynrt
