// The approximate mode (RenderOptions::adaptive_tolerance): off it changes nothing; on, it
// interpolates part of the image, never loses an object that only a cell's interior sees, and
// its error against the exact frame shrinks with the tolerance.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace dynrt {
namespace {

RenderedFrame render_with(const Scene& scene, const Camera& camera, float tolerance, int width,
                          int height) {
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.adaptive_tolerance = tolerance;
    // Adaptive sampling interpolates the Phong image; a frame with reflection or refraction
    // rays (the bundled scene's gold is a smooth metal) traces every pixel instead
    // (secondary_rays_test.cpp).
    options.secondary.max_depth = 0;
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    return frame;
}

double colour_rmse(const RenderedFrame& a, const RenderedFrame& b) {
    double sum = 0.0;
    for (std::size_t p = 0; p < a.color.size(); ++p) {
        const glm::dvec3 d = glm::dvec3(a.color[p]) - glm::dvec3(b.color[p]);
        sum += glm::dot(d, d);
    }
    return std::sqrt(sum / (3.0 * double(a.color.size())));
}

TEST(AdaptiveSampling, ZeroToleranceIsTheExactPath) {
    const Scene scene = load_scene(default_scene_path().string());
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = 72;
    options.height = 40;
    options.secondary.max_depth = 0;  // as render_with
    Renderer exact_renderer(options);
    RenderedFrame exact, zero;
    exact_renderer.render(scene, camera, 0, exact);
    const RenderedFrame same = render_with(scene, camera, 0.0f, 72, 40);
    ASSERT_EQ(exact.color.size(), same.color.size());
    EXPECT_EQ(std::memcmp(exact.color.data(), same.color.data(),
                          exact.color.size() * sizeof(glm::vec3)), 0);
    EXPECT_EQ(exact.object, same.object);
    EXPECT_EQ(same.stats.interpolated_pixels, 0u);
    EXPECT_EQ(same.stats.primary_rays, 72u * 40u);
}

TEST(AdaptiveSampling, ErrorShrinksWithTheTolerance) {
    const Scene scene = load_scene(default_scene_path().string());
    const Camera camera = default_camera(scene_bounds(scene));
    const int w = 200, h = 152;  // not multiples of 16: clipped edge tiles too
    const RenderedFrame exact = render_with(scene, camera, 0.0f, w, h);
    double previous_rmse = 0.0;
    std::size_t previous_interpolated = 0;
    for (const float tolerance : {1e-4f, 0.01f, 0.1f, 0.5f}) {
        const RenderedFrame approx = render_with(scene, camera, tolerance, w, h);
        const double rmse = colour_rmse(approx, exact);
        const std::size_t interpolated = approx.stats.interpolated_pixels;
        EXPECT_GT(interpolated, 0u) << tolerance;
        // Every pixel is traced or interpolated (a traced tile traces its samples again).
        EXPECT_GE(approx.stats.primary_rays + interpolated, std::size_t(w) * std::size_t(h))
            << tolerance;
        EXPECT_LT(approx.stats.primary_rays, std::size_t(w) * std::size_t(h)) << tolerance;
        // A looser tolerance interpolates at least as much and errs at least as much.
        EXPECT_GE(interpolated, previous_interpolated) << tolerance;
        EXPECT_GE(rmse, previous_rmse) << tolerance;
        previous_rmse = rmse;
        previous_interpolated = interpolated;
        // Interpolated pixels still see the object the exact frame sees almost everywhere.
        std::size_t object_differs = 0;
        for (std::size_t p = 0; p < exact.object.size(); ++p) {
            object_differs += exact.object[p] != approx.object[p] ? 1 : 0;
        }
        EXPECT_LT(double(object_differs), 0.01 * double(w * h)) << tolerance;
    }
    EXPECT_GT(previous_rmse, 0.0);  // the mode does approximate
}

TEST(AdaptiveSampling, ObjectsBetweenTheSamplesAreNeverLost) {
    // Small spheres in front of a big far one (object 0, filling most of the view), each a
    // few pixels wide, so that most of them fall between the samples of the 4-pixel grid: the
    // cells around them must be traced, on the backdrop and against the background alike.
    Scene scene = load_scene(
        "sphere:2000@0,0,-30,12#808080+sphere:80@0.3,0.2,0,0.05#ff0000+sphere:80@-0.61,-0.33,0,"
        "0.04+sphere:80@0.9,-0.7,0,0.05+sphere:80@-1.6,1.5,0,0.03");
    Camera camera;
    camera.eye = glm::vec3(0.0f, 0.0f, 5.0f);
    camera.target = glm::vec3(0.0f, 0.0f, 0.0f);
    camera.fov_y_deg = 40.0f;
    const RenderedFrame exact = render_with(scene, camera, 0.0f, 160, 160);
    const RenderedFrame approx = render_with(scene, camera, 1.0f, 160, 160);
    std::size_t sphere_pixels = 0;
    for (std::size_t p = 0; p < exact.object.size(); ++p) {
        if (exact.object[p] <= 0) continue;  // the wall or a miss
        ++sphere_pixels;
        EXPECT_EQ(approx.object[p], exact.object[p]) << "pixel " << p;
    }
    EXPECT_GT(sphere_pixels, 0u);
    EXPECT_GT(approx.stats.interpolated_pixels, 0u);
}

TEST(AdaptiveSampling, BadTolerancesAreRejected) {
    RenderOptions options;
    options.adaptive_tolerance = -0.1f;
    EXPECT_THROW(Renderer{options}, std::invalid_argument);
    options.adaptive_tolerance = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(Renderer{options}, std::invalid_argument);
    options.adaptive_tolerance = std::numeric_limits<float>::infinity();
    EXPECT_THROW(Renderer{options}, std::invalid_argument);
    options.adaptive_tolerance = 0.1f;
    options.tracer = Tracer::single;
    EXPECT_THROW(Renderer{options}, std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
