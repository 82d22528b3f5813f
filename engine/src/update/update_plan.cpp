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

UpdatePlan plan_update(std::span<const TreeHistory> previous, const StaticGroupHistory& group,
                       std::span<const ObjectState> now) {
    UpdatePlan plan;
    plan.objects.resize(now.size());
    plan.rebuild_static_group = !group.built;

    // ---- Class changes: which trees are lost, and whether the static group changes ----
    // `built[i]`: object i still has a tree it may keep, refit or move.
    std::vector<bool> built(now.size(), false);
    std::vector<bool> class_changed(now.size(), false);
    for (std::size_t i = 0; i < now.size(); ++i) {
        const TreeHistory before = i < previous.size() ? previous[i] : TreeHistory{};
        const MotionClass c = now[i].motion_class;
        ObjectPlan& object = plan.objects[i];
        built[i] = before.built;
        if (!before.known) {
            // A new object: a static one joins the group, any other is built below.
            if (c == MotionClass::static_) plan.rebuild_static_group = true;
            continue;
        }
        if (before.motion_class == c) continue;
        object.leaves_static_group = before.motion_class == MotionClass::static_;
        object.joins_static_group = c == MotionClass::static_;
        if (object.leaves_static_group || world_space(before.motion_class) != world_space(c)) {
            built[i] = false;
            class_changed[i] = true;
        }
        if (object.leaves_static_group || object.joins_static_group) plan.rebuild_static_group = true;
    }
    if (plan.rebuild_static_group) {
        plan.static_group_reason =
            group.known ? RebuildReason::static_group_changed : RebuildReason::first_build;
    }

    // ---- One action per object ----
    for (std::size_t i = 0; i < now.size(); ++i) {
        ObjectPlan& object = plan.objects[i];
        const ObjectState& state = now[i];
        const RebuildReason first = class_changed[i] ? RebuildReason::class_changed
                                                     : RebuildReason::first_build;
        switch (state.motion_class) {
            case MotionClass::static_:
                if (plan.rebuild_static_group) {
                    object.action = TreeAction::build_in_static_group;
                    object.reason = plan.static_group_reason;
                }
                break;
            case MotionClass::rigid:
                if (!built[i]) {
                    object.action = TreeAction::rebuild;
                    object.reason = first;
                } else if (state.changed) {
                    object.action = TreeAction::move_instance;
                }
                break;
            case MotionClass::deformable:
            case MotionClass::exploding:
                if (!built[i]) {
                    object.action = TreeAction::rebuild;
                    object.reason = first;
                } else if (!state.changed) {
                    object.action = TreeAction::keep;
                } else if (state.motion_class == MotionClass::exploding) {
                    object.action = TreeAction::rebuild;
                    object.reason = RebuildReason::exploding;
                } else {
                    object.action = TreeAction::refit;
                }
                break;
        }
    }
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
