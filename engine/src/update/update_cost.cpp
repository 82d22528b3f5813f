// The refit / fast rebuild / SAH rebuild choice from measured costs (update_cost.h, which
// gives the model and its sources).

#include "dynrt/engine/update_cost.h"

#include <algorithm>
#include <cstdio>

namespace dynrt {

const char* update_method_name(UpdateMethod method) {
    switch (method) {
        case UpdateMethod::automatic: return "auto";
        case UpdateMethod::threshold: return "threshold";
        case UpdateMethod::refit: return "refit";
        case UpdateMethod::fast: return "fast";
        case UpdateMethod::sah: return "sah";
    }
    return "unknown";
}

std::optional<UpdateMethod> parse_update_method(std::string_view name) {
    for (UpdateMethod method : {UpdateMethod::automatic, UpdateMethod::threshold,
                                UpdateMethod::refit, UpdateMethod::fast, UpdateMethod::sah}) {
        if (name == update_method_name(method)) return method;
    }
    return std::nullopt;
}

RebuildChoice choose_rebuild(const ObjectCosts& costs, std::size_t triangles,
                             const BuildRates& rates, const TraceCost& trace) {
    const double n = static_cast<double>(triangles);
    RebuildChoice choice;
    choice.fast_build_ms = costs.fast_ms >= 0.0 ? costs.fast_ms : n * rates.fast_ns * 1e-6;
    choice.sah_build_ms = costs.sah_ms >= 0.0 ? costs.sah_ms : n * rates.sah_ns * 1e-6;
    choice.fast_trace_extra_ms = trace.trace_ms * trace.share / std::max(1.0, trace.degradation) *
                                 std::max(0.0, costs.fast_quality - 1.0);
    choice.method = choice.fast_total() < choice.sah_build_ms ? bvh::BuildMethod::morton
                                                              : bvh::BuildMethod::binned_sah;
    return choice;
}

RefitJudgement judge_refit_cost(double refit_sah, double fresh_sah, const ObjectCosts& costs,
                                std::size_t triangles, const BuildRates& rates,
                                const TraceCost& trace) {
    RefitJudgement j;
    const double degradation = fresh_sah > 0.0 ? std::max(0.0, refit_sah / fresh_sah - 1.0) : 0.0;
    j.extra_ms = trace.trace_ms * trace.share * degradation;
    j.penalty_ms = costs.penalty_ms + j.extra_ms;
    j.choice = choose_rebuild(costs, triangles, rates, trace);
    j.rebuild = j.penalty_ms >= j.choice.cost();
    return j;
}

std::optional<RebuildChoice> rebuild_instead_of_refit(const ObjectCosts& costs,
                                                      std::size_t triangles,
                                                      const BuildRates& rates,
                                                      const TraceCost& trace) {
    if (costs.last_extra_ms < 0.0 || costs.refit_ms < 0.0) return std::nullopt;
    const RebuildChoice choice = choose_rebuild(costs, triangles, rates, trace);
    if (costs.last_extra_ms >= choice.cost() - costs.refit_ms) return choice;
    return std::nullopt;
}

namespace {

const char* method_word(bvh::BuildMethod method) {
    return method == bvh::BuildMethod::morton ? "fast" : "sah";
}

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0,
                   double d = 0.0) {
    char text[256];
    std::snprintf(text, sizeof text, pattern, a, b, c, d);
    return text;
}

}  // namespace

std::string explain_rebuild(const RebuildChoice& c) {
    const std::string fast = format("fast %.1f ms + trace %+.1f ms", c.fast_build_ms,
                                    c.fast_trace_extra_ms);
    const std::string sah = format("sah %.1f ms", c.sah_build_ms);
    return c.method == bvh::BuildMethod::morton ? fast + " < " + sah : sah + " <= " + fast;
}

std::string explain_skipped_refit(const ObjectCosts& costs, const RebuildChoice& c) {
    return format("last refit's extra trace %.1f ms >= rebuild %.1f ms - refit %.1f ms; ",
                  costs.last_extra_ms, c.cost(), costs.refit_ms) +
           explain_rebuild(c);
}

std::string explain_refit(const RefitJudgement& j) {
    const std::string penalty =
        format("refits' extra trace %.1f ms so far (%.1f this frame)", j.penalty_ms, j.extra_ms);
    const std::string rebuild =
        std::string("rebuild (") + method_word(j.choice.method) + format(") %.1f ms", j.choice.cost());
    if (j.rebuild) return penalty + " >= " + rebuild + "; " + explain_rebuild(j.choice);
    return penalty + " < " + rebuild;
}

}  // namespace dynrt
