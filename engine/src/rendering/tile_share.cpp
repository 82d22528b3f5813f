// Packing a process's share of a frame's tiles for the gather of a frame split across
// processes (dynrt/engine/tile_share.h).

#include "dynrt/engine/tile_share.h"

#include <bit>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace dynrt {

std::size_t packed_floats_per_pixel(bool hit_buffers) {
    return kPackedColorFloats + (hit_buffers ? kPackedHitFloats : 0);
}

std::size_t packed_share_size(int width, int height, packet::TileShare share, bool hit_buffers) {
    return packet::Tiling(width, height, share).pixel_count() * packed_floats_per_pixel(hit_buffers);
}

void pack_tiles(const RenderedFrame& frame, packet::TileShare share, std::vector<float>& out) {
    const bool hits = !frame.depth.empty();
    out.reserve(out.size() + packed_share_size(frame.width, frame.height, share, hits));
    packet::Tiling(frame.width, frame.height, share).for_each_pixel([&](std::size_t p) {
        const glm::vec3& c = frame.color[p];
        out.insert(out.end(), {c.x, c.y, c.z});
        if (!hits) return;
        const glm::vec3& n = frame.normal[p];
        out.insert(out.end(), {frame.depth[p], std::bit_cast<float>(frame.object[p]),
                               std::bit_cast<float>(frame.prim[p]), n.x, n.y, n.z});
    });
}

void unpack_tiles(std::span<const float> packed, packet::TileShare share, bool hit_buffers,
                  RenderedFrame& frame) {
    const std::size_t expected = packed_share_size(frame.width, frame.height, share, hit_buffers);
    if (packed.size() != expected) {
        throw std::invalid_argument("tile share " + std::to_string(share.index) + " of " +
                                    std::to_string(share.count) + ": " +
                                    std::to_string(packed.size()) + " floats received, " +
                                    std::to_string(expected) + " expected");
    }
    const float* f = packed.data();
    packet::Tiling(frame.width, frame.height, share).for_each_pixel([&](std::size_t p) {
        frame.color[p] = glm::vec3(f[0], f[1], f[2]);
        f += kPackedColorFloats;
        if (!hit_buffers) return;
        frame.depth[p] = f[0];
        frame.object[p] = std::bit_cast<std::int32_t>(f[1]);
        frame.prim[p] = std::bit_cast<std::int32_t>(f[2]);
        frame.normal[p] = glm::vec3(f[3], f[4], f[5]);
        f += kPackedHitFloats;
    });
}

}  // namespace dynrt
