#pragma once
// A packet of 256 rays in structure-of-arrays layout, the unit the packet tracer traces, and
// the hits it returns. A camera tile of 16x16 pixels is one packet; shadow rays of one tile
// toward one light are another.

#include "dynrt/bvh/ray.h"
#include "dynrt/packet/tiling.h"

#include <bit>
#include <cstdint>

namespace dynrt::packet {

inline constexpr int kPacketRays = kTileSize * kTileSize;

/// A set of lanes of a packet: lane i is bit i % 64 of words[i / 64].
struct LaneMask {
    std::uint64_t words[kPacketRays / 64] = {};

    void set(int lane) { words[lane >> 6] |= std::uint64_t{1} << (lane & 63); }
    void reset(int lane) { words[lane >> 6] &= ~(std::uint64_t{1} << (lane & 63)); }
    bool test(int lane) const { return (words[lane >> 6] >> (lane & 63)) & 1u; }
    int count() const {
        int n = 0;
        for (std::uint64_t w : words) n += std::popcount(w);
        return n;
    }
    bool any() const { return (words[0] | words[1] | words[2] | words[3]) != 0; }
    /// Lanes [first, first + n) as bits 0..n-1; n is 1, 2, 4, 8, 16 or 32 and divides first.
    std::uint32_t extract(int first, int n) const {
        const std::uint64_t bits = words[first >> 6] >> (first & 63);
        return std::uint32_t(n == 32 ? bits & 0xffffffffu : bits & ((std::uint64_t{1} << n) - 1));
    }
    bool operator==(const LaneMask&) const = default;

    /// Calls f(lane) for every lane in the set, ascending.
    template <typename F>
    void for_each(F&& f) const {
        for (int w = 0; w < kWords; ++w) {
            for (std::uint64_t bits = words[w]; bits != 0; bits &= bits - 1) f(w * 64 + std::countr_zero(bits));
        }
    }

    LaneMask& operator&=(const LaneMask& other) {
        for (int w = 0; w < kWords; ++w) words[w] &= other.words[w];
        return *this;
    }
    LaneMask& operator|=(const LaneMask& other) {
        for (int w = 0; w < kWords; ++w) words[w] |= other.words[w];
        return *this;
    }
    /// The lanes not in the set (all 256 lanes are a packet's).
    LaneMask operator~() const {
        LaneMask out;
        for (int w = 0; w < kWords; ++w) out.words[w] = ~words[w];
        return out;
    }
    friend LaneMask operator&(LaneMask a, const LaneMask& b) { return a &= b; }
    friend LaneMask operator|(LaneMask a, const LaneMask& b) { return a |= b; }

private:
    static constexpr int kWords = kPacketRays / 64;
};

/// 256 rays, one array per component, each aligned for SIMD loads. Lanes not in `active` are
/// ignored by every trace (they may hold anything); `set_ray` activates a lane. The layout does
/// not assume any order of rays: a tile packet puts pixel (x, y) in lane tile_lane(tile, x, y),
/// but any caller may fill lanes as it likes (coherent packets simply trace faster).
///
/// 10 KiB: keep one per thread and refill it rather than building one per call.
struct alignas(64) RayPacket {
    alignas(64) float org_x[kPacketRays];
    alignas(64) float org_y[kPacketRays];
    alignas(64) float org_z[kPacketRays];
    alignas(64) float dir_x[kPacketRays];
    alignas(64) float dir_y[kPacketRays];
    alignas(64) float dir_z[kPacketRays];
    alignas(64) float tmin[kPacketRays];
    alignas(64) float tmax[kPacketRays];
    LaneMask active;

    /// Makes every lane inactive (the ray data is left as it is).
    void clear() { active = LaneMask{}; }

    /// Stores `ray` in `lane` and activates it. The direction must be finite and non-zero and
    /// tmin <= tmax, as for the single-ray tracer.
    void set_ray(int lane, const bvh::Ray& ray) {
        org_x[lane] = ray.org.x;
        org_y[lane] = ray.org.y;
        org_z[lane] = ray.org.z;
        dir_x[lane] = ray.dir.x;
        dir_y[lane] = ray.dir.y;
        dir_z[lane] = ray.dir.z;
        tmin[lane] = ray.tmin;
        tmax[lane] = ray.tmax;
        active.set(lane);
    }

    /// The ray in `lane` (meaningful for active lanes).
    bvh::Ray ray(int lane) const {
        bvh::Ray r;
        r.org = {org_x[lane], org_y[lane], org_z[lane]};
        r.dir = {dir_x[lane], dir_y[lane], dir_z[lane]};
        r.tmin = tmin[lane];
        r.tmax = tmax[lane];
        return r;
    }
};

/// The lane of pixel (x, y) of `tile` in a tile packet: row-major within the tile, so lane
/// (y - y0) * 16 + (x - x0). Pixels of a clipped edge tile keep their lane; the lanes past the
/// image edge stay inactive.
inline int tile_lane(const Tile& tile, int x, int y) {
    return (y - tile.y0) * kTileSize + (x - tile.x0);
}

/// The pixel of `lane` in a tile packet (tile_lane's inverse); it lies outside the tile (x >=
/// x1 or y >= y1) for the lanes past a clipped tile's edge.
struct LanePixel {
    int x, y;
    bool inside;
};
inline LanePixel tile_pixel(const Tile& tile, int lane) {
    const int x = tile.x0 + lane % kTileSize, y = tile.y0 + lane / kTileSize;
    return LanePixel{x, y, x < tile.x1 && y < tile.y1};
}

/// Fills `packet` with the rays of `tile`: lane tile_lane(tile, x, y) gets ray_of(x, y) (a
/// bvh::Ray) for every pixel of the tile, and every other lane is inactive.
template <typename RayOf>
void fill_tile(const Tile& tile, RayOf&& ray_of, RayPacket& packet) {
    packet.clear();
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) packet.set_ray(tile_lane(tile, x, y), ray_of(x, y));
    }
}

/// Closest hits of a packet, one lane per ray, in the same SoA layout. A lane that missed (or
/// is inactive) holds t = +inf, u = v = 0 and prim = bvh::kInvalidId, exactly like a default
/// bvh::Hit.
struct alignas(64) PacketHits {
    alignas(64) float t[kPacketRays];
    alignas(64) float u[kPacketRays];
    alignas(64) float v[kPacketRays];
    alignas(64) std::uint32_t prim[kPacketRays];

    bvh::Hit hit(int lane) const { return bvh::Hit{t[lane], u[lane], v[lane], prim[lane]}; }
};

}  // namespace dynrt::packet
