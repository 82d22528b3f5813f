// Splitting a frame or a ray batch across processes with the library API (dynrt/api/
// distribute.h): engines given the same meshes and moves, each rendering its tile share into
// a caller's image that keeps its other pixels, gather to the whole render bit for bit, frame
// after frame (exact reuse per share); ray shares cover a batch once, in order.

#include "api_test_world.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr int kWidth = 72, kHeight = 40;  // clipped edge tiles on both axes
constexpr int kShares = 3;

struct Scene {
    Engine engine;
    MeshId cloth{};
    MeshData sheet_mesh = sheet(0.0f, 0.0f, 0.0f, 2.0f, 12);
    Scene() {
        MeshDesc floor;
        const MeshData f = sheet(0.0f, 0.0f, 0.0f, 8.0f, 8);
        floor.positions = f.positions;
        floor.indices = f.indices;
        floor.transform = Transform::rotation({1.0f, 0.0f, 0.0f}, -1.5707964f, {0.0f, -1.0f, 0.0f});
        engine.add_mesh(floor);
        MeshDesc cloth_desc;
        cloth_desc.positions = sheet_mesh.positions;
        cloth_desc.indices = sheet_mesh.indices;
        cloth_desc.motion = Motion::deformable;
        cloth_desc.surface.diffuse = {0.2f, 0.3f, 0.9f};
        cloth = engine.add_mesh(cloth_desc);
    }
    void step(int s) {
        engine.set_positions(cloth, waved(sheet_mesh, 0.4f * float(s), 0.3f));
        engine.update();
    }
};

TEST(ApiDistribute, TileSharesGatherToTheWholeRenderFrameAfterFrame) {
    Scene whole;
    std::vector<std::unique_ptr<Scene>> parts;
    for (int r = 0; r < kShares; ++r) parts.push_back(std::make_unique<Scene>());
    View view;
    view.eye = {0.0f, 2.0f, 5.0f};
    view.target = {0.0f, -0.5f, 0.0f};
    const std::size_t pixels = std::size_t(kWidth) * kHeight;
    std::vector<float> expected(3 * pixels), gathered(3 * pixels);
    std::vector<float> expected_depth(pixels), gathered_depth(pixels);
    for (int s = 0; s < 4; ++s) {
        SCOPED_TRACE("step " + std::to_string(s));
        whole.step(s);
        whole.engine.render(view, ImageView{kWidth, kHeight, expected, expected_depth});
        // Each share renders into its own image, whose other pixels hold a marker that must
        // survive; the gather copies the share's pixels in tile_share_pixels order.
        std::set<std::size_t> covered;
        for (int r = 0; r < kShares; ++r) {
            parts[std::size_t(r)]->step(s);
            std::vector<float> rgb(3 * pixels, -7.0f), depth(pixels, -7.0f);
            RenderSettings settings;
            settings.tile_share = r;
            settings.tile_shares = kShares;
            parts[std::size_t(r)]->engine.render(view, ImageView{kWidth, kHeight, rgb, depth}, settings);
            const std::vector<std::size_t> mine = tile_share_pixels(kWidth, kHeight, r, kShares);
            std::vector<bool> in_share(pixels, false);
            for (const std::size_t p : mine) {
                in_share[p] = true;
                covered.insert(p);
                std::memcpy(&gathered[3 * p], &rgb[3 * p], 3 * sizeof(float));
                gathered_depth[p] = depth[p];
            }
            for (std::size_t p = 0; p < pixels; ++p) {
                if (!in_share[p]) {
                    ASSERT_EQ(depth[p], -7.0f) << "pixel " << p << " outside share " << r;
                }
            }
        }
        EXPECT_EQ(covered.size(), pixels);
        EXPECT_EQ(std::memcmp(gathered.data(), expected.data(), gathered.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(gathered_depth.data(), expected_depth.data(), pixels * sizeof(float)), 0);
    }
}

TEST(ApiDistribute, RaySharesCoverABatchOnceInOrder) {
    for (const std::size_t count : {std::size_t(0), std::size_t(1), std::size_t(10), std::size_t(1000003)}) {
        std::size_t next = 0;
        for (int r = 0; r < 7; ++r) {
            const RayShare share = ray_share(count, r, 7);
            EXPECT_EQ(share.begin, next);
            EXPECT_LE(share.end - share.begin, count / 7 + 1);
            next = share.end;
        }
        EXPECT_EQ(next, count);
    }
}

TEST(ApiDistribute, BadSharesAreRefused) {
    expect_error([] { tile_share_pixels(64, 64, 3, 3); }, Error::Code::invalid_argument, {"share 3 of 3"});
    expect_error([] { tile_share_pixels(0, 64, 0, 1); }, Error::Code::invalid_argument, {"image size"});
    expect_error([] { ray_share(10, -1, 2); }, Error::Code::invalid_argument, {"share -1 of 2"});
    Scene scene;
    scene.step(0);
    std::vector<float> rgb(3 * 16 * 16);
    RenderSettings settings;
    settings.tile_shares = 0;
    expect_error([&] { scene.engine.render(View{}, ImageView{16, 16, rgb}, settings); },
                 Error::Code::invalid_argument, {"tile share 0 of 0"});
}

}  // namespace
}  // namespace dynrt::api_test
