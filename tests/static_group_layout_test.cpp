// The memory budget's choice of the static group's layout (engine/src/update/static_group_layout.h):
// the fastest layout whose predicted peak fits, the smallest when none does, and the prediction
// it reports.

#include "update/static_group_layout.h"

#include <gtest/gtest.h>

#include <string>

namespace dynrt {
namespace {

constexpr StaticGroupLayout kFull{false, false};
constexpr StaticGroupLayout kCompact{true, false};
constexpr StaticGroupLayout kSmallest{true, true};

bool same(const StaticGroupLayout& a, const StaticGroupLayout& b) {
    return a.compact_leaves == b.compact_leaves && a.quantized_nodes == b.quantized_nodes;
}

std::size_t peak(const StaticGroupLayout& layout, std::size_t triangles, std::size_t resident) {
    return resident + triangles * layout_peak_bytes_per_triangle(layout, triangles);
}

TEST(StaticGroupLayout, TheLadderGetsSmallerAsItGetsSlower) {
    constexpr std::size_t kMillion = 1'000'000;
    EXPECT_GT(layout_peak_bytes_per_triangle(kFull, kMillion), layout_peak_bytes_per_triangle(kCompact, kMillion));
    EXPECT_GT(layout_peak_bytes_per_triangle(kCompact, kMillion), layout_peak_bytes_per_triangle(kSmallest, kMillion));
    EXPECT_EQ(kFull.name(), "full leaves, float nodes");
    EXPECT_EQ(kSmallest.name(), "compact leaves, quantized nodes");
}

TEST(StaticGroupLayout, TheFastestLayoutWhosePeakFitsIsChosenAtEachBoundary) {
    const std::size_t triangles = 4'000'000, resident = 400'000'000;
    struct Case {
        std::size_t budget;
        StaticGroupLayout want;
        bool fits;
    };
    const Case cases[] = {
        {peak(kFull, triangles, resident), kFull, true},  // exactly the full layout's peak
        {peak(kFull, triangles, resident) - 1, kCompact, true},
        {peak(kCompact, triangles, resident), kCompact, true},
        {peak(kCompact, triangles, resident) - 1, kSmallest, true},
        {peak(kSmallest, triangles, resident), kSmallest, true},
        {peak(kSmallest, triangles, resident) - 1, kSmallest, false},  // nothing fits
        {1'000'000, kSmallest, false},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE("budget " + std::to_string(c.budget));
        const StaticLayoutChoice choice = choose_static_group_layout(triangles, resident, c.budget);
        EXPECT_TRUE(same(choice.layout, c.want)) << choice.layout.name();
        EXPECT_EQ(choice.fits, c.fits);
        EXPECT_EQ(choice.predicted_peak, peak(c.want, triangles, resident));
        EXPECT_EQ(choice.why.find("over the budget") != std::string::npos, !c.fits) << choice.why;
    }
}

TEST(StaticGroupLayout, TheReasonNamesTheFigures) {
    const std::size_t triangles = 4'000'000, resident = 480'000'000;
    const StaticLayoutChoice choice = choose_static_group_layout(triangles, resident, 800'000'000);
    EXPECT_TRUE(same(choice.layout, kCompact));
    // budget, prediction, its terms and what the faster layout would have cost.
    EXPECT_EQ(choice.why,
              "budget 0.80 GB: predicted peak 0.72 GB (0.48 GB resident + 4000000 triangles x 60 B); "
              "full leaves, float nodes would peak at 0.92 GB");
}

TEST(StaticGroupLayout, FromTwoToTheTwentyThirdTheCompactLayoutsPeakAlikeAndTheFasterIsChosen) {
    // Their builds' binary leaves take up to eight triangles from 2^23 (lean_leaf_size_min),
    // less scratch than from 2^20, where they take four.
    const std::size_t large = std::size_t(1) << 23;
    EXPECT_EQ(lean_leaf_size_min(large - 1), 4u);
    EXPECT_EQ(lean_leaf_size_min(large), 8u);
    EXPECT_EQ(lean_leaf_size_min((std::size_t(1) << 20) - 1), 1u);
    EXPECT_LT(layout_peak_bytes_per_triangle(kCompact, large), layout_peak_bytes_per_triangle(kCompact, large - 1));
    EXPECT_EQ(layout_peak_bytes_per_triangle(kCompact, large), layout_peak_bytes_per_triangle(kSmallest, large));
    EXPECT_GT(layout_peak_bytes_per_triangle(kFull, large), layout_peak_bytes_per_triangle(kCompact, large));
    const std::size_t triangles = 20'000'000, resident = 1'100'000'000;
    const std::size_t compact_peak = peak(kCompact, triangles, resident);
    const StaticLayoutChoice fits = choose_static_group_layout(triangles, resident, compact_peak);
    EXPECT_TRUE(same(fits.layout, kCompact)) << fits.layout.name();
    EXPECT_TRUE(fits.fits);
    const StaticLayoutChoice over = choose_static_group_layout(triangles, resident, compact_peak - 1);
    EXPECT_TRUE(same(over.layout, kSmallest)) << over.layout.name();
    EXPECT_FALSE(over.fits);
    EXPECT_NE(over.why.find("x 40 B), over the budget"), std::string::npos) << over.why;
}

TEST(StaticGroupLayout, NoTrianglesKeepTheFullLayout) {
    const StaticLayoutChoice choice = choose_static_group_layout(0, 100'000'000, 200'000'000);
    EXPECT_TRUE(same(choice.layout, kFull));
    EXPECT_TRUE(choice.fits);
}

}  // namespace
}  // namespace dynrt
