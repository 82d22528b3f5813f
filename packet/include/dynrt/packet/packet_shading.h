#pragma once
// Phong shading of one 16x16 tile in SIMD, after tracing: the renderer stores per lane the hit
// point, the shading normal, the view vector and the material, plus one visibility mask per
// light (the shadow packets' verdicts), and the kernel goes through the materials present in
// the tile, computing the Phong terms of all lanes of one material at once.
//
// The formula is the renderer's (engine/include/dynrt/engine/renderer.h): at a hit with unit
// shading normal n, view vector v, material (kd, ks, s) (kd times the lane's texture colour
// where a DiffuseTint gives one), ambient fraction a,
//   color = a kd + sum over visible lights L with n.l > 0: I_L (kd (n.l) + ks max(0, r.v)^s),
//   l = normalize(P_L - point), r = 2 (n.l) n - l.
// "Visible" is the caller's verdict (the geometric normal faces the light and the shadow ray
// is clear); n.l > 0 is the kernel's own test, as the shading normal may face away where the
// geometric one does not.
// Every operation is lane-wise IEEE float (-ffp-contract=off), so every lane width gives the
// same bits; only the power is approximate (simd_pow.h).

#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/packet_config.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace dynrt::packet {

/// One tile's shading inputs, structure of arrays, lane = tile_lane(tile, x, y). Lanes outside
/// `hit` are never read (they may hold anything). 16 KiB: keep one per thread.
struct alignas(64) SurfacePacket {
    LaneMask hit;
    alignas(64) float point[3][kPacketRays];   ///< hit point
    /// Unit geometric normal facing the eye (the shadow rays' side; the kernel does not read it).
    alignas(64) float normal[3][kPacketRays];
    /// Unit shading normal the kernel lights with: the interpolated vertex normal turned to
    /// `normal`'s side, or `normal` itself (flat shading).
    alignas(64) float shading_normal[3][kPacketRays];
    alignas(64) float view[3][kPacketRays];    ///< -(primary ray direction)
    alignas(64) std::int32_t material[kPacketRays];  ///< index into the materials span
};

/// A Phong material as the kernel reads it (dynrt::Material without its name).
struct PhongMaterial {
    glm::vec3 diffuse{0.8f};
    glm::vec3 specular{0.2f};
    float shininess = 32.0f;  ///< >= 0 and finite
    /// Added to every lit or unlit hit's colour (0: nothing is added, the same bits).
    glm::vec3 emission{0.0f};
    /// When own_ambient, the ambient colour (times the lane's tint) in place of ambient * kd.
    glm::vec3 ambient{0.0f};
    bool own_ambient = false;
};

/// A light as the kernel reads it (dynrt::PointLight posed, renderer.h "Lights"): lane k takes
/// intensity * color * falloff_k, where the falloff is 1 unless the light asks for one.
struct ShadingLight {
    glm::vec3 position{0.0f};
    float intensity = 1.0f;
    /// When not null, each lane's own position instead of `position` (an area light's point
    /// for that lane's sample): x, y, z arrays of kPacketRays floats, one after the other.
    const float* lane_position = nullptr;
    glm::vec3 color{1.0f};
    /// A directional light: every lane's unit vector toward the light is `toward` (the
    /// negated direction of travel); `position` and `lane_position` are not read.
    bool directional = false;
    glm::vec3 toward{0.0f, 0.0f, 1.0f};
    /// Falloff with the distance d to the light: 1 / d^2 ...
    bool inverse_square = false;
    /// ... times clamp(1 - (d^2 / range^2)^2, 0, 1) when range > 0 (glTF's window).
    float range = 0.0f;
    /// A spot: times clamp((-l).axis * cone_scale + cone_offset, 0, 1)^2 (glTF's cone).
    bool spot = false;
    glm::vec3 spot_axis{0.0f, 0.0f, -1.0f};
    float cone_scale = 1.0f, cone_offset = 0.0f;

    /// When not null, what reaches each lane through transmissive surfaces (coloured
    /// shadows): r, g, b arrays of kPacketRays floats, one after the other, multiplying the
    /// light's colour; read only on lanes `visible` gives.
    const float* lane_filter = nullptr;

    /// Whether lanes take a falloff other than 1.
    bool falls_off() const { return inverse_square || range > 0.0f || spot; }
};

/// Per-lane factors of the material's diffuse colour (a texture's colour at each hit): lanes in
/// `lanes` shade with kd * rgb (ambient term included), the others with kd. 3 KiB.
struct alignas(64) DiffuseTint {
    LaneMask lanes;
    alignas(64) float rgb[3][kPacketRays];
};

/// Linear RGB per lane: meaningful for the lanes of SurfacePacket::hit, unspecified elsewhere.
struct alignas(64) ShadedColors {
    alignas(64) float rgb[3][kPacketRays];
};

/// Shades every hit lane of `surface` into `out`. `visible[l]` holds the lanes that light l
/// may light (the geometric n.l > 0 and the shadow ray unoccluded; the kernel adds the light
/// where the shading normal's n.l > 0 too); one mask per light, same order as `lights`. Every `surface.material` of a hit lane must index `materials`. `lanes` is
/// native_simd_lanes() or 1, as PacketConfig::lanes; both give the same bits. `tint`, when not
/// null, scales the diffuse colour of its lanes. Throws std::invalid_argument for another
/// width or mismatched spans. `glow`, when not null, scales the emission of its lanes (an
/// emission map's colour). Thread-safe (no shared state).
void shade(const SurfacePacket& surface, std::span<const PhongMaterial> materials,
           std::span<const ShadingLight> lights, std::span<const LaneMask> visible,
           float ambient, ShadedColors& out, int lanes = native_simd_lanes(),
           const DiffuseTint* tint = nullptr, const DiffuseTint* glow = nullptr);

}  // namespace dynrt::packet
