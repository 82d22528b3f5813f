// Pixel classification behind `dynrt bench --vs embree`'s hit agreement and --diff-image.

#include "dynrt/bench/hit_agreement.h"

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <stdexcept>

namespace dynrt {
namespace {

TEST(HitAgreement, CountsObjectAndPrimitiveDifferencesSeparately) {
    const HitAgreement a = compare_hits({-1, 0, 1, 1, 2}, {-1, 3, 4, 5, 6},
                                        {0, 0, 1, 1, -1}, {1, 3, 4, 9, -1});
    EXPECT_EQ(a.object_differs, 2u);     // miss vs hit, hit vs miss
    EXPECT_EQ(a.prim_only_differs, 1u);  // same object, other triangle
}

TEST(HitAgreement, ClassifiesEachPixelAndOrdersClassesByBadness) {
    const std::vector<PixelAgreement> p =
        classify_hits({-1, 0, 1, 1, 2}, {-1, 3, 4, 5, 6}, {-1, 1, 1, 1, 2}, {-1, 3, 4, 9, 6});
    EXPECT_EQ(p, (std::vector<PixelAgreement>{PixelAgreement::same, PixelAgreement::object,
                                              PixelAgreement::same, PixelAgreement::prim_only,
                                              PixelAgreement::same}));
    // bench --vs embree keeps the worst class over the build qualities with std::max.
    EXPECT_LT(PixelAgreement::same, PixelAgreement::prim_only);
    EXPECT_LT(PixelAgreement::prim_only, PixelAgreement::object);
}

TEST(HitAgreement, DifferentSizesAreAnError) {
    EXPECT_THROW(compare_hits({0, 1}, {0, 1}, {0}, {0}), std::invalid_argument);
    EXPECT_THROW(classify_hits({0}, {0, 1}, {0}, {0}), std::invalid_argument);
}

TEST(HitAgreement, DiffImageMarksObjectRedPrimitiveYellowAndDarkensTheRest) {
    RenderedFrame frame;
    frame.width = 3;
    frame.height = 1;
    frame.color = {glm::vec3(0.8f), glm::vec3(0.8f), glm::vec3(0.8f)};
    const std::filesystem::path path =
        std::filesystem::path(testing::TempDir()) / "dynrt_hit_diff.exr";
    write_disagreement_image(
        path, frame, {PixelAgreement::object, PixelAgreement::prim_only, PixelAgreement::same});
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    float pixels[9];
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels));
    EXPECT_EQ(pixels[0], 1.0f);  // red
    EXPECT_EQ(pixels[1], 0.0f);
    EXPECT_EQ(pixels[3], 1.0f);  // yellow
    EXPECT_GT(pixels[4], 0.5f);
    EXPECT_EQ(pixels[5], 0.0f);
    EXPECT_FLOAT_EQ(pixels[6], 0.2f);  // a quarter of 0.8
    EXPECT_THROW(write_disagreement_image(path, frame, {PixelAgreement::same}),
                 std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
