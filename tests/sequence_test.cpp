// Frame ranges, output-path patterns and glTF cameras for sequence rendering.

#include "dynrt/engine/sequence.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace dynrt {
namespace {

TEST(FrameRange, ParsesRangesAndCounts) {
    const FrameRange a = parse_frame_range("3-7");
    EXPECT_EQ(a.first, 3);
    EXPECT_EQ(a.last, 7);
    EXPECT_EQ(a.count(), 5);
    const FrameRange b = parse_frame_range("32");
    EXPECT_EQ(b.first, 0);
    EXPECT_EQ(b.last, 31);
    const FrameRange c = parse_frame_range("0-0");
    EXPECT_EQ(c.count(), 1);
}

TEST(FrameRange, RefusesMalformedText) {
    for (const char* bad : {"", "0", "-1", "5-3", "a-b", "1-", "-", "1-2-3", "1.5", "2-x"}) {
        EXPECT_THROW(parse_frame_range(bad), std::invalid_argument) << bad;
    }
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
