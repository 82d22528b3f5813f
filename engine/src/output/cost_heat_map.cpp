// cost_scale and cost_heat_rgb8 (dynrt/engine/pixel_cost.h).

#include "dynrt/engine/pixel_cost.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace dynrt {

namespace {

/// The ramp's stops: a fraction of the scale and its colour, in 8-bit sRGB.
struct Stop {
    float at;
    std::array<float, 3> rgb;
};

constexpr Stop kRamp[] = {
    {0.00f, {0, 0, 0}},       {0.20f, {60, 10, 110}},   {0.45f, {200, 30, 50}},
    {0.70f, {250, 140, 20}},  {0.90f, {255, 230, 90}},  {1.00f, {255, 255, 255}},
};

}  // namespace

std::uint32_t cost_scale(std::span<const PixelCost> costs, CostMeasure measure) {
    if (costs.empty()) return 1;
    std::vector<std::uint32_t> values(costs.size());
    std::transform(costs.begin(), costs.end(), values.begin(), [&](const PixelCost& c) { return cost_of(c, measure); });
    const std::size_t k = (values.size() - 1) * 99 / 100;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    const std::uint64_t high = std::max<std::uint32_t>(values[k], 1);
    for (std::uint64_t power = 1;; power *= 10) {
        for (const std::uint64_t step : {1u, 2u, 5u}) {
            if (step * power >= high) return std::uint32_t(std::min<std::uint64_t>(step * power, 0xffffffffu));
        }
    }
}

std::vector<std::uint8_t> cost_heat_rgb8(std::span<const PixelCost> costs, CostMeasure measure, std::uint32_t scale) {
    if (scale == 0) throw std::invalid_argument("cost heat map: the scale must be at least 1");
    std::vector<std::uint8_t> rgb(costs.size() * 3);
    for (std::size_t i = 0; i < costs.size(); ++i) {
        const float f = std::min(float(cost_of(costs[i], measure)) / float(scale), 1.0f);
        std::size_t s = 1;
        while (s + 1 < std::size(kRamp) && kRamp[s].at < f) ++s;
        const Stop& a = kRamp[s - 1];
        const Stop& b = kRamp[s];
        const float t = (f - a.at) / (b.at - a.at);
        for (int c = 0; c < 3; ++c) rgb[3 * i + std::size_t(c)] = std::uint8_t(a.rgb[c] + t * (b.rgb[c] - a.rgb[c]) + 0.5f);
    }
    return rgb;
}

}  // namespace dynrt
