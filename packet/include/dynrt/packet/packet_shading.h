#pragma once
// Phong shading of one 16x16 tile in SIMD, after tracing: the renderer stores per lane the hit
// point, the facing normal, the view vector and the material, plus one visibility mask per
// light (the shadow packets' verdicts), and the kernel goes through the materials present in
// the tile, computing the Phong terms of all lanes of one material at once.
//
// The formula is the renderer's (engine/include/dynrt/engine/renderer.h): at a hit with unit
// normal n facing the eye, view vector v, material (kd, ks, s), ambient fraction a,
//   color = a kd + sum over visible lights L: I_L (kd (n.l) + ks max(0, r.v)^s),
//   l = normalize(P_L - point), r = 2 (n.l) n - l.
// Every operation is lane-wise IEEE float (-ffp-contract=off), so every lane width gives the
// same bits; only the power is approximate (simd_pow.h).

#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/packet_config.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace dynrt::packet {

/// One tile's shading inputs, structure of arrays, lane = tile_lane(tile, x, y). Lanes outside
/// `hit` are never read (they may hold anything). 13 KiB: keep one per thread.
struct alignas(64) SurfacePacket {
    LaneMask hit;
    alignas(64) float point[3][kPacketRays];   ///< hit point
    alignas(64) float normal[3][kPacketRays];  ///< unit geometric normal facing the eye
    alignas(64) float view[3][kPacketRays];    ///< -(primary ray direction)
    alignas(64) std::int32_t material[kPacketRays];  ///< index into the materials span
};

/// A Phong material as the kernel reads it (dynrt::Material without its name).
struct PhongMaterial {
    glm::vec3 diffuse{0.8f};
    glm::vec3 specular{0.2f};
    float shininess = 32.0f;  ///< >= 0 and finite
};

/// A point light: position and intensity (no falloff).
struct ShadingLight {
    glm::vec3 position{0.0f};
    float intensity = 1.0f;
};

/// Linear RGB per lane: meaningful for the lanes of SurfacePacket::hit, unspecified elsewhere.
struct alignas(64) ShadedColors {
    alignas(64) float rgb[3][kPacketRays];
};

/// Shades every hit lane of `surface` into `out`. `visible[l]` holds the lanes that light l
/// lights (n.l > 0 and the shadow ray unoccluded); one mask per light, same order as
/// `lights`. Every `surface.material` of a hit lane must index `materials`. `lanes` is
/// native_simd_lanes() or 1, as PacketConfig::lanes; both give the same bits. Throws
/// std::invalid_argument for another width or mismatched spans. Thread-safe (no shared state).
void shade(const SurfacePacket& surface, std::span<const PhongMaterial> materials,
           std::span<const ShadingLight> lights, std::span<const LaneMask> visible,
           float ambient, ShadedColors& out, int lanes = native_simd_lanes());

}  // namespace dynrt::packet
