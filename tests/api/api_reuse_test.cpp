// Exact pixel reuse through the library API (RenderSettings::reuse_pixels): two engines are
// given the same calls step by step, one reusing the previous render's pixels and one tracing
// every pixel, and every render must be bit-identical (colour, depth and mesh ids) while the
// reusing engine really does keep pixels. The steps cover what can change in a simulation
// loop: a rigid mesh moving over a static floor (its shadow moves on the floor), a deformable
// mesh, a mesh entering the view, a changed surface, a moved light, a removed mesh, a mesh
// added, and a step where nothing changed.

#include "api_test_world.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr int kWidth = 72, kHeight = 56;

/// Two engines given every call alike.
struct Twins {
    Engine reusing, full;

    template <typename Call>
    auto both(Call&& call) {
        call(full);
        return call(reusing);
    }
};

struct Image {
    std::vector<float> rgb = std::vector<float>(std::size_t(kWidth) * kHeight * 3);
    std::vector<float> depth = std::vector<float>(std::size_t(kWidth) * kHeight);
    std::vector<std::int32_t> mesh = std::vector<std::int32_t>(std::size_t(kWidth) * kHeight);
    ImageView view() { return ImageView{kWidth, kHeight, rgb, depth, mesh}; }
};

bool same_bits(const Image& a, const Image& b) {
    return std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0 &&
           std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0 &&
           a.mesh == b.mesh;
}

/// The view both tests look from, and its light: with pixel reuse and without.
struct Shot {
    View view;
    RenderSettings settings, full_settings;
    Shot() {
        view.eye = {0.0f, 2.5f, 6.0f};
        view.target = {0.0f, -0.5f, 0.0f};
        settings.lights = {Light{{2.0f, 6.0f, 3.0f}, 1.0f}};
        full_settings = settings;
        full_settings.reuse_pixels = false;
    }
};

MeshId add(Engine& e, const std::string& name, const MeshData& m, Motion motion,
           const Transform& transform, Vec3 colour) {
    MeshDesc desc;
    desc.name = name;
    desc.positions = m.positions;
    desc.indices = m.indices;
    desc.motion = motion;
    desc.transform = transform;
    desc.surface.diffuse = colour;
    return e.add_mesh(desc);
}

/// The floor both tests stand their meshes on, lying at y = -1.
void add_floor(Twins& twins) {
    const MeshData floor = sheet(0.0f, 0.0f, 0.0f, 8.0f, 8);
    const Transform lying = Transform::rotation({1.0f, 0.0f, 0.0f}, -1.5707964f, {0.0f, -1.0f, 0.0f});
    twins.both([&](Engine& e) { return add(e, "floor", floor, Motion::static_, lying, {0.7f, 0.7f, 0.6f}); });
}

