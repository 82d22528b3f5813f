// The hand-out of frames to the processes of a render across processes (engine/cli/distributed/
// frame_handout.h, guided self-scheduling): every frame exactly once, in order, in runs that
// shrink from frames-left / (2 processes) to single frames.

#include "distributed/frame_handout.h"

#include <gtest/gtest.h>

#include <vector>

namespace dynrt::cli {
namespace frame_handout_test {

TEST(FrameHandout, HandsOutEveryFrameOnceInShrinkingRuns) {
    std::vector<int> todo;
    for (int f = 100; f < 900; ++f) todo.push_back(f);
    FrameHandout handout(todo, 4);
    std::vector<int> seen;
    std::vector<std::size_t> runs;
    for (std::vector<int> run = handout.take(); !run.empty(); run = handout.take()) {
        runs.push_back(run.size());
        for (std::size_t i = 1; i < run.size(); ++i) EXPECT_EQ(run[i], run[i - 1] + 1);
        seen.insert(seen.end(), run.begin(), run.end());
    }
    EXPECT_EQ(seen, todo);
    ASSERT_GE(runs.size(), 8u);
    EXPECT_EQ(runs.front(), 100u);  // 800 left / (2 x 4)
    EXPECT_EQ(runs.back(), 1u);
    for (std::size_t i = 1; i < runs.size(); ++i) EXPECT_LE(runs[i], runs[i - 1]);
    EXPECT_EQ(handout.left(), 0u);
    EXPECT_TRUE(handout.take().empty());  // and again: still nothing
}

TEST(FrameHandout, ResumedJobsSkipTheFramesDoneAndOneProcessTakesHalves) {
    FrameHandout gaps({0, 1, 2, 7, 8, 20}, 1);
    EXPECT_EQ(gaps.take(), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(gaps.take(), (std::vector<int>{7, 8}));
    EXPECT_EQ(gaps.take(), (std::vector<int>{20}));
    EXPECT_TRUE(gaps.take().empty());
    FrameHandout none({}, 3);
    EXPECT_TRUE(none.take().empty());
    EXPECT_THROW(FrameHandout({1}, 0), std::invalid_argument);
}

}  // namespace frame_handout_test
}  // namespace dynrt::cli
