// Environment maps (dynrt/engine/environment_map.h): the lookup's mapping from directions to
// an equirectangular image, reading files (and refusing bad ones, naming them), and renders
// where camera rays that miss and mirror reflections see it, against the exact reference for
// both tracers; the reference looks the environment up at its own exact directions, so a
// renderer that showed the background to its reflections would fail.

#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/environment_map.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/packet/pinhole.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

namespace dynrt::reference {
namespace {

/// A map whose texel (i, j) is (i / w, j / h, 0.25): its colour says where it was looked up.
std::shared_ptr<const EnvironmentMap> coordinate_map(int w = 16, int h = 8) {
    std::vector<glm::vec3> texels;
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) texels.emplace_back(float(i) / float(w), float(j) / float(h), 0.25f);
    }
    return std::make_shared<const EnvironmentMap>(w, h, std::move(texels), 1.0f, "coordinates");
}

TEST(EnvironmentMap, MapsDirectionsAsDocumented) {
    // A constant map is the constant, times the scale, in every direction.
    const EnvironmentMap flat(3, 2, std::vector<glm::vec3>(6, glm::vec3(0.5f, 1.0f, 2.0f)), 2.0f, "flat");
    for (const glm::vec3 d : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(1, 0.3f, -2), glm::vec3(-1, 0, 0)}) {
        EXPECT_EQ(flat.radiance(d), glm::vec3(1.0f, 2.0f, 4.0f));
    }
    const auto map = coordinate_map();
    // -Z is the centre: u = 1/2, v = 1/2 (between texel centres 7.5 and 8.5 across: i = 7.5).
    const glm::vec3 forward = map->radiance(glm::vec3(0, 0, -1));
    EXPECT_NEAR(forward.x, 7.5f / 16.0f, 1e-5f);
    EXPECT_NEAR(forward.y, 3.5f / 8.0f, 1e-5f);
    // +X is three quarters across, -X one quarter; up is the top row (clamped), down the bottom.
    EXPECT_NEAR(map->radiance(glm::vec3(1, 0, 0)).x, 11.5f / 16.0f, 1e-5f);
    EXPECT_NEAR(map->radiance(glm::vec3(-1, 0, 0)).x, 3.5f / 16.0f, 1e-5f);
    EXPECT_NEAR(map->radiance(glm::vec3(0, 1, 0)).y, 0.0f, 1e-5f);
    EXPECT_NEAR(map->radiance(glm::vec3(0, -1, 0)).y, 7.0f / 8.0f, 1e-5f);
    // Across the seam behind (+Z) it wraps: both sides blend the first and last columns.
    const glm::vec3 left = map->radiance(glm::vec3(-1e-4f, 0, 1)), right = map->radiance(glm::vec3(1e-4f, 0, 1));
    EXPECT_NEAR(left.x, right.x, 1e-3f);
    EXPECT_GT(left.x, 0.4f);  // half of the last column's 15/16 and the first's 0
    EXPECT_LT(left.x, 0.55f);
}

class EnvironmentFiles : public ::testing::Test {
protected:
    std::filesystem::path path(const std::string& name) const {
        return std::filesystem::path(::testing::TempDir()) / ("dynrt_env_" + std::to_string(::getpid()) + "_" + name);
    }
    void write(const std::filesystem::path& file, int w, int h, const std::vector<float>& rgb) const {
        std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file.string());
        ASSERT_TRUE(out);
        const OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
        ASSERT_TRUE(out->open(file.string(), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()));
        out->close();
    }
};