TEST(ApiReuse, EveryStepMatchesAFullRenderBitForBit) {
    Twins twins;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 0.5f);
    const MeshData cloth = sheet(0.0f, 0.0f, 0.0f, 1.5f, 10);
    add_floor(twins);
    const MeshId mover = twins.both([&](Engine& e) {
        return add(e, "ball", ball, Motion::rigid, Transform::translation({-1.5f, 0.0f, 0.0f}),
                   {0.9f, 0.2f, 0.2f});
    });
    const MeshId sheet_id = twins.both([&](Engine& e) {
        return add(e, "cloth", cloth, Motion::deformable, Transform::translation({1.2f, 0.3f, -1.0f}),
                   {0.2f, 0.3f, 0.9f});
    });
    // Starts far to the side, out of the view; enters it at step 4.
    const MeshId visitor = twins.both([&](Engine& e) {
        return add(e, "visitor", ball, Motion::rigid, Transform::translation({40.0f, 0.0f, 0.0f}),
                   {0.9f, 0.9f, 0.2f});
    });

    Shot shot;
    const View& view = shot.view;
    RenderSettings& settings = shot.settings;
    RenderSettings& full_settings = shot.full_settings;

    std::size_t reused = 0;
    for (int step = 0; step < 12; ++step) {
        SCOPED_TRACE("step " + std::to_string(step));
        const float x = -1.5f + 0.25f * float(step);
        if (step != 6) {  // step 6 changes nothing
            twins.both([&](Engine& e) {
                e.set_transform(mover, Transform::translation({x, 0.0f, 0.0f}));
                return 0;
            });
        }
        if (step % 3 == 1) {
            const std::vector<float> waved_cloth = waved(cloth, 0.4f * float(step), 0.2f);
            twins.both([&](Engine& e) {
                e.set_positions(sheet_id, waved_cloth);
                return 0;
            });
        }
        if (step == 4) {
            twins.both([&](Engine& e) {
                e.set_transform(visitor, Transform::translation({0.5f, 0.8f, 1.0f}));
                return 0;
            });
        }
        if (step == 5) {
            twins.both([&](Engine& e) {
                e.set_surface(sheet_id, Surface{{0.9f, 0.5f, 0.1f}, {0.4f, 0.4f, 0.4f}, 16.0f});
                return 0;
            });
        }
        if (step == 7) settings.lights[0].position = {-2.0f, 5.0f, 2.0f};  // a moved light
        full_settings.lights = settings.lights;
        if (step == 9) {
            twins.both([&](Engine& e) {
                e.remove_mesh(visitor);
                return 0;
            });
        }
        if (step == 10) {
            twins.both([&](Engine& e) {
                return add(e, "late", ball, Motion::static_, Transform::translation({-0.5f, 1.2f, 0.5f}),
                           {0.3f, 0.9f, 0.9f});
            });
        }
        twins.both([](Engine& e) {
            e.update();
            return 0;
        });
        Image with_reuse, without;
        const FrameStats stats = twins.reusing.render(view, with_reuse.view(), settings);
        const FrameStats full_stats = twins.full.render(view, without.view(), full_settings);
        EXPECT_TRUE(same_bits(with_reuse, without)) << stats.reuse_reason;
        EXPECT_EQ(full_stats.pixels_traced, std::size_t(kWidth) * kHeight);
        EXPECT_EQ(stats.pixels_traced + stats.pixels_shadows_retraced + stats.pixels_reused,
                  std::size_t(kWidth) * kHeight);
        if (step == 6) {
            EXPECT_EQ(stats.reuse_reason, "nothing changed");
            EXPECT_EQ(stats.pixels_traced, 0u);
        }
        if (step == 7) {
            EXPECT_EQ(stats.reuse_reason, "lights changed");
        }
        if (step == 5) {
            EXPECT_NE(stats.reuse_reason.find("changed material"), std::string::npos)
                << stats.reuse_reason;
        }
        reused += stats.pixels_reused;
    }
    // Exact reuse kept pixels, else the comparison above proves nothing about it.
    EXPECT_GT(reused, std::size_t(kWidth) * kHeight * 3);
}

// A mesh removed (or given new triangles) between updates: a render before the update still
// traces the last update's trees, and the render after it must not keep the removed mesh's
// pixels.
TEST(ApiReuse, RemovalSeenByTheRenderAfterTheUpdate) {
    Twins twins;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 0.8f);
    add_floor(twins);
    const MeshId gone = twins.both([&](Engine& e) {
        return add(e, "ball", ball, Motion::rigid, Transform::translation({0.0f, 0.0f, 0.0f}),
                   {0.9f, 0.2f, 0.2f});
    });
    const Shot shot;
    const auto render_both = [&](const char* what) {
        SCOPED_TRACE(what);
        Image with_reuse, without;
        const FrameStats stats = twins.reusing.render(shot.view, with_reuse.view(), shot.settings);
        twins.full.render(shot.view, without.view(), shot.full_settings);
        EXPECT_TRUE(same_bits(with_reuse, without)) << stats.reuse_reason;
        return with_reuse;
    };
    twins.both([](Engine& e) { e.update(); return 0; });
    const Image before = render_both("first render");
    twins.both([&](Engine& e) { e.remove_mesh(gone); return 0; });
    render_both("removed, not yet updated");
    twins.both([](Engine& e) { e.update(); return 0; });
    const Image after = render_both("updated");
    EXPECT_FALSE(same_bits(before, after));  // the ball is gone from the image
}

}  // namespace
}  // namespace dynrt::api_test
