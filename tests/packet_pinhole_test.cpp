// packet::PinholeRays' SIMD tile rays reproduce its single rays bit for bit: every pixel of random and
// extreme cameras (1 and 170 degree fields of view, axis-aligned views, far from the origin),
// in images whose sizes are not multiples of 16, through both the scalar and the SIMD path.

#include "same_bits.h"
#include "dynrt/engine/camera.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"


#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

namespace dynrt::packet {
namespace {

using dynrt::test::same_bits;

bool same_ray(const bvh::Ray& a, const bvh::Ray& b) {
    for (int k = 0; k < 3; ++k) {
        if (!same_bits(a.org[k], b.org[k]) || !same_bits(a.dir[k], b.dir[k])) return false;
    }
    return same_bits(a.tmin, b.tmin) && same_bits(a.tmax, b.tmax);
}

void check(const Camera& camera, int width, int height) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + ", fov " +
                 std::to_string(camera.fov_y_deg));
    const PinholeRays pinhole(camera, width, height);
    const Tiling tiling(width, height);
    auto packet = std::make_unique<RayPacket>();
    for (int i = 0; i < tiling.count(); ++i) {
        const Tile tile = tiling.tile(i);
        pinhole.fill_tile(tile, *packet);
        int active = 0;
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                const bvh::Ray want = pinhole.ray(x, y);
                const int lane = tile_lane(tile, x, y);
                ASSERT_TRUE(packet->active.test(lane));
                ASSERT_TRUE(same_ray(packet->ray(lane), want)) << "SIMD ray of pixel " << x << ", " << y;
                ++active;
            }
        }
        ASSERT_EQ(packet->active.count(), active);
    }
}

TEST(PinholeRays, TilesMatchSingleRaysBitForBit) {
    Camera camera;
    check(camera, 37, 23);
    check(camera, 16, 16);
    check(camera, 1, 1);
    camera.fov_y_deg = 1.0f;
    check(camera, 33, 40);
    camera.fov_y_deg = 170.0f;
    check(camera, 40, 33);
    // Looking down each axis (zero direction components) and from far away.
    for (const glm::vec3& axis : {glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)}) {
        Camera c;
        c.eye = glm::vec3(1500.0f, -980.0f, -700.0f) + 80.0f * axis;
        c.target = glm::vec3(1500.0f, -980.0f, -700.0f);
        c.up = axis.y != 0.0f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
        check(c, 31, 17);
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    std::uniform_real_distribution<float> fov(0.5f, 175.0f);
    for (int i = 0; i < 20; ++i) {
        Camera c;
        c.eye = glm::vec3(u(rng), u(rng), u(rng));
        c.target = glm::vec3(u(rng), u(rng), u(rng));
        c.up = glm::vec3(u(rng), u(rng), u(rng));
        c.fov_y_deg = fov(rng);
        check(c, 7 + i * 5, 50 - i * 2);
    }
}

TEST(PinholeRays, OffsetTilesMatchRayAtBitForBit) {
    // Each lane moved by its own offset (a pixel's sample): the SIMD fill is ray_at lane by
    // lane; zero offsets give ray()'s bits.
    Camera camera;
    camera.eye = {2.0f, 1.0f, 6.0f};
    const PinholeRays pinhole(camera, 45, 29);
    const Tiling tiling(45, 29);
    auto packet = std::make_unique<RayPacket>();
    auto offsets = std::make_unique<PixelOffsets>();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (const bool zero : {true, false}) {
        for (int i = 0; i < tiling.count(); ++i) {
            const Tile tile = tiling.tile(i);
            for (int k = 0; k < kPacketRays; ++k) {
                offsets->dx[k] = zero ? 0.0f : u(rng);
                offsets->dy[k] = zero ? 0.0f : u(rng);
            }
            pinhole.fill_tile(tile, *offsets, *packet);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const int lane = tile_lane(tile, x, y);
                    const bvh::Ray want = zero ? pinhole.ray(x, y)
                                               : pinhole.ray_at(float(x) + offsets->dx[lane], float(y) + offsets->dy[lane]);
                    ASSERT_TRUE(same_ray(packet->ray(lane), want)) << "pixel " << x << ", " << y;
                }
            }
        }
    }
}

}  // namespace
}  // namespace dynrt::packet
