// Warnings (dynrt/scene/warnings.h): grouped once per kind of problem with a count and the
// first few items, every one with --verbose, none with --quiet; collected from any thread.

#include "dynrt/scene/warnings.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace dynrt {
namespace {

/// Material m's texture, one of `files` texture files, missing.
Warning missing_texture(int m, int files) {
    return {.source = "city.aff",
            .kind = "texture cannot be read",
            .kinds = "textures cannot be read",
            .item = "tex" + std::to_string(m % files) + ".ppm",
            .user = "material 'm" + std::to_string(m) + "'",
            .users = "materials",
            .detail = "no such file",
            .effect = "the diffuse colour is used alone"};
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::string printed(WarningLog& log, WarningDetail detail) {
    std::ostringstream out;
    log.print(out, detail);
    return out.str();
}

TEST(Warnings, OneKindOfProblemIsOneLineWithCountsAndTheFirstItems) {
    WarningLog log;
    for (int m = 0; m < 15; ++m) log.add(missing_texture(m, 8));
    const std::vector<std::string> lines = lines_of(printed(log, WarningDetail::grouped));
    ASSERT_EQ(lines.size(), 1u) << printed(log, WarningDetail::grouped);
    EXPECT_EQ(lines[0],
              "dynrt: warning: city.aff: 8 textures cannot be read (no such file): tex0.ppm, "
              "tex1.ppm, tex2.ppm and 5 more (--verbose lists them), used by 15 materials; the "
              "diffuse colour is used alone");
}

TEST(Warnings, ASingleItemIsNamedWithItsUser) {
    WarningLog log;
    log.add(missing_texture(0, 1));
    EXPECT_EQ(printed(log, WarningDetail::grouped),
              "dynrt: warning: city.aff: texture cannot be read: tex0.ppm (no such file), used by "
              "material 'm0'; the diffuse colour is used alone\n");
    // Three items are all named, with no "more".
    for (int m = 0; m < 3; ++m) log.add(missing_texture(m, 3));
    const std::string three = printed(log, WarningDetail::grouped);
    EXPECT_NE(three.find("3 textures cannot be read (no such file): tex0.ppm, tex1.ppm and tex2.ppm, used by 3 materials"),
              std::string::npos)
        << three;
}

TEST(Warnings, KindsSourcesAndEffectsAreSeparateGroupsInTheOrderTheyCame) {
    WarningLog log;
    log.add({.kind = "frames 30-40 are past the end of the animation", .effect = "they repeat its last pose"});
    log.add(missing_texture(0, 2));
    Warning other_file = missing_texture(1, 2);
    other_file.source = "robot.aff";
    log.add(other_file);
    log.add(missing_texture(2, 2));
    const std::vector<std::string> lines = lines_of(printed(log, WarningDetail::grouped));
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0], "dynrt: warning: frames 30-40 are past the end of the animation; they repeat its last pose");
    EXPECT_NE(lines[1].find("city.aff: texture cannot be read: tex0.ppm (no such file), used by 2 materials"),
              std::string::npos)
        << lines[1];
    EXPECT_NE(lines[2].find("robot.aff: texture cannot be read: tex1.ppm"), std::string::npos) << lines[2];
}

TEST(Warnings, ReasonsThatDifferPerItemAreLeftToVerbose) {
    WarningLog log;
    Warning a = missing_texture(0, 2), b = missing_texture(1, 2);
    a.detail = "not a PPM file";
    log.add(a);
    log.add(b);
    const std::string grouped = printed(log, WarningDetail::grouped);
    EXPECT_EQ(grouped.find("not a PPM"), std::string::npos) << grouped;
    EXPECT_EQ(grouped.find("no such file"), std::string::npos) << grouped;
    log.add(a);
    log.add(b);
    const std::string every = printed(log, WarningDetail::every);
    EXPECT_NE(every.find("tex0.ppm (not a PPM file), used by material 'm0'"), std::string::npos) << every;
    EXPECT_NE(every.find("tex1.ppm (no such file), used by material 'm1'"), std::string::npos) << every;
}

TEST(Warnings, VerboseListsEveryWarningAndQuietNone) {
    WarningLog log;
    for (int m = 0; m < 15; ++m) log.add(missing_texture(m, 8));
    EXPECT_EQ(lines_of(printed(log, WarningDetail::every)).size(), 15u);
    // Printing forgets what it printed.
    EXPECT_EQ(log.pending(), 0u);
    EXPECT_EQ(printed(log, WarningDetail::grouped), "");
    for (int m = 0; m < 15; ++m) log.add(missing_texture(m, 8));
    EXPECT_EQ(printed(log, WarningDetail::none), "");
    EXPECT_EQ(log.pending(), 0u);
}

TEST(Warnings, WarnGoesToTheInstalledLogFromEveryThreadAndToStderrWithout) {
    WarningLog log;
    {
        const ScopedWarningLog scope(log);
        std::vector<std::thread> threads;
        for (int t = 0; t < 4; ++t) {
            threads.emplace_back([t] {
                for (int m = 0; m < 50; ++m) warn(missing_texture(t * 50 + m, 8));
            });
        }
        for (std::thread& thread : threads) thread.join();
    }
    EXPECT_EQ(log.pending(), 200u);
    const std::string grouped = printed(log, WarningDetail::grouped);
    EXPECT_NE(grouped.find("8 textures cannot be read"), std::string::npos) << grouped;
    EXPECT_NE(grouped.find("used by 200 materials"), std::string::npos) << grouped;
    // Without a log, warn prints at once and the log sees nothing.
    testing::internal::CaptureStderr();
    warn(missing_texture(0, 1));
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, "dynrt: warning: " + warning_line(missing_texture(0, 1)) + "\n");
    EXPECT_EQ(log.pending(), 0u);
}

}  // namespace
}  // namespace dynrt
