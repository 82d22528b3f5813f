// What a slow stage of a command tells while it runs (engine/cli/stage_progress.h): nothing
// for a quick one; for a slow one its time and memory every so often, and a closing line that
// says whether it finished or failed.

#include "stage_progress.h"

#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

namespace dynrt::cli {
namespace {

using namespace std::chrono_literals;

int count_of(const std::string& text, const std::string& part) {
    int n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

TEST(StageProgress, AQuickStageSaysNothing) {
    std::ostringstream out;
    { const StageProgress progress("loading quick", out, false, 10s, 1s); }
    EXPECT_EQ(out.str(), "");
}

TEST(StageProgress, ASlowStageTellsItsTimeAndMemoryAndThatItIsDone) {
    std::ostringstream out;
    {
        const StageProgress progress("loading slow", out, false, 0ms, 20ms);
        std::this_thread::sleep_for(300ms);
    }
    const std::string text = out.str();
    // A line at once, then about every 20 ms: at least two before the closing one.
    EXPECT_GE(count_of(text, "loading slow: "), 3) << text;
    EXPECT_EQ(count_of(text, "loading slow: done in "), 1) << text;
    EXPECT_NE(text.find(" GB resident"), std::string::npos) << text;  // Linux
    EXPECT_EQ(text.back(), '\n');
    EXPECT_EQ(text.find('\r'), std::string::npos);  // lines, not redrawn, off a terminal
}

TEST(StageProgress, OnATerminalTheLineIsRedrawnInPlace) {
    std::ostringstream out;
    {
        const StageProgress progress("loading", out, true, 0ms, 10ms);
        std::this_thread::sleep_for(50ms);
    }
    const std::string text = out.str();
    EXPECT_EQ(text.front(), '\r');
    EXPECT_EQ(count_of(text, "\n"), 1) << text;  // only after the closing line
}

TEST(StageProgress, AStageEndedByAnErrorSaysWhereItStopped) {
    std::ostringstream out;
    try {
        const StageProgress progress("loading bad", out, false, 0ms, 1s);
        std::this_thread::sleep_for(100ms);
        throw std::runtime_error("bad file");
    } catch (const std::runtime_error&) {
    }
    EXPECT_NE(out.str().find("loading bad: stopped after "), std::string::npos) << out.str();
    EXPECT_EQ(out.str().find("done in"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace dynrt::cli