TEST_F(EnvironmentFiles, ReadsAnExrAndRefusesBadFilesNamingThem) {
    const std::filesystem::path exr = path("sky.exr");
    std::vector<float> rgb;
    for (int i = 0; i < 4 * 2; ++i) rgb.insert(rgb.end(), {0.1f * float(i), 2.0f, 0.0f});
    write(exr, 4, 2, rgb);
    const auto map = EnvironmentMap::read(exr, 0.5f);
    EXPECT_EQ(map->width(), 4);
    EXPECT_EQ(map->height(), 2);
    EXPECT_FLOAT_EQ(map->radiance(glm::vec3(0, 1, 0)).y, 1.0f);  // 2 times the scale

    const auto refused = [](const std::filesystem::path& file, const std::string& fragment, float scale = 1.0f) {
        try {
            EnvironmentMap::read(file, scale);
            ADD_FAILURE() << file << " accepted";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("environment map '" + file.string() + "'"), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    refused(path("missing.exr"), "no such file");
    refused(exr, "scale", -1.0f);
    const std::filesystem::path bad = path("bad.exr");
    rgb[4] = std::numeric_limits<float>::quiet_NaN();
    write(bad, 4, 2, rgb);
    refused(bad, "texel 1,0 is not finite");
    const std::filesystem::path text = path("notes.hdr");
    { std::ofstream(text) << "not an image"; }
    refused(text, "");
}

/// A mirror ball and a grey ball over a floor under a sky whose colour changes with the
/// direction everywhere, so that a reflection shown with the wrong direction, or the
/// background instead, is seen.
struct SkyShot {
    Scene scene = load_scene("plane:6@0,-1,0,4#a0a0a0+sphere:800@-0.6,-0.3,0,0.6#ffffff+sphere:500@0.9,-0.5,0.3,0.45#808080");
    Camera camera;
    RenderOptions options;

    SkyShot() {
        Material& mirror = scene.materials[scene.objects[1].material];
        mirror.diffuse = glm::vec3(0.05f);
        mirror.reflectance = glm::vec3(0.9f);
        camera.eye = glm::vec3(0.0f, 0.6f, 3.2f);
        camera.target = glm::vec3(0.0f, -0.2f, 0.0f);
        camera.fov_y_deg = 60.0f;
        options.width = 64;
        options.height = 48;
        options.environment = coordinate_map(64, 32);
    }
};

TEST(EnvironmentRender, MissesAndReflectionsSeeItAndMatchTheReference) {
    const SkyShot shot;
    anim::PosedScene posed;
    anim::pose_scene(shot.scene, shot.options.pose, 0, posed);
    const ReferenceTracer tracer(shot.scene, posed);
    const ReferenceFrame ref = render_reference(shot.scene, tracer, shot.camera, shot.options.width,
                                                shot.options.height, shading_from(shot.scene, shot.options));
    ComparisonOptions tolerance;
    tolerance.color_abs_tol = 1e-3;
    for (const Tracer t : {Tracer::packet, Tracer::single}) {
        SCOPED_TRACE(t == Tracer::packet ? "packet" : "single");
        RenderOptions options = shot.options;
        options.tracer = t;
        Renderer renderer(options);
        RenderedFrame frame;
        renderer.render(shot.scene, shot.camera, 0, frame);
        const ImageComparison cmp = compare_images(frame, ref, tolerance);
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.color_checked, 64 * 48 / 2);
        // A miss shows the map along its own ray.
        const packet::PinholeRays rays(shot.camera, frame.width, frame.height);
        int misses = 0;
        for (int y = 0; y < frame.height; ++y) {
            for (int x = 0; x < frame.width; ++x) {
                const std::size_t p = std::size_t(y) * std::size_t(frame.width) + std::size_t(x);
                if (frame.object[p] >= 0) continue;
                ++misses;
                const glm::vec3 want = shot.options.environment->radiance(rays.ray(x, y).dir);
                EXPECT_LT(glm::length(frame.color[p] - want), 1e-5f) << x << "," << y;
            }
        }
        EXPECT_GT(misses, 200);
    }
    // Without the map the mirror shows the background: many of its pixels differ.
    RenderOptions plain = shot.options;
    plain.environment = nullptr;
    Renderer a(shot.options), b(plain);
    RenderedFrame with, without;
    a.render(shot.scene, shot.camera, 0, with);
    b.render(shot.scene, shot.camera, 0, without);
    int mirror_changed = 0;
    for (std::size_t p = 0; p < with.color.size(); ++p) {
        mirror_changed += with.object[p] == 1 && glm::length(with.color[p] - without.color[p]) > 0.05f;
    }
    EXPECT_GT(mirror_changed, 100);
}

}  // namespace
}  // namespace dynrt::reference
