// The gnuplot script behind `dynrt bench --plot`: the right data, axes and layout per sweep.

#include "dynrt/engine/bench_plot.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace dynrt {
namespace {

BenchRow row(float cost_ratio, std::uint32_t leaf, double build_ms, double trace_ms) {
    BenchRow r;
    r.build.cost_ratio = cost_ratio;
    r.build.leaf_size_max = leaf;
    r.build_ms = {build_ms, build_ms - 1, build_ms + 1};
    r.trace_ms = {trace_ms, trace_ms, trace_ms};
    r.total_ms = {build_ms + trace_ms, build_ms + trace_ms, build_ms + trace_ms};
    return r;
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(BenchPlot, OneSweptCostRatioGivesOneLogChartWithRowsSortedByX) {
    const std::string s = bench_plot_script({row(1, 8, 30, 60), row(0.1f, 8, 20, 70)},
                                            "my title", "out/chart.png");
    EXPECT_TRUE(contains(s, "set output 'out/chart.png'"));
    EXPECT_TRUE(contains(s, "set logscale x 10"));
    EXPECT_TRUE(contains(s, "set xtics (0.1, 1)"));
    EXPECT_TRUE(contains(s, "'my title'"));
    EXPECT_TRUE(contains(s, "SAH cost ratio"));
    // x, build median/min/max, trace, total; the 0.1 row first although given second.
    EXPECT_TRUE(contains(s, "0.1 20 19 21 70 70 70 90 90 90\n1 30 29 31 60 60 60 90 90 90\n"))
        << s;
    EXPECT_FALSE(contains(s, "multiplot"));
}

TEST(BenchPlot, LeafSweepUsesABaseTwoAxisAndNarrowRangesStayLinear) {
    const std::string leaf = bench_plot_script({row(1, 1, 1, 1), row(1, 32, 1, 1)}, "t", "a.png");
    EXPECT_TRUE(contains(leaf, "set logscale x 2"));
    EXPECT_TRUE(contains(leaf, "maximum triangles per leaf"));
    const std::string narrow =
        bench_plot_script({row(0.5f, 8, 1, 1), row(2, 8, 1, 1)}, "t", "a.png");
    EXPECT_FALSE(contains(narrow, "logscale"));
}

TEST(BenchPlot, TwoSweptParametersGiveThreePanelsWithALinePerLeafSize) {
    std::vector<BenchRow> rows;
    for (float c : {0.1f, 1.0f}) {
        for (std::uint32_t leaf : {2u, 8u}) rows.push_back(row(c, leaf, 1, 2));
    }
    const std::string s = bench_plot_script(rows, "t", "a.png");
    EXPECT_TRUE(contains(s, "set multiplot layout 1,3"));
    EXPECT_TRUE(contains(s, "'leaf 2'"));
    EXPECT_TRUE(contains(s, "'leaf 8'"));
    EXPECT_TRUE(contains(s, "$leaf1 using 1:8:9:10"));  // the total panel
}

TEST(BenchPlot, QuotesInTitlesAndPathsAreEscaped) {
    const std::string s = bench_plot_script({row(1, 8, 1, 1)}, "it's", "d'x.png");
    EXPECT_TRUE(contains(s, "'it''s'"));
    EXPECT_TRUE(contains(s, "set output 'd''x.png'"));
}

TEST(BenchPlot, NoRowsIsAnError) {
    EXPECT_THROW(bench_plot_script({}, "t", "a.png"), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
