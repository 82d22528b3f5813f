#pragma once
// Primary rays of a pinhole camera: the camera convention (README.md, "Camera convention")
// for one pixel (ray; dynrt::CameraRays checks a camera and then delegates to it, so the
// convention's arithmetic exists once) and for a whole tile packet in SIMD (fill_tile), with
// the same operations in the same order lane by lane, so both give the same bits
// (tests/packet_pinhole_test.cpp checks every pixel).

#include "dynrt/bvh/ray.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"

#include <glm/vec3.hpp>

namespace dynrt::packet {

class PinholeRays {
public:
    /// The basis of a camera at `eye` looking at `target` with `up` and a vertical field of
    /// view of `fov_y_deg` degrees, for a width x height image. Preconditions as for
    /// dynrt::CameraRays, which validates them (this constructor does not).
    PinholeRays(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float fov_y_deg, int width,
                int height);

    /// The ray of pixel (x, y), y = 0 the top row, one at a time.
    bvh::Ray ray(int x, int y) const;

    /// Fills `packet` with the rays of `tile`, pixel (x, y) in lane tile_lane(tile, x, y), like
    /// fill_tile(tile, ray, packet) but in SIMD. Thread-safe.
    void fill_tile(const Tile& tile, RayPacket& packet) const;

private:
    glm::vec3 eye_, fwd_, right_, up_;
    float tan_half_fov_, aspect_;
    int width_, height_;
};

}  // namespace dynrt::packet
