// The renderer's two tracers give identical frames: every output buffer (colour, depth,
// object, prim, normal) bit for bit and the same ray counts, over scenes, cameras, lights
// (several, and behind surfaces), image sizes that are not multiples of 16, culling choices and
// both packet lane widths.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/simd.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dynrt {
namespace {

template <typename T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

/// The first pixel where two frames differ, or -1.
std::ptrdiff_t first_difference(const RenderedFrame& a, const RenderedFrame& b) {
    for (std::size_t p = 0; p < a.color.size(); ++p) {
        if (std::memcmp(&a.color[p], &b.color[p], sizeof(glm::vec3)) != 0 ||
            std::bit_cast<std::uint32_t>(a.depth[p]) != std::bit_cast<std::uint32_t>(b.depth[p]) ||
            a.object[p] != b.object[p] || a.prim[p] != b.prim[p] ||
            std::memcmp(&a.normal[p], &b.normal[p], sizeof(glm::vec3)) != 0) {
            return std::ptrdiff_t(p);
        }
    }
    return -1;
}

struct Case {
    const char* label;
    std::string spec;  ///< empty: the bundled scene
};

class PacketRenderer : public ::testing::TestWithParam<Case> {};

TEST_P(PacketRenderer, SingleAndPacketTracersRenderIdenticalFrames) {
    const Case& param = GetParam();
    const Scene scene = load_scene(param.spec.empty() ? default_scene_path().string() : param.spec);
    const bvh::Aabb bounds = scene_bounds(scene);
    const glm::vec3 c = bounds.center();
    const float r = 0.5f * glm::length(bounds.extent());

    std::vector<Camera> cameras = {default_camera(bounds)};
    Camera inside;
    inside.eye = c + 0.05f * r * glm::vec3(1.0f, 0.6f, 0.3f);
    inside.target = inside.eye + glm::vec3(1.0f, 0.25f, -0.4f);
    inside.fov_y_deg = 170.0f;
    cameras.push_back(inside);
    Camera along;
    along.eye = c + 2.0f * r * glm::vec3(0, 0, 1);
    along.target = c;
    cameras.push_back(along);

    // The scene's own lights (or the default one), then two lights, one of them low.
    const std::vector<std::vector<PointLight>> light_sets = {
        {}, {PointLight{c + glm::vec3(0, 3 * r, 0), 0.7f}, PointLight{c + glm::vec3(3 * r, -0.2f * r, r), 0.5f}}};
    const int sizes[][2] = {{37, 23}, {48, 32}, {1, 1}};

    int k = 0;
    for (const Camera& camera : cameras) {
        for (const std::vector<PointLight>& lights : light_sets) {
            const int* size = sizes[k % 3];
            RenderOptions options;
            options.width = size[0];
            options.height = size[1];
            options.lights = lights;
            options.tracer = Tracer::single;
            RenderedFrame single;
            Renderer(options).render(scene, camera, 0, single);

            options.tracer = Tracer::packet;
            options.packet.lanes = k % 2 == 0 ? packet::simd::kNativeLanes : 1;
            options.packet.culling = k % 3 == 2 ? packet::PacketCulling::none() : packet::PacketCulling{};
            options.count_packet_work = k % 2 == 1;
            RenderedFrame packed;
            Renderer(options).render(scene, camera, 0, packed);
            ++k;

            SCOPED_TRACE("camera " + std::to_string(k) + ", " + std::to_string(lights.size()) +
                         " lights, " + std::to_string(size[0]) + "x" + std::to_string(size[1]));
            ASSERT_EQ(packed.width, single.width);
            ASSERT_EQ(packed.height, single.height);
            EXPECT_EQ(first_difference(single, packed), -1);
            EXPECT_TRUE(same_bytes(single.depth, packed.depth));
            EXPECT_EQ(packed.stats.primary_rays, single.stats.primary_rays);
            EXPECT_EQ(packed.stats.shadow_rays, single.stats.shadow_rays);
            EXPECT_EQ(single.stats.ray_triangle_tests, 0u);
            if (options.count_packet_work && packed.stats.shadow_rays > 0) {
                EXPECT_GT(packed.stats.ray_triangle_tests, 0u);
            } else if (!options.count_packet_work) {
                EXPECT_EQ(packed.stats.ray_triangle_tests, 0u);
            }
        }
    }
}

const std::string kComposition =
    "plane:8@0,-1,0,4#808080+sphere:600@-0.8,-0.4,0.3,0.6#e04020+sphere:300@1.2,-0.5,-0.6,0.5"
    "+sphere:200@0.1,0.9,0.2,0.35#f0d020+soup:600@-0.6,-1,-2,1.4#40c060";

INSTANTIATE_TEST_SUITE_P(Scenes, PacketRenderer,
                         ::testing::Values(Case{"composition", kComposition},
                                           Case{"soup", "soup:3000"},
                                           Case{"defaultScene", ""}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             return std::string(info.param.label);
                         });

TEST(PacketRenderer, PacketTracerIsTheDefault) {
    EXPECT_EQ(RenderOptions{}.tracer, Tracer::packet);
    EXPECT_EQ(RenderOptions{}.packet.culling, packet::PacketCulling{});
    EXPECT_EQ(RenderOptions{}.packet.lanes, packet::simd::kNativeLanes);
}

}  // namespace
}  // namespace dynrt
