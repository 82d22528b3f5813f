#include "dynrt/engine/camera.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>

namespace dynrt {
namespace {

TEST(Camera, DefaultFramesTheBoundsFromTheDocumentedDirection) {
    bvh::Aabb box;
    box.extend(glm::vec3(-1.0f, 0.0f, 2.0f));
    box.extend(glm::vec3(3.0f, 2.0f, 6.0f));
    const Camera camera = default_camera(box);
    const glm::dvec3 c(1.0, 1.0, 4.0);
    const double r = 0.5 * std::sqrt(16.0 + 4.0 + 16.0);
    const glm::dvec3 eye = c + 2.5 * r * glm::normalize(glm::dvec3(0.6, 0.5, 1.0));
    EXPECT_NEAR(camera.eye.x, eye.x, 1e-5);
    EXPECT_NEAR(camera.eye.y, eye.y, 1e-5);
    EXPECT_NEAR(camera.eye.z, eye.z, 1e-5);
    EXPECT_EQ(camera.target, glm::vec3(c));
    EXPECT_EQ(camera.up, glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(camera.fov_y_deg, 45.0f);
}

/// A scene collapsed to a point (a zero-scale node) or without triangles still gets a camera
/// whose eye is not its target, so it renders instead of failing with a misleading error.
TEST(Camera, DefaultFramesAPointOrAnEmptySceneAtUnitRadius) {
    bvh::Aabb point;
    point.extend(glm::vec3(2.0f, 3.0f, 4.0f));
    const Camera at_point = default_camera(point);
    EXPECT_EQ(at_point.target, glm::vec3(2.0f, 3.0f, 4.0f));
    EXPECT_NEAR(glm::length(at_point.eye - at_point.target), 2.5f, 1e-5f);
    const Camera empty = default_camera(bvh::Aabb{});
    EXPECT_EQ(empty.target, glm::vec3(0.0f));
    EXPECT_NEAR(glm::length(empty.eye - empty.target), 2.5f, 1e-5f);
    EXPECT_NO_THROW(packet::PinholeRays(at_point, 16, 16));
    EXPECT_NO_THROW(packet::PinholeRays(empty, 16, 16));
}

TEST(Camera, RaysFollowTheDocumentedConvention) {
    Camera camera;
    camera.eye = glm::vec3(1.0f, 2.0f, 3.0f);
    camera.target = glm::vec3(4.0f, 0.0f, -1.0f);
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.fov_y_deg = 60.0f;
    const int w = 37, h = 23;
    const packet::PinholeRays rays(camera, w, h);
    // The convention evaluated independently in double.
    const glm::dvec3 fwd = glm::normalize(glm::dvec3(camera.target - camera.eye));
    const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, fwd);
    const double t = std::tan(60.0 * 3.14159265358979323846 / 360.0);
    for (int y : {0, 11, 22}) {
        for (int x : {0, 18, 36}) {
            const glm::dvec3 d = glm::normalize(
                fwd + ((2.0 * (x + 0.5) / w - 1.0) * t * w / h) * right +
                ((1.0 - 2.0 * (y + 0.5) / h) * t) * up);
            const bvh::Ray ray = rays.ray(x, y);
            EXPECT_EQ(ray.org, camera.eye);
            EXPECT_NEAR(ray.dir.x, d.x, 1e-6) << x << "," << y;
            EXPECT_NEAR(ray.dir.y, d.y, 1e-6) << x << "," << y;
            EXPECT_NEAR(ray.dir.z, d.z, 1e-6) << x << "," << y;
        }
    }
    // y = 0 is the top row: its rays point more "up" than the bottom row's.
    EXPECT_GT(glm::dot(glm::dvec3(rays.ray(18, 0).dir), up), 0.0);
    EXPECT_LT(glm::dot(glm::dvec3(rays.ray(18, 22).dir), up), 0.0);
}

TEST(Camera, ParsesAnySubsetOfKeys) {
    const Camera base;
    const Camera c = parse_camera("fov=30,target=1,2,3", base);
    EXPECT_EQ(c.fov_y_deg, 30.0f);
    EXPECT_EQ(c.target, glm::vec3(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(c.eye, base.eye);
    const Camera d = parse_camera("eye=-1.5,0,1e3,up=0,0,1", base);
    EXPECT_EQ(d.eye, glm::vec3(-1.5f, 0.0f, 1000.0f));
    EXPECT_EQ(d.up, glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(Camera, RejectsMalformedSpecs) {
    const Camera base;
    for (const char* bad : {"eye=1,2", "eye=1,2,x", "fov=0", "fov=180", "fov=nan", "zoom=2",
                            "1,2,3", "eye=1,2,3,", "target=inf,0,0", ""}) {
        EXPECT_THROW(parse_camera(bad, base), std::invalid_argument) << bad;
    }
}

TEST(Camera, RejectsDegenerateViews) {
    Camera same;
    same.target = same.eye;
    EXPECT_THROW(packet::PinholeRays(same, 4, 4), std::invalid_argument);
    Camera parallel;
    parallel.eye = glm::vec3(0.0f, 5.0f, 0.0f);
    parallel.target = glm::vec3(0.0f);
    EXPECT_THROW(packet::PinholeRays(parallel, 4, 4), std::invalid_argument);
    EXPECT_THROW(packet::PinholeRays(Camera{}, 0, 4), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt
