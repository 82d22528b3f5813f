// Pinhole primary rays, one at a time and in SIMD, operation for operation the same (glm's
// normalize is v * (1 / sqrt(dot(v, v))), its dot (x*x + y*y) + z*z).

#include "dynrt/packet/pinhole.h"

#include "dynrt/packet/simd.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace dynrt::packet {

namespace {

/// `camera`, once it has passed PinholeRays' checks; throws std::invalid_argument otherwise.
const PinholeCamera& checked(const PinholeCamera& camera, int width, int height) {
    if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
    if (!(camera.fov_y_deg > 0.0f && camera.fov_y_deg < 180.0f)) {
        throw std::invalid_argument("camera fov must be in (0, 180) degrees");
    }
    const auto finite = [](const glm::vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    // Before the other checks: a NaN eye would otherwise read as "eye equals target".
    if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up)) {
        throw std::invalid_argument("camera eye, target and up must be finite");
    }
    const glm::vec3 view = camera.target - camera.eye;
    if (!(glm::length(view) > 0.0f)) throw std::invalid_argument("camera eye equals target");
    const glm::vec3 side = glm::cross(glm::normalize(view), camera.up);
    if (!(glm::length(side) > 1e-6f * glm::length(camera.up))) {
        throw std::invalid_argument("camera up is parallel to the view direction");
    }
    return camera;
}

}  // namespace

PinholeRays::PinholeRays(const PinholeCamera& camera, int width, int height)
    : eye_(checked(camera, width, height).eye), width_(width), height_(height) {
    fwd_ = glm::normalize(camera.target - camera.eye);
    right_ = glm::normalize(glm::cross(fwd_, camera.up));
    up_ = glm::cross(right_, fwd_);
    tan_half_fov_ = std::tan(glm::radians(camera.fov_y_deg) * 0.5f);
    aspect_ = float(width) / float(height);
}

bvh::Ray PinholeRays::ray_at(float x, float y) const {
    const float sx = (2.0f * (x + 0.5f) / float(width_) - 1.0f) * tan_half_fov_ * aspect_;
    const float sy = (1.0f - 2.0f * (y + 0.5f) / float(height_)) * tan_half_fov_;
    bvh::Ray ray;
    ray.org = eye_;
    ray.dir = glm::normalize(fwd_ + sx * right_ + sy * up_);
    return ray;
}

bvh::Ray PinholeRays::ray(int x, int y) const {
    const float sx = (2.0f * (float(x) + 0.5f) / float(width_) - 1.0f) * tan_half_fov_ * aspect_;
    const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height_)) * tan_half_fov_;
    bvh::Ray ray;
    ray.org = eye_;
    ray.dir = glm::normalize(fwd_ + sx * right_ + sy * up_);
    return ray;
}

namespace {

template <int W>
void fill_rows(const PinholeRays& camera, const glm::vec3& eye, const glm::vec3& fwd,
               const glm::vec3& right, const glm::vec3& up, float tan_half_fov, float aspect,
               int width, int height, const Tile& tile, const PixelOffsets* offsets, RayPacket& packet) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    static_assert(kTileSize % W == 0 || W > kTileSize);
    if constexpr (W > kTileSize) {
        fill_tile(tile, [&](int x, int y) {
            if (offsets == nullptr) return camera.ray(x, y);
            const int lane = tile_lane(tile, x, y);
            return camera.ray_at(float(x) + offsets->dx[lane], float(y) + offsets->dy[lane]);
        }, packet);
    } else {
        // Each lane's ray through its pixel's centre, moved by its offset when there are
        // offsets (ray_at's operations, lane by lane: at whole pixels, ray()'s bits).
        packet.clear();
        F lane_x;
        for (int i = 0; i < W; ++i) lane_x[i] = float(i);
        const float inf = std::numeric_limits<float>::infinity();
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x0 = tile.x0; x0 < tile.x0 + kTileSize; x0 += W) {
                // Lanes past the image edge compute a ray too (a harmless one) but stay inactive.
                const int lane = tile_lane(tile, x0, y);
                F x = L::splat(float(x0)) + lane_x;
                F yy = L::splat(float(y));
                if (offsets != nullptr) {
                    x = x + L::load(offsets->dx + lane);
                    yy = yy + L::load(offsets->dy + lane);
                }
                const F sx = (L::splat(2.0f) * (x + L::splat(0.5f)) / L::splat(float(width)) -
                              L::splat(1.0f)) *
                             L::splat(tan_half_fov) * L::splat(aspect);
                const F sy = (L::splat(1.0f) - L::splat(2.0f) * (yy + L::splat(0.5f)) / L::splat(float(height))) *
                             L::splat(tan_half_fov);
                const F dx = L::splat(fwd.x) + sx * L::splat(right.x) + sy * L::splat(up.x);
                const F dy = L::splat(fwd.y) + sx * L::splat(right.y) + sy * L::splat(up.y);
                const F dz = L::splat(fwd.z) + sx * L::splat(right.z) + sy * L::splat(up.z);
                const F inv_len = L::splat(1.0f) / L::sqrt(dx * dx + dy * dy + dz * dz);
                L::store(packet.org_x + lane, L::splat(eye.x));
                L::store(packet.org_y + lane, L::splat(eye.y));
                L::store(packet.org_z + lane, L::splat(eye.z));
                L::store(packet.dir_x + lane, dx * inv_len);
                L::store(packet.dir_y + lane, dy * inv_len);
                L::store(packet.dir_z + lane, dz * inv_len);
                L::store(packet.tmin + lane, L::splat(0.0f));
                L::store(packet.tmax + lane, L::splat(inf));
            }
            // The row's pixels as one run of bits (16 lanes per row, never across a word).
            const int row_lane = tile_lane(tile, tile.x0, y);
            packet.active.words[row_lane >> 6] |= ((std::uint64_t{1} << (tile.x1 - tile.x0)) - 1)
                                                 << (row_lane & 63);
        }
    }
}

}  // namespace

void PinholeRays::fill_tile(const Tile& tile, RayPacket& packet) const {
    fill_rows<simd::kNativeLanes>(*this, eye_, fwd_, right_, up_, tan_half_fov_, aspect_, width_,
                                  height_, tile, nullptr, packet);
}

void PinholeRays::fill_tile(const Tile& tile, const PixelOffsets& offsets, RayPacket& packet) const {
    fill_rows<simd::kNativeLanes>(*this, eye_, fwd_, right_, up_, tan_half_fov_, aspect_, width_,
                                  height_, tile, &offsets, packet);
}

}  // namespace dynrt::packet
