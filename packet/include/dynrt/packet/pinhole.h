#pragma once
// Primary rays of a pinhole camera, generated a whole tile packet at a time in SIMD. They are
// exactly the rays of the camera convention (README.md, "Camera convention") as
// dynrt::CameraRays computes them in engine/src/camera.cpp, bit for bit: the same operations in
// the same order, lane by lane (tests/packet_pinhole_test.cpp checks every pixel against
// CameraRays). The packet module cannot see the engine's camera type, hence the copy of the
// convention here; keep the two in step.

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
