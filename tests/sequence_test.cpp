// Frame ranges, output-path patterns and glTF cameras for sequence rendering.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/sequence.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace dynrt {
namespace {

TEST(FrameRange, ParsesRangesAndCounts) {
    const FrameRange a = parse_frame_range("3-7");
    EXPECT_EQ(a.first, 3);
    EXPECT_EQ(a.last, 7);
    EXPECT_EQ(a.count(), 5);
    // One number is that frame alone (Blender's -f 32), not the first 32 frames.
    const FrameRange b = parse_frame_range("32");
    EXPECT_EQ(b.first, 32);
    EXPECT_EQ(b.last, 32);
    EXPECT_EQ(parse_frame_range("0").count(), 1);
    const FrameRange c = parse_frame_range("0-0");
    EXPECT_EQ(c.count(), 1);
}

TEST(FrameRange, RefusesMalformedText) {
    for (const char* bad : {"", "-1", "5-3", "a-b", "1-", "-", "1-2-3", "1.5", "2-x"}) {
        EXPECT_THROW(parse_frame_range(bad), std::invalid_argument) << bad;
    }
}

/// The bound on frame numbers (kFrameMax) holds for every way of writing a range, however large
/// its numbers, and a refusal says why.
TEST(FrameRange, RefusesFramesBeyondTheBoundNamingIt) {
    const std::string bound = "frame numbers above " + std::to_string(kFrameMax);
    for (const char* far : {"2147483646-2147483647", "10000000-10000001", "0-10000000", "10000000",
                            "10000001", "99999999999999999999", "5-99999999999999999999999",
                            "99999999999999999999-99999999999999999999"}) {
        try {
            parse_frame_range(far);
            ADD_FAILURE() << far << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(bound), std::string::npos) << e.what();
        }
    }
    const FrameRange last = parse_frame_range("9999998-9999999");
    EXPECT_EQ(last.count(), 2);
    EXPECT_EQ(parse_frame_range("9999999").first, kFrameMax);
}

/// Property: any text made of digits, dashes and a few other characters either parses into a
/// range within the bound whose count is first..last, or is refused with invalid_argument.
TEST(FrameRange, RandomTextParsesWithinTheBoundOrIsRefused) {
    std::mt19937 rng(17);
    const std::string alphabet = "0123456789999--+ x.";
    std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1);
    std::uniform_int_distribution<int> length(0, 24);
    int parsed = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string text;
        const int n = length(rng);
        for (int k = 0; k < n; ++k) text += alphabet[pick(rng)];
        try {
            const FrameRange r = parse_frame_range(text);
            ++parsed;
            ASSERT_GE(r.first, 0) << text;
            ASSERT_LE(r.first, r.last) << text;
            ASSERT_LE(r.last, kFrameMax) << text;
            ASSERT_EQ(static_cast<long long>(r.count()), static_cast<long long>(r.last) - r.first + 1);
        } catch (const std::invalid_argument&) {
        }
    }
    EXPECT_GT(parsed, 100);
}

/// frame_of_path inverts frame_path: the frame whose file has a name, for the output checks.
TEST(FramePath, FindsTheFrameOfAFileName) {
    EXPECT_EQ(frame_of_path("frames/%04d.png", "frames/0007.png"), 7);
    EXPECT_EQ(frame_of_path("f%d.exr", "f123.exr"), 123);
    EXPECT_EQ(frame_of_path("f%3d.png", "f  5.png"), 5);
    EXPECT_EQ(frame_of_path("a%%b%d.png", "a%b3.png"), 3);
    EXPECT_EQ(frame_of_path("frames/%04d.png", "frames/7.png"), std::nullopt);  // not its name
    EXPECT_EQ(frame_of_path("frames/%04d.png", "frames/0007.jpg"), std::nullopt);
    EXPECT_EQ(frame_of_path("frames/%04d.png", "frames/abcd.png"), std::nullopt);
    EXPECT_EQ(frame_of_path("still.png", "still.png"), std::nullopt);
    for (int f : {0, 9, 10, 12345, kFrameMax}) EXPECT_EQ(frame_of_path("x/%05d_y.tif", frame_path("x/%05d_y.tif", f)), f);
}

TEST(FramePath, FormatsTheFrameNumber) {
    EXPECT_EQ(frame_path("frames/%04d.png", 7), "frames/0007.png");
    EXPECT_EQ(frame_path("f%d.exr", 123), "f123.exr");
    EXPECT_EQ(frame_path("100%%_%d.png", 5), "100%_5.png");
    EXPECT_EQ(frame_path("still.png", 5), "still.png");
    EXPECT_TRUE(has_frame_number("a/%03d.png"));
    EXPECT_FALSE(has_frame_number("a/100%%.png"));
}

TEST(FramePath, RefusesOtherConversions) {
    for (const char* bad : {"%s.png", "%d_%d.png", "%.3d.png", "%ld.png", "x%", "%x.png"}) {
        EXPECT_THROW(has_frame_number(bad), std::invalid_argument) << bad;
        EXPECT_THROW(frame_path(bad, 1), std::invalid_argument) << bad;
    }
}

/// Property: any pattern of %, d, digits, flags and other characters is either refused with
/// invalid_argument by both functions, or formats frames 0 and kFrameMax into paths that
/// differ exactly when it has a frame number, the larger one's digits in full.
TEST(FramePath, RandomPatternsFormatOrAreRefused) {
    std::mt19937 rng(23);
    const std::string alphabet = "%%%dd0123-+ #.lsxa/_";
    std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1);
    std::uniform_int_distribution<int> length(0, 12);
    int formatted = 0, numbered = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string pattern;
        const int n = length(rng);
        for (int k = 0; k < n; ++k) pattern += alphabet[pick(rng)];
        bool has = false;
        try {
            has = has_frame_number(pattern);
        } catch (const std::invalid_argument&) {
            EXPECT_THROW(frame_path(pattern, 0), std::invalid_argument) << pattern;
            continue;
        }
        const std::string a = frame_path(pattern, 0), b = frame_path(pattern, kFrameMax);
        ++formatted;
        numbered += has ? 1 : 0;
        ASSERT_EQ(a != b, has) << pattern;
        if (has) {
            ASSERT_NE(b.find(std::to_string(kFrameMax)), std::string::npos) << pattern << " -> " << b;
        }
    }
    EXPECT_GT(formatted, 1000);
    EXPECT_GT(numbered, 100);
}

TEST(SceneCamera, LooksAlongTheNodesMinusZ) {
    anim::PosedCamera posed;
    posed.eye = {1.0, 2.0, 3.0};
    posed.forward = {0.0, 0.0, -1.0};
    posed.up = {0.0, 1.0, 0.0};
    posed.yfov_rad = 0.5;
    const Camera camera = camera_from_scene(posed);
    EXPECT_EQ(camera.eye, glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(camera.target, glm::vec3(1.0f, 2.0f, 2.0f));
    EXPECT_EQ(camera.up, glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_NEAR(camera.fov_y_deg, 0.5 * 180.0 / M_PI, 1e-4);
}

}  // namespace
}  // namespace dynrt
