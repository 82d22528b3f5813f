// The update planner (update_plan.h): per object, the cheapest action that keeps its tree
// correct, from its class, whether it changed and what its tree was after the last update.
// Refit versus rebuild for deformable objects follows Wald, Boulos and Shirley 2007 ("Ray
// Tracing Deformable Scenes Using Dynamic Bounding Volume Hierarchies"): refit while the SAH
// cost stays within a threshold of the last build's, rebuild when it has degraded past it.

#include "dynrt/engine/update_plan.h"

#include <algorithm>

namespace dynrt {

namespace {

using anim::MotionClass;

/// Rigid trees are in object space, every other tree (the static group's included) in world
/// space: a class change across that line needs a new tree.
bool world_space(MotionClass c) { return c != MotionClass::rigid; }

}  // namespace

const char* tree_action_name(TreeAction action) {
    switch (action) {
        case TreeAction::keep: return "keep";
        case TreeAction::move_instance: return "move instance";
        case TreeAction::refit: return "refit";
        case TreeAction::rebuild: return "rebuild";
        case TreeAction::build_in_static_group: return "build in static group";
    }
    return "unknown";
}

void plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                 std::span<const ObjectState> now, UpdatePlan& plan) {
    plan_update(previous, group, now, UpdateMethod::threshold, plan);
}

void plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                 std::span<const ObjectState> now, UpdateMethod method, UpdatePlan& plan) {
    const bool rebuild_every_frame = method == UpdateMethod::fast || method == UpdateMethod::sah;
    plan.objects.assign(now.size(), ObjectPlan{});
    plan.rebuild_static_group = !group.built;

    // ---- Every object but the static ones: their actions depend on themselves alone ----
    for (std::size_t i = 0; i < now.size(); ++i) {
        const TreeHistory before = i < previous.size() ? previous[i] : TreeHistory{};
        const ObjectState& state = now[i];
        const MotionClass c = state.motion_class;
        ObjectPlan& object = plan.objects[i];
        // A class change loses the tree when it leaves the static group (static objects have
        // no tree of their own) or moves it between object and world space.
        const bool class_changed = before.known && before.motion_class != c;
        object.leaves_static_group = class_changed && before.motion_class == MotionClass::static_;
        object.joins_static_group = class_changed && c == MotionClass::static_;
        const bool tree_lost = object.leaves_static_group ||
                               (class_changed && world_space(before.motion_class) != world_space(c));
        // A new static object joins the group as well.
        if (object.leaves_static_group || object.joins_static_group ||
            (!before.known && c == MotionClass::static_)) {
            plan.rebuild_static_group = true;
        }
        if (c == MotionClass::static_) continue;  // decided below, with the group
        if (!before.built || tree_lost) {
            object.action = TreeAction::rebuild;
            object.reason = tree_lost ? RebuildReason::class_changed : RebuildReason::first_build;
        } else if (!state.changed) {
            object.action = TreeAction::keep;
        } else if (c == MotionClass::rigid) {
            object.action = TreeAction::move_instance;
        } else if (rebuild_every_frame) {
            object.action = TreeAction::rebuild;
            object.reason = RebuildReason::update_method;
        } else if (c == MotionClass::exploding && method != UpdateMethod::refit) {
            object.action = TreeAction::rebuild;
            object.reason = RebuildReason::exploding;
        } else {
            object.action = TreeAction::refit;
        }
    }

    // ---- The static group: rebuilt with all its members, or kept with them ----
    if (!plan.rebuild_static_group) return;
    plan.static_group_reason =
        group.known ? RebuildReason::static_group_changed : RebuildReason::first_build;
    for (std::size_t i = 0; i < now.size(); ++i) {
        if (now[i].motion_class != MotionClass::static_) continue;
        plan.objects[i].action = TreeAction::build_in_static_group;
        plan.objects[i].reason = plan.static_group_reason;
    }
}

UpdatePlan plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                       std::span<const ObjectState> now) {
    UpdatePlan plan;
    plan_update(previous, group, now, plan);
    return plan;
}

std::optional<RebuildReason> judge_refit(const bvh::RefitResult& refit, double sah_at_last_build,
                                         const UpdatePolicy& policy) {
    if (refit.needs_rebuild()) return RebuildReason::degenerate_gained_area;
    if (refit.sah_cost > (1.0 + policy.rebuild_threshold) * sah_at_last_build) {
        return RebuildReason::sah_degraded;
    }
    return std::nullopt;
}

MotionClass raise_automatic_class(MotionClass current, bool transform_changed,
                                  bool positions_changed) {
    MotionClass raised = current;
    if (transform_changed) raised = std::max(raised, MotionClass::rigid);
    if (positions_changed) raised = std::max(raised, MotionClass::deformable);
    return raised;
}

MotionClass class_after_update(MotionClass motion_class, bool changed, bool refit_degraded,
                               int& degraded_steps) {
    if (motion_class != MotionClass::deformable || !changed) return motion_class;
    degraded_steps = refit_degraded ? degraded_steps + 1 : 0;
    return degraded_steps >= kDegradedStepsToExploding ? MotionClass::exploding : motion_class;
}

}  // namespace dynrt
