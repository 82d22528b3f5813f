// The gnuplot script behind `dynrt bench --plot`: the right data, axes and layout per sweep.

#include "dynrt/bench/bench_plot.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <set>
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

TEST(ErrorPlot, TheParetoFrontIsThePointsNoOtherBeatsOnBoth) {
    const auto point = [](const char* label, double ms, double error) {
        return ErrorPoint{label, Spread{ms, ms, ms}, error};
    };
    const std::vector<ErrorPoint> points = {
        point("exact", 10, 1e-7),  point("slow exact", 12, 1e-7), point("fast", 4, 1e-2),
        point("worse", 5, 2e-2),   point("middle", 6, 1e-3),      point("tie", 10, 1e-7)};
    // "slow exact" and "worse" are beaten; the two equal "exact" rows beat neither each other.
    EXPECT_EQ(pareto_front(points), (std::vector<std::size_t>{0, 2, 4, 5}));

    const std::string s = error_plot_script(points, "t", "e.png");
    EXPECT_TRUE(contains(s, "set logscale x 10"));
    EXPECT_TRUE(contains(s, "0.01 4 4 4 \"fast\""));
    EXPECT_TRUE(contains(s, "Pareto front"));
    EXPECT_TRUE(contains(s, "with labels"));
    // The front's block is sorted by error.
    const std::size_t front = s.find("$front << EOD");
    ASSERT_NE(front, std::string::npos);
    EXPECT_LT(s.find("1e-07 10", front), s.find("0.001 6", front));
    EXPECT_LT(s.find("0.001 6", front), s.find("0.01 4", front));
}

TEST(ErrorPlot, ZeroErrorSitsADecadeBelowOnALogAxisAndNarrowRangesStayLinear) {
    const std::vector<ErrorPoint> spread = {{"a", {1, 1, 1}, 0.0}, {"b", {2, 2, 2}, 1e-4},
                                            {"c", {3, 3, 3}, 1e-2}};
    const std::string s = error_plot_script(spread, "t", "e.png");
    EXPECT_TRUE(contains(s, "set logscale x"));
    EXPECT_TRUE(contains(s, "1e-05 1 1 1 \"a (0)\""));
    const std::vector<ErrorPoint> narrow = {{"a", {1, 1, 1}, 1e-3}, {"b", {2, 2, 2}, 2e-3}};
    EXPECT_FALSE(contains(error_plot_script(narrow, "t", "e.png"), "logscale"));
    EXPECT_THROW(error_plot_script({}, "t", "e.png"), std::invalid_argument);
}

// Errors over a narrow range (adaptive tolerances that change a few pixels): gnuplot puts
// about ten ticks over it, and each must read differently in the script's format.
TEST(ErrorPlot, TicksOverANarrowRangeReadApart) {
    const std::vector<ErrorPoint> close = {{"a", {3, 3, 3}, 9.42e-8}, {"b", {2, 2, 2}, 9.44e-8},
                                           {"c", {1, 1, 1}, 9.46e-8}};
    const std::string s = error_plot_script(close, "t", "e.png");
    const std::size_t at = s.find("set format x '");
    ASSERT_NE(at, std::string::npos) << s;
    const std::string format = s.substr(at + 14, s.find('\'', at + 14) - at - 14);
    std::set<std::string> labels;
    for (int k = 0; k <= 10; ++k) {
        char label[64];
        std::snprintf(label, sizeof label, format.c_str(), 9.42e-8 + k * 0.04e-8 / 10);
        labels.insert(label);
    }
    EXPECT_EQ(labels.size(), 11u) << "format " << format;
}

TEST(ErrorPlot, AxesSayWhatTheyMeasure) {
    const std::vector<ErrorPoint> points = {{"a", {1, 1, 1}, 0.0}, {"b", {2, 2, 2}, 1e-2}};
    // By default the still frame's RMSE against the exact reference.
    EXPECT_TRUE(contains(error_plot_script(points, "t", "e.png"), "set xlabel 'RMSE against"));
    const std::string s =
        error_plot_script(points, "t", "e.png", ErrorPlotAxes{"1 - mean SSIM", "ms per frame"});
    EXPECT_TRUE(contains(s, "set xlabel '1 - mean SSIM'"));
    EXPECT_TRUE(contains(s, "set ylabel 'ms per frame'"));
    EXPECT_FALSE(contains(s, "RMSE"));
}

}  // namespace
}  // namespace dynrt
