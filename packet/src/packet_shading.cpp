#include "dynrt/packet/packet_shading.h"

#include "dynrt/packet/light_cosine.h"
#include "dynrt/packet/simd_pow.h"

#include <bit>
#include <stdexcept>

namespace dynrt::packet {

namespace {

/// The distinct materials of the hit lanes, in order of first appearance; returns how many.
/// A tile usually shows one to three, so a linear search beats any set.
int distinct_materials(const SurfacePacket& surface, std::int32_t (&out)[kPacketRays]) {
    int count = 0;
    std::int32_t last = -1;
    surface.hit.for_each([&](int lane) {
        const std::int32_t m = surface.material[lane];
        if (m == last) return;  // neighbours mostly share a material
        last = m;
        bool seen = false;
        for (int i = 0; i < count && !seen; ++i) seen = out[i] == m;
        if (!seen) out[count++] = m;
    });
    return count;
}

template <int W>
void shade_lanes(const SurfacePacket& surface, std::span<const PhongMaterial> materials,
                 std::span<const ShadingLight> lights, std::span<const LaneMask> visible,
                 float ambient, ShadedColors& out, const DiffuseTint* tint, const DiffuseTint* glow) {
    using L = simd::Lanes<W>;
    using F = typename L::F;
    using I = typename L::I;
    std::int32_t present[kPacketRays];
    const int material_count = distinct_materials(surface, present);
    for (int mi = 0; mi < material_count; ++mi) {
        // ---- One material: its constants splatted once, then every step holding it ----
        const std::int32_t id = present[mi];
        const PhongMaterial& material = materials[std::size_t(id)];
        const F kd[3] = {L::splat(material.diffuse.x), L::splat(material.diffuse.y),
                         L::splat(material.diffuse.z)};
        const F ks[3] = {L::splat(material.specular.x), L::splat(material.specular.y),
                         L::splat(material.specular.z)};
        // The ambient term: the frame's fraction of kd, or the material's own colour.
        const F ambient_kd[3] = {material.own_ambient ? L::splat(material.ambient.x) : L::splat(ambient) * kd[0],
                                 material.own_ambient ? L::splat(material.ambient.y) : L::splat(ambient) * kd[1],
                                 material.own_ambient ? L::splat(material.ambient.z) : L::splat(ambient) * kd[2]};
        const F shininess = L::splat(material.shininess);
        const bool glows = material.emission != glm::vec3(0.0f);
        const F emission[3] = {L::splat(material.emission.x), L::splat(material.emission.y),
                               L::splat(material.emission.z)};
        for (int base = 0; base < kPacketRays; base += W) {
            const std::uint32_t hit_bits = surface.hit.extract(base, W);
            if (hit_bits == 0) continue;
            const I mine_mask =
                (L::load(surface.material + base) == L::splat(id)) & L::from_bits(hit_bits);
            const std::uint32_t mine = L::bits(mine_mask);
            if (mine == 0) continue;
            const F p[3] = {L::load(surface.point[0] + base), L::load(surface.point[1] + base),
                            L::load(surface.point[2] + base)};
            const F n[3] = {L::load(surface.shading_normal[0] + base),
                            L::load(surface.shading_normal[1] + base),
                            L::load(surface.shading_normal[2] + base)};
            const F v[3] = {L::load(surface.view[0] + base), L::load(surface.view[1] + base),
                            L::load(surface.view[2] + base)};
            // Textured lanes: kd times their texture colour (the ambient term too).
            F kd_lane[3] = {kd[0], kd[1], kd[2]};
            F color[3] = {ambient_kd[0], ambient_kd[1], ambient_kd[2]};
            if (tint != nullptr) {
                if (const std::uint32_t tinted = tint->lanes.extract(base, W) & mine; tinted != 0) {
                    const I tinted_mask = L::from_bits(tinted);
                    for (int a = 0; a < 3; ++a) {
                        kd_lane[a] = L::select(tinted_mask, kd[a] * L::load(tint->rgb[a] + base), kd[a]);
                        const F tinted_ambient = material.own_ambient
                                                     ? ambient_kd[a] * L::load(tint->rgb[a] + base)
                                                     : L::splat(ambient) * kd_lane[a];
                        color[a] = L::select(tinted_mask, tinted_ambient, ambient_kd[a]);
                    }
                }
            }
            for (std::size_t l = 0; l < lights.size(); ++l) {
                const std::uint32_t lit = visible[l].extract(base, W) & mine;
                if (lit == 0) continue;
                // l = normalize(P_L - point) (or a directional light's fixed vector) and s.l,
                // as the renderer's shadow rays see them.
                const ShadingLight& light = lights[l];
                F at[3] = {L::splat(light.position.x), L::splat(light.position.y), L::splat(light.position.z)};
                if (const float* lane = light.lane_position; lane != nullptr) {
                    for (int a = 0; a < 3; ++a) at[a] = L::load(lane + a * kPacketRays + base);
                }
                F to[3];
                const F n_dot_l = light_cosine<W>(light, p, n, at, to);
                const F twice = L::splat(2.0f) * n_dot_l;
                const F r_dot_v = (twice * n[0] - to[0]) * v[0] + (twice * n[1] - to[1]) * v[1] +
                                  (twice * n[2] - to[2]) * v[2];
                const F specular = simd::pow<W>(
                    L::select(r_dot_v > L::splat(0.0f), r_dot_v, L::splat(0.0f)), shininess);
                // A shading normal may face away from a light its triangle faces.
                const I lit_mask = L::from_bits(lit) & (n_dot_l > L::splat(0.0f));
                const bool falls_off = light.falls_off();
                const F falloff = falls_off ? light_falloff<W>(light, p, at, to) : L::splat(1.0f);
                for (int a = 0; a < 3; ++a) {
                    F intensity = L::splat(light.intensity * light.color[a]);
                    if (falls_off) intensity = intensity * falloff;
                    if (light.lane_filter != nullptr) {
                        intensity = intensity * L::load(light.lane_filter + a * kPacketRays + base);
                    }
                    const F term = intensity * (kd_lane[a] * n_dot_l + ks[a] * specular);
                    color[a] = L::select(lit_mask, color[a] + term, color[a]);
                }
            }
            if (glows) {
                const std::uint32_t mapped = glow != nullptr ? glow->lanes.extract(base, W) & mine : 0u;
                for (int a = 0; a < 3; ++a) {
                    // An emission map's lanes: the factor times the map's colour.
                    const F e = mapped == 0 ? emission[a]
                                            : L::select(L::from_bits(mapped), emission[a] * L::load(glow->rgb[a] + base),
                                                        emission[a]);
                    color[a] = color[a] + e;
                }
            }
            for (int a = 0; a < 3; ++a) {
                // Lanes of other materials keep what their own pass wrote (or will write).
                const F stored = mine == hit_bits ? color[a]
                                                  : L::select(mine_mask, color[a],
                                                              L::load(out.rgb[a] + base));
                L::store(out.rgb[a] + base, stored);
            }
        }
    }
}

}  // namespace

void shade(const SurfacePacket& surface, std::span<const PhongMaterial> materials,
           std::span<const ShadingLight> lights, std::span<const LaneMask> visible,
           float ambient, ShadedColors& out, int lanes, const DiffuseTint* tint, const DiffuseTint* glow) {
    if (visible.size() != lights.size()) {
        throw std::invalid_argument("packet::shade: one visibility mask per light");
    }
    if (lanes == simd::kNativeLanes) {
        shade_lanes<simd::kNativeLanes>(surface, materials, lights, visible, ambient, out, tint, glow);
    } else if (lanes == 1) {
        shade_lanes<1>(surface, materials, lights, visible, ambient, out, tint, glow);
    } else {
        throw std::invalid_argument("packet::shade: lanes must be simd::kNativeLanes or 1");
    }
}

}  // namespace dynrt::packet
