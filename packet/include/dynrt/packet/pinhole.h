#pragma once
// The pinhole camera, dynrt's one camera value (dynrt::Camera is this type), and its primary
// rays: the camera convention (README.md, "Camera convention") for one pixel (ray) and for a
// whole tile packet in SIMD (fill_tile), with the same operations in the same order lane by
// lane, so both give the same bits (tests/packet_pinhole_test.cpp checks every pixel). Single
// rays, packets, the reference renderer and the Embree comparison all take their rays from
// here, so the convention's arithmetic exists once.

#include "dynrt/bvh/ray.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"

#include <glm/vec3.hpp>

namespace dynrt::packet {

/// A pinhole camera at `eye` looking at `target`, `up` giving the image's up direction.
struct PinholeCamera {
    glm::vec3 eye{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    /// Vertical field of view in degrees, in (0, 180).
    float fov_y_deg = 45.0f;
};

/// Per lane of a tile packet (lane tile_lane(tile, x, y)), how far its ray's point lies from
/// the pixel's centre, in pixels: a pixel's sample (dynrt/engine/pixel_sampling.h).
struct alignas(64) PixelOffsets {
    alignas(64) float dx[kPacketRays];
    alignas(64) float dy[kPacketRays];
};

/// A camera's precomputed basis for one image size.
class PinholeRays {
public:
    /// Throws std::invalid_argument for a degenerate camera (eye == target, up parallel to the
    /// view direction, fov outside (0, 180)) or an empty image.
    PinholeRays(const PinholeCamera& camera, int width, int height);

    /// The ray of pixel (x, y), y = 0 the top row, one at a time.
    bvh::Ray ray(int x, int y) const;

    /// The ray through image point (x + 1/2, y + 1/2) in pixels: ray(x, y) at whole x and y.
    bvh::Ray ray_at(float x, float y) const;

    /// Fills `packet` with the rays of `tile`, pixel (x, y) in lane tile_lane(tile, x, y), like
    /// fill_tile(tile, ray, packet) but in SIMD. Thread-safe.
    void fill_tile(const Tile& tile, RayPacket& packet) const;
    /// The same through each pixel's point moved by `offsets`: lane k's ray is
    /// ray_at(x + dx[k], y + dy[k]), by the same operations in the same order.
    void fill_tile(const Tile& tile, const PixelOffsets& offsets, RayPacket& packet) const;

private:
    glm::vec3 eye_, fwd_, right_, up_;
    float tan_half_fov_, aspect_;
    int width_, height_;
};

}  // namespace dynrt::packet
