#include "dynrt/engine/pixel_reuse.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace dynrt {

const char* pixel_reuse_name(PixelReuse mode) {
    switch (mode) {
        case PixelReuse::off: return "off";
        case PixelReuse::exact: return "exact";
        case PixelReuse::render_cache: return "cache";
        case PixelReuse::frameless: return "frameless";
    }
    return "unknown";
}

namespace {

[[noreturn]] void bad_reuse(std::string_view text, const char* why) {
    throw std::invalid_argument("pixel reuse '" + std::string(text) + "': " + why +
                                " (off, exact, cache[:SHARE|:MSms], frameless[:SHARE|:MSms])");
}

}  // namespace

ReuseSettings parse_reuse(std::string_view text) {
    ReuseSettings reuse;
    const std::size_t colon = text.find(':');
    const std::string_view name = text.substr(0, colon);
    if (name == "off") {
        reuse.mode = PixelReuse::off;
    } else if (name == "exact") {
        reuse.mode = PixelReuse::exact;
    } else if (name == "cache") {
        reuse.mode = PixelReuse::render_cache;
    } else if (name == "frameless") {
        reuse.mode = PixelReuse::frameless;
    } else {
        bad_reuse(text, "unknown mode");
    }
    if (colon == std::string_view::npos) return reuse;
    if (!reuse.approximate()) bad_reuse(text, "only the approximate modes take a budget");
    std::string_view budget = text.substr(colon + 1);
    const bool ms = budget.size() > 2 && budget.substr(budget.size() - 2) == "ms";
    if (ms) budget.remove_suffix(2);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(budget.data(), budget.data() + budget.size(), value);
    if (ec != std::errc() || end != budget.data() + budget.size() || !std::isfinite(value)) {
        bad_reuse(text, "the budget is not a number");
    }
    if (ms) {
        if (value <= 0.0) bad_reuse(text, "a budget in ms must be above 0");
        reuse.budget_ms = value;
    } else {
        if (!(value > 0.0 && value <= 1.0)) bad_reuse(text, "a share of pixels must be in (0, 1]");
        reuse.budget_share = float(value);
    }
    return reuse;
}

std::string to_string(const ReuseSettings& reuse) {
    std::string text = pixel_reuse_name(reuse.mode);
    if (!reuse.approximate()) return text;
    char number[32];
    if (reuse.budget_ms > 0.0) {
        const auto [end, ec] = std::to_chars(number, number + sizeof(number), reuse.budget_ms);
        return text + ":" + std::string(number, end) + "ms";
    }
    const auto [end, ec] = std::to_chars(number, number + sizeof(number), reuse.budget_share);
    return text + ":" + std::string(number, end);
}

}  // namespace dynrt
