#pragma once
// The choice between refitting an object's tree, rebuilding it fast (the Morton builder) and
// rebuilding it well (binned SAH), from what the last frames measured: the builds' and refits'
// times, the frame's trace time and the trees' SAH costs.
//
// The trace time a tree costs is predicted from its SAH cost (MacDonald and Booth 1990, "Heuristics
// for ray tracing using space subdivision"): the object's share of the frame's trace time is
// its share of the scene's SAH cost (its SAH weighted by the chance of reaching its world box),
// and that share scales with its own SAH cost. So a refitted tree whose SAH rose by 20% is
// predicted to cost share * trace_ms * 0.2 more than a fresh one, every frame it is kept.
//
// A refit is kept until the extra trace time the refits have cost since the last build adds up
// to the price of a rebuild (the ski-rental rule: it never pays more than twice the best
// schedule in hindsight; Karlin, Manasse, Rudolph and Sleator 1988). The rebuild is the fast one
// when its build time plus the extra trace time of its poorer tree (its measured SAH over the
// SAH tree's) is below the SAH build's time.

#include "dynrt/bvh/binned_sah_builder.h"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace dynrt {

/// How deformable and exploding objects' trees are brought up to date (UpdatePolicy::method,
/// `--update`). The fixed ones exist so a benchmark can sweep them.
enum class UpdateMethod : std::uint8_t {
    /// From measurements, per object and frame (this header's model).
    automatic,
    /// Refit deformable objects, rebuilding (binned SAH) when the SAH cost degraded past
    /// UpdatePolicy::rebuild_threshold; rebuild exploding ones every frame (binned SAH).
    threshold,
    /// Always refit (a rebuild only where a refit cannot keep the tree correct).
    refit,
    /// Rebuild every frame with the Morton builder.
    fast,
    /// Rebuild every frame with the binned SAH builder.
    sah,
};

/// "auto", "threshold", "refit", "fast", "sah".
const char* update_method_name(UpdateMethod method);
/// The inverse of update_method_name; nullopt for anything else.
std::optional<UpdateMethod> parse_update_method(std::string_view name);

/// The SAH cost of a Morton tree over the binned-SAH tree's of the same triangles, before one
/// was measured for an object (sphere:1000000, leaves of up to 8: 61.0 against 47.5).
inline constexpr double kDefaultFastQuality = 1.3;

/// Build and refit throughput before any was measured, in ns per triangle on the 2-core
/// development machine (bm_build, bm_refit); replaced by measurements as they come.
struct BuildRates {
    double sah_ns = 250.0;
    double fast_ns = 100.0;
    double refit_ns = 15.0;
};

/// What the last frames measured of one object's tree (kept by SceneAccel).
struct ObjectCosts {
    /// The last measured times, or negative when not yet measured.
    double fast_ms = -1.0;
    double sah_ms = -1.0;
    /// SAH cost of its Morton tree over that of its binned-SAH tree, when both were measured.
    double fast_quality = kDefaultFastQuality;
    /// SAH cost of its last binned-SAH tree (0: none yet), for fast_quality.
    double sah_tree_sah = 0.0;
    /// Predicted extra trace time the refits have cost since the last build.
    double penalty_ms = 0.0;
    /// The last refit's time and its predicted extra trace time (negative: none since the
    /// last build).
    double refit_ms = -1.0;
    double last_extra_ms = -1.0;
};

/// The frame-wide inputs of a choice.
struct TraceCost {
    /// The previous frame's trace time (primary + shadow rays), 0 before the first.
    double trace_ms = 0.0;
    /// The object's share of it: its SAH cost weighted by the chance of reaching its world
    /// box, over the scene's SAH cost (1 for a scene of one object; 0 when unknown).
    double share = 0.0;
    /// How much the object's tree had degraded in that frame: its SAH cost over its cost
    /// right after its build (>= 1). A rebuilt tree's trace time is predicted from the
    /// object's share of the trace divided by this, the share a fresh tree would have had.
    double degradation = 1.0;
};

/// The two rebuilds' predicted costs for one object, and the cheaper.
struct RebuildChoice {
    bvh::BuildMethod method = bvh::BuildMethod::binned_sah;
    double fast_build_ms = 0.0;
    double fast_trace_extra_ms = 0.0;  ///< of its poorer tree, this frame
    double sah_build_ms = 0.0;
    double fast_total() const { return fast_build_ms + fast_trace_extra_ms; }
    double cost() const {
        return method == bvh::BuildMethod::morton ? fast_total() : sah_build_ms;
    }
};

/// The rebuild to make of an object of `triangles` triangles: fast when its build plus its
/// poorer tree's extra trace time is below the SAH build's time. Build times are the object's
/// last measured, else estimated from `rates`.
RebuildChoice choose_rebuild(const ObjectCosts& costs, std::size_t triangles,
                             const BuildRates& rates, const TraceCost& trace);

/// After a refit: keep it or rebuild.
struct RefitJudgement {
    bool rebuild = false;
    /// Predicted extra trace time of the refitted tree this frame, over a fresh one.
    double extra_ms = 0.0;
    /// The penalty so far, this frame's included (reset by the caller after a rebuild).
    double penalty_ms = 0.0;
    RebuildChoice choice;
};

/// Before a refit: whether to skip it and rebuild at once. Trees degrade further with every
/// refit, so when the last refit's extra trace time alone reached the cheaper rebuild's cost
/// less a refit's, the next refit is predicted to cost more than rebuilding (geometry that
/// scrambles quickly, as explode does, is then rebuilt every frame instead of every other).
std::optional<RebuildChoice> rebuild_instead_of_refit(const ObjectCosts& costs,
                                                      std::size_t triangles,
                                                      const BuildRates& rates,
                                                      const TraceCost& trace);

/// Judges a refit whose tree now has SAH cost `refit_sah` against `fresh_sah`, its cost right
/// after its last build: rebuild once the accumulated extra trace time reaches the cheaper
/// rebuild's cost.
RefitJudgement judge_refit_cost(double refit_sah, double fresh_sah, const ObjectCosts& costs,
                                std::size_t triangles, const BuildRates& rates,
                                const TraceCost& trace);

/// The report's sentence for a kept refit ("refit: extra trace 3.1 ms so far < rebuild (fast)
/// 35.2 ms"), a rebuild after a refit and an exploding object's rebuild.
std::string explain_refit(const RefitJudgement& judgement);
std::string explain_skipped_refit(const ObjectCosts& costs, const RebuildChoice& choice);
std::string explain_rebuild(const RebuildChoice& choice);

}  // namespace dynrt
