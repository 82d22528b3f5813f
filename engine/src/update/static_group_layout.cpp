#include "update/static_group_layout.h"

#include <array>
#include <cstdio>

namespace dynrt {

namespace {

/// The ladder, fastest (and largest) first.
constexpr std::array<StaticGroupLayout, 3> kLadder{{
    {false, false},
    {true, false},
    {true, true},
}};

std::string gigabytes(std::size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f GB", double(bytes) / 1e9);
    return text;
}

std::size_t predicted_peak(const StaticGroupLayout& layout, std::size_t triangles, std::size_t resident) {
    return resident + triangles * layout_peak_bytes_per_triangle(layout, triangles);
}

}  // namespace

std::string StaticGroupLayout::name() const {
    return std::string(compact_leaves ? "compact" : "full") + " leaves, " +
           (quantized_nodes ? "quantized" : "float") + " nodes";
}

std::uint32_t lean_leaf_size_min(std::size_t triangles) {
    if (triangles >= (std::size_t(1) << 23)) return 8;
    if (triangles >= (std::size_t(1) << 20)) return 4;
    return 1;
}

std::size_t layout_peak_bytes_per_triangle(const StaticGroupLayout& layout, std::size_t triangles) {
    if (!layout.compact_leaves) return 110;
    if (lean_leaf_size_min(triangles) >= 8) return 40;
    return layout.quantized_nodes ? 52 : 60;
}

StaticLayoutChoice choose_static_group_layout(std::size_t triangles, std::size_t resident, std::size_t budget) {
    // The first layout that fits, else the last (the smallest).
    std::size_t chosen = 0;
    while (chosen + 1 < kLadder.size() && predicted_peak(kLadder[chosen], triangles, resident) > budget) ++chosen;
    StaticLayoutChoice choice;
    choice.layout = kLadder[chosen];
    choice.predicted_peak = predicted_peak(choice.layout, triangles, resident);
    choice.fits = choice.predicted_peak <= budget;
    choice.why = "budget " + gigabytes(budget) + ": predicted peak " + gigabytes(choice.predicted_peak) + " (" +
                 gigabytes(resident) + " resident + " + std::to_string(triangles) + " triangles x " +
                 std::to_string(layout_peak_bytes_per_triangle(choice.layout, triangles)) + " B)";
    if (!choice.fits) {
        choice.why += ", over the budget even with the smallest layout";
    } else if (chosen > 0) {
        const StaticGroupLayout& faster = kLadder[chosen - 1];
        choice.why += "; " + faster.name() + " would peak at " +
                      gigabytes(predicted_peak(faster, triangles, resident));
    }
    return choice;
}

}  // namespace dynrt
