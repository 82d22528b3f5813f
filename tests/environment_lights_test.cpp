// The environment as lights (dynrt/engine/environment_lights.h, median cut): the suns carry the
// map's light in the documented units and point where it comes from; and a scene lit by them
// alone matches the exact reference (which lights with the same suns) for both tracers, and is
// lit: turning them off leaves it dark.

#include "reference_shot.h"
#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/environment_lights.h"
#include "dynrt/engine/environment_map.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace dynrt::reference {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

/// The sum over `lights` of colour times max(0, cos) toward `normal`: what a white Phong
/// surface facing `normal` shows of their diffuse light, unshadowed.
glm::vec3 diffuse_from(const std::vector<PointLight>& lights, glm::vec3 normal) {
    glm::vec3 sum(0.0f);
    for (const PointLight& light : lights) sum += light.intensity * light.color * std::max(0.0f, glm::dot(-light.direction, normal));
    return sum;
}

TEST(EnvironmentLights, AUniformSkyLightsAsItsIntegralSays) {
    // Uniform radiance L: the suns' colours sum to (1 / pi) * L * 4 pi = 4 L, and a surface
    // facing any way gets (1 / pi) * integral of L cos over its hemisphere = L.
    const glm::vec3 radiance(0.5f, 0.25f, 1.0f);
    const EnvironmentMap sky(64, 32, std::vector<glm::vec3>(64 * 32, radiance), 1.0f, "uniform");
    const std::vector<PointLight> lights = environment_lights(sky, 64);
    ASSERT_EQ(lights.size(), 64u);
    glm::vec3 total(0.0f);
    for (const PointLight& light : lights) {
        EXPECT_EQ(light.kind, PointLight::Kind::directional);
        EXPECT_NEAR(glm::length(light.direction), 1.0f, 1e-5f);
        total += light.color;
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(total[c], 4.0f * radiance[c], 0.01f * 4.0f * radiance[c]);
    for (const glm::vec3 n : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, 1, -1))}) {
        const glm::vec3 lit = diffuse_from(lights, n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(lit[c], radiance[c], 0.06f * radiance[c]) << n.x << "," << n.y << "," << n.z;
    }
}

TEST(EnvironmentLights, ABrightSpotBecomesOneSunPointingFromIt) {
    // A dim sky with one bright texel: one of the suns carries almost all the light, and it
    // shines from that texel's direction.
    const int w = 32, h = 16;
    std::vector<glm::vec3> texels(std::size_t(w * h), glm::vec3(0.001f));
    const int sx = 20, sy = 4;
    texels[std::size_t(sy * w + sx)] = glm::vec3(5000.0f);
    const EnvironmentMap sky(w, h, texels, 1.0f, "sun");
    const std::vector<PointLight> lights = environment_lights(sky, 8);
    ASSERT_FALSE(lights.empty());
    const PointLight* brightest = &lights[0];
    float total = 0.0f;
    for (const PointLight& light : lights) {
        total += light.color.x;
        if (light.color.x > brightest->color.x) brightest = &light;
    }
    EXPECT_GT(brightest->color.x, 0.99f * total);
    // The texel's centre direction, as environment_map.h maps it.
    const float theta = (float(sy) + 0.5f) / float(h) * kPi, phi = ((float(sx) + 0.5f) / float(w) - 0.5f) * 2.0f * kPi;
    const glm::vec3 toward(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
    EXPECT_GT(glm::dot(-brightest->direction, toward), std::cos(0.02f));
    EXPECT_EQ(sky.radiance(toward), glm::vec3(5000.0f));
}

TEST(EnvironmentLights, CountsOutOfRangeAreRefusedAndTinyMapsGiveFewerLights) {
    const EnvironmentMap two(2, 1, std::vector<glm::vec3>(2, glm::vec3(1.0f)), 1.0f, "two");
    EXPECT_THROW(environment_lights(two, 0), std::invalid_argument);
    EXPECT_THROW(environment_lights(two, kEnvironmentLightsMax + 1), std::invalid_argument);
    EXPECT_EQ(environment_lights(two, 16).size(), 2u);
    // A black sky lights nothing: no lights at all.
    const EnvironmentMap black(8, 4, std::vector<glm::vec3>(32, glm::vec3(0.0f)), 1.0f, "black");
    EXPECT_TRUE(environment_lights(black, 16).empty());
}

/// A sky brighter on one side, so that the suns' shadows and shading have a direction.
std::shared_ptr<const EnvironmentMap> lopsided_sky() {
    const int w = 48, h = 24;
    std::vector<glm::vec3> texels;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float up = std::max(0.0f, 1.0f - float(y) / float(h / 2));
            const float side = float(x) / float(w);
            texels.emplace_back(0.2f + 1.5f * up * side, 0.3f + up, 0.6f + 0.4f * up);
        }
    }
    return std::make_shared<const EnvironmentMap>(w, h, std::move(texels), 1.0f, "lopsided");
}

TEST(EnvironmentLights, AScenelitByItsSkyMatchesTheReference) {
    const Scene scene = load_scene("plane:6@0,-1,0,4#c0c0c0+sphere:800@-0.6,-0.4,0,0.6#e04020+sphere:500@0.9,-0.5,0.3,0.45#2050e0");
    Camera camera;
    camera.eye = glm::vec3(0.0f, 1.2f, 3.5f);
    camera.target = glm::vec3(0.0f, -0.5f, 0.0f);
    camera.fov_y_deg = 55.0f;
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    options.environment = lopsided_sky();
    options.environment_lights = 24;
    const ReferenceShading shading = shading_from(scene, options);
    // The reference is lit by the suns alone (the default light is left out).
    ASSERT_EQ(shading.lights.size(), 24u);
    const ReferenceFrame ref = test::reference_shot(scene, camera, options, &shading);
    ComparisonOptions tolerance;
    tolerance.color_abs_tol = 1e-3;
    for (const Tracer t : {Tracer::packet, Tracer::single}) {
        SCOPED_TRACE(t == Tracer::packet ? "packet" : "single");
        options.tracer = t;
        const ImageComparison cmp = compare_images(test::renderer_shot(scene, camera, options), ref, tolerance);
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.color_checked, 64 * 48 / 2);
    }
    // Without them (and without another light) the floor shows only its ambient term.
    RenderOptions unlit = options;
    unlit.environment_lights = 0;
    unlit.lights = {PointLight{glm::vec3(0.0f, 5.0f, 0.0f), 0.0f}};
    const RenderedFrame with = test::renderer_shot(scene, camera, options);
    const RenderedFrame without = test::renderer_shot(scene, camera, unlit);
    double brighter = 0.0;
    for (std::size_t p = 0; p < with.color.size(); ++p) brighter += with.color[p].y - without.color[p].y;
    EXPECT_GT(brighter / double(with.color.size()), 0.2);
}

}  // namespace
}  // namespace dynrt::reference
