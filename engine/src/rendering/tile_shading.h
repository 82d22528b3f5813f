#pragma once
// A tile's hits made ready for shadow rays and shading, shared by the renderer's exact and
// adaptive paths: where each hit's shadow rays start (bit-identical between the packet and
// single-ray tracers), the shading normal each hit is lit with (its vertex normals
// interpolated, renderer.h "Shading normals"), the tile's shadow packets toward a light, the
// texture colours of its hits (tint_lanes) and the Phong shading and output writes of a whole
// tile.

#include "dynrt/bvh/triangle.h"
#include "dynrt/bvh/two_level_bvh.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/texture_set.h"
#include "dynrt/packet/light_cosine.h"
#include "dynrt/packet/packet_shading.h"
#include "dynrt/packet/simd.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/packet/tiling.h"
#include "rendering/pixel_samples.h"
#include "update/scene_accel.h"
#include "dynrt/engine/shadow_ray_offset.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

namespace dynrt::detail {

/// Unit geometric normal of `tri`, turned to face against `dir`.
inline glm::vec3 facing_normal(const bvh::Triangle& tri, const glm::vec3& dir) {
    const glm::vec3 n = glm::normalize(glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    return glm::dot(n, dir) > 0.0f ? -n : n;
}

/// The hit point from barycentrics: unlike org + t * dir, its error does not grow with the
/// distance travelled, so the small shadow-ray offset is enough to clear the surface.
inline glm::vec3 hit_point(const bvh::Triangle& tri, const bvh::Hit& hit) {
    return (1.0f - hit.u - hit.v) * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
}

/// `light` as the shading kernel reads it (renderer.h, "Lights"): a spot's cone as glTF's
/// scale and offset, 1 / max(0.001, cos(inner) - cos(outer)) and -cos(outer) times it.
inline packet::ShadingLight shading_light(const PointLight& light) {
    packet::ShadingLight out{light.position, light.intensity};
    out.color = light.color;
    out.directional = light.kind == PointLight::Kind::directional;
    out.toward = -light.direction;
    const bool local = !out.directional;
    out.inverse_square = local && light.inverse_square;
    out.range = local ? light.range : 0.0f;
    out.spot = light.kind == PointLight::Kind::spot;
    if (out.spot) {
        const double cos_inner = std::cos(double(light.inner_cone)), cos_outer = std::cos(double(light.outer_cone));
        const double scale = 1.0 / std::max(0.001, cos_inner - cos_outer);
        out.spot_axis = light.direction;
        out.cone_scale = float(scale);
        out.cone_offset = float(-cos_outer * scale);
    }
    return out;
}

/// Where a pixel's shadow rays start and what they need to know: the facing normal and the
/// hit point, exactly as both tracers compute them.
struct ShadowOrigin {
    glm::vec3 n, point, origin;

    ShadowOrigin(const bvh::Triangle& tri, const bvh::Hit& hit, const glm::vec3& primary_dir)
        : n(facing_normal(tri, primary_dir)), point(hit_point(tri, hit)),
          origin(offset_along_normal(point, n, triangle_magnitude(tri.v0, tri.v1, tri.v2))) {}

    /// The light is on the lit side of the surface, so a shadow ray is traced.
    bool faces(const PointLight& light) const { return glm::dot(n, light.position - point) > 0.0f; }

    /// The shadow ray runs from the light to the offset origin: t in [0, 1] is exactly the
    /// segment between them. From the light, all the shadow rays of a tile share one origin,
    /// which gives packets a tight beam (culling, cheaper box tests); see packet/README.md,
    /// "Shadow ray direction", for what it gained.
    bvh::Ray ray_to(const PointLight& light) const {
        bvh::Ray shadow;
        shadow.org = light.position;
        shadow.dir = shadow_ray_end(origin, n, light.position) - light.position;
        shadow.tmin = 0.0f;
        shadow.tmax = 1.0f;
        return shadow;
    }
};

/// One tile's hits as shading and shadow rays need them, lane by lane in SIMD: facing normal,
/// hit point and offset origin by exactly the operations of facing_normal, hit_point and
/// offset_along_normal (glm's cross, normalize = v * (1 / sqrt(dot)), dot = (x*x + y*y) +
/// z*z), so the shadow rays are bit-identical to the single-ray tracer's; plus the shading
/// normal, the view vector and material per lane, so the shading kernel reads the same arrays
/// while they are hot.
///
/// The shading normal (renderer.h, "Shading normals"): where ShadingGeometry::world_vertex_normals
/// gives the hit triangle's vertex normals n0, n1, n2, it is s = (1 - u - v) n0 + u n1 + v n2
/// normalised, negated when s . n < 0 for the facing normal n (so it lies on the eye's side
/// exactly when the geometric normal does, whichever way the file's normals and winding
/// point); where s . s <= kMinShadingNormalLength2 (opposed vertex normals) or there are none, it is
/// n itself, bit for bit.
struct TileShadowOrigins {
    packet::SurfacePacket surface;  ///< hit mask, point, normals, view, material
    alignas(64) float origin[3][packet::kPacketRays];


    /// Lanes whose ray met the back of its triangle (against the winding normal (v1 - v0) x
    /// (v2 - v0), which `surface.normal` was turned from): a refracted ray leaves the inside.
    packet::LaneMask back_hit;
    /// Per lane, triangle_magnitude of the hit triangle (for offsets along the normal).
    alignas(64) float magnitude[packet::kPacketRays];

    /// Per hit lane, what texture lookups need (tint_lanes): the hit's object, triangle,
    /// barycentrics and the triangle's twice area, |(v1 - v0) x (v2 - v0)|, in world space.
    alignas(64) std::int32_t object[packet::kPacketRays];
    alignas(64) std::uint32_t prim[packet::kPacketRays];
    alignas(64) float bary[2][packet::kPacketRays];
    alignas(64) float twice_area[packet::kPacketRays];

    /// Per light, the point of it each hit lane's shadow ray and shading use: one sample of an
    /// area light per pixel sample (sample_lights). Empty when every light is a point.
    struct LightLanes {
        alignas(64) float point[3][packet::kPacketRays];
        bool sampled = false;  ///< an area light's (a point light's entry is unused)
    };
    std::vector<LightLanes> light_lanes;

    /// Fills light_lanes for `lights` (light_sample_point): hit lane k takes the point of the
    /// pixel sample `sample_of(k)` (a PixelSample) of `spp`. Nothing when every light is a point.
    template <typename SampleOf>
    void sample_lights(std::span<const PointLight> lights, SampleOf&& sample_of, int spp) {
        light_lanes.clear();
        if (std::none_of(lights.begin(), lights.end(),
                         [](const PointLight& l) { return l.shape != PointLight::Shape::point; })) {
            return;
        }
        light_lanes.resize(lights.size());
        for (std::size_t l = 0; l < lights.size(); ++l) {
            if (lights[l].shape == PointLight::Shape::point) continue;
            LightLanes& lanes = light_lanes[l];
            lanes.sampled = true;
            surface.hit.for_each([&](int lane) {
                const PixelSample ps = sample_of(lane);
                const glm::vec3 at = light_sample_point(lights[l], std::uint32_t(l), ps.pixel, int(ps.sample), spp);
                for (int a = 0; a < 3; ++a) lanes.point[a][lane] = at[a];
            });
        }
    }

    /// Per light, what reaches each hit lane whose shadow ray passed through transmissive
    /// surfaces only (trace_tile_shadows): the product of their transmittances. Empty when no
    /// ray did.
    struct LightFilter {
        alignas(64) float rgb[3][packet::kPacketRays];
        bool any = false;  ///< some lane of this light's is filtered (the others read 1)
    };
    std::vector<LightFilter> light_filter;

    /// Light l's filter for lanes reached through glass, made (all 1) on first use.
    LightFilter& filter_of(std::size_t l, std::size_t light_count) {
        if (light_filter.size() != light_count) light_filter.assign(light_count, LightFilter{});
        LightFilter& f = light_filter[l];
        if (!f.any) {
            for (auto& channel : f.rgb) std::fill(std::begin(channel), std::end(channel), 1.0f);
            f.any = true;
        }
        return f;
    }
    /// Light l's filter (r, g, b arrays), or null when none of its lanes is filtered.
    const float* light_filter_of(std::size_t l) const {
        return l < light_filter.size() && light_filter[l].any ? &light_filter[l].rgb[0][0] : nullptr;
    }

    /// Light l's points per lane (x, y, z arrays), or null when it is a point light.
    const float* light_points(std::size_t l) const {
        return l < light_lanes.size() && light_lanes[l].sampled ? &light_lanes[l].point[0][0] : nullptr;
    }

    /// `primary` holds the tile's camera rays (lane tile_lane(tile, x, y)); object i has
    /// material object_material[i].
    void compute(const SceneAccel& accel, const std::vector<bvh::InstanceHit>& hits, int width,
                 const packet::Tile& tile, const packet::RayPacket& primary,
                 const std::vector<std::int32_t>& object_material) {
        // The hit triangles are scattered through large arrays: request them all before
        // reading any, so the cache misses overlap.
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                const bvh::InstanceHit& h = hits[std::size_t(y) * width + x];
                if (!h.is_hit()) continue;
                accel.prefetch_triangle(h.object, h.hit.prim);
            }
        }
        compute_lanes(
            accel,
            [&](int lane) -> const bvh::InstanceHit* {
                const packet::LanePixel px = packet::tile_pixel(tile, lane);
                if (!px.inside) return nullptr;
                const bvh::InstanceHit& h = hits[std::size_t(px.y) * width + px.x];
                return h.is_hit() ? &h : nullptr;
            },
            primary, object_material);
    }

    /// The same for any packet of rays: `hit_of(lane)` gives the lane's resolved hit, or null
    /// for a lane without one; `rays` holds the rays that made them (their directions turn the
    /// normals, and their negations are the view vectors, so they must be unit length).
    template <typename HitOf>
    void compute_lanes(const SceneAccel& accel, HitOf&& hit_of, const packet::RayPacket& rays,
                       const std::vector<std::int32_t>& object_material) {
        packet::LaneMask& hit = surface.hit;
        light_filter.clear();
        using L = packet::simd::Lanes<packet::simd::kNativeLanes>;
        using F = L::F;
        using I = L::I;
        constexpr int W = packet::simd::kNativeLanes;
        // Gather each hit's triangle and barycentrics into lanes; lanes without a hit get a
        // harmless triangle and are never used.
        alignas(64) float v[9][packet::kPacketRays];
        alignas(64) float vertex_normal[9][packet::kPacketRays];
        constexpr float kHarmless[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        hit = packet::LaneMask{};
        back_hit = packet::LaneMask{};
        packet::LaneMask smooth;  // lanes whose triangle has vertex normals
        for (int lane = 0; lane < packet::kPacketRays; ++lane) {
            const bvh::InstanceHit* ih = hit_of(lane);
            float coords[9];
            glm::vec3 normals[3] = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
            if (ih != nullptr) {
                hit.set(lane);
                const bvh::Triangle tri = accel.world_triangle(ih->object, ih->hit.prim);
                std::memcpy(coords, &tri, sizeof coords);
                surface.material[lane] = object_material[ih->object];
                object[lane] = std::int32_t(ih->object);
                prim[lane] = ih->hit.prim;
                if (accel.shading().world_vertex_normals(ih->object, ih->hit.prim, normals)) smooth.set(lane);
            } else {
                std::memcpy(coords, kHarmless, sizeof coords);
            }
            for (int k = 0; k < 9; ++k) v[k][lane] = coords[k];
            for (int k = 0; k < 3; ++k) {
                for (int a = 0; a < 3; ++a) vertex_normal[3 * k + a][lane] = normals[k][a];
            }
            bary[0][lane] = ih ? ih->hit.u : 0.0f;
            bary[1][lane] = ih ? ih->hit.v : 0.0f;
        }
        const packet::RayPacket& primary = rays;
        const float* dir_in[3] = {primary.dir_x, primary.dir_y, primary.dir_z};
        for (int base = 0; base < packet::kPacketRays; base += W) {
            if (hit.extract(base, W) == 0) {
                // Misses keep their view vector too: their direction picks what the
                // environment shows (TileShading::miss).
                for (int a = 0; a < 3; ++a) L::store(surface.view[a] + base, -L::load(dir_in[a] + base));
                continue;
            }
            F v0[3], v1[3], v2[3], e1[3], e2[3];
            for (int a = 0; a < 3; ++a) {
                v0[a] = L::load(v[a] + base);
                v1[a] = L::load(v[3 + a] + base);
                v2[a] = L::load(v[6 + a] + base);
                e1[a] = v1[a] - v0[a];
                e2[a] = v2[a] - v0[a];
            }
            // facing_normal: normalize(cross(e1, e2)), negated where it faces along the ray.
            const F c[3] = {e1[1] * e2[2] - e2[1] * e1[2], e1[2] * e2[0] - e2[2] * e1[0],
                            e1[0] * e2[1] - e2[0] * e1[1]};
            const F length = L::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            const F inv_len = L::splat(1.0f) / length;
            L::store(twice_area + base, length);
            F nv[3] = {c[0] * inv_len, c[1] * inv_len, c[2] * inv_len};
            const F d[3] = {L::load(dir_in[0] + base), L::load(dir_in[1] + base),
                            L::load(dir_in[2] + base)};
            const I flip = (nv[0] * d[0] + nv[1] * d[1] + nv[2] * d[2]) > L::splat(0.0f);
            back_hit.words[base >> 6] |= std::uint64_t(L::bits(flip) & hit.extract(base, W))
                                         << (base & 63);
            for (int a = 0; a < 3; ++a) {
                nv[a] = L::select(flip, -nv[a], nv[a]);
                L::store(surface.view[a] + base, -d[a]);
            }
            // hit_point: (1 - u - v) v0 + u v1 + v v2.
            const F u = L::load(bary[0] + base), w = L::load(bary[1] + base);
            const F b0 = L::splat(1.0f) - u - w;
            // The shading normal: the vertex normals interpolated alike (see above).
            F shading[3] = {nv[0], nv[1], nv[2]};
            if (const std::uint32_t smooth_bits = smooth.extract(base, W); smooth_bits != 0) {
                F sn[3];
                for (int a = 0; a < 3; ++a) {
                    sn[a] = b0 * L::load(vertex_normal[a] + base) + u * L::load(vertex_normal[3 + a] + base) +
                            w * L::load(vertex_normal[6 + a] + base);
                }
                const F length2 = sn[0] * sn[0] + sn[1] * sn[1] + sn[2] * sn[2];
                const I usable = L::from_bits(smooth_bits) & (length2 > L::splat(kMinShadingNormalLength2));
                const F inv = L::splat(1.0f) / L::sqrt(L::select(usable, length2, L::splat(1.0f)));
                const I away = (sn[0] * nv[0] + sn[1] * nv[1] + sn[2] * nv[2]) < L::splat(0.0f);
                const F sign = L::select(away, L::splat(-1.0f), L::splat(1.0f));
                for (int a = 0; a < 3; ++a) shading[a] = L::select(usable, sign * (sn[a] * inv), nv[a]);
            }
            // triangle_magnitude: the largest |coordinate| of the three vertices.
            F magnitude_lanes = L::splat(0.0f);
            for (const F* vertex : {v0, v1, v2}) {
                for (int a = 0; a < 3; ++a) {
                    const F m = L::abs(vertex[a]);
                    magnitude_lanes = L::select(m > magnitude_lanes, m, magnitude_lanes);
                }
            }
            L::store(magnitude + base, magnitude_lanes);
            for (int a = 0; a < 3; ++a) {
                const F p = b0 * v0[a] + u * v1[a] + w * v2[a];
                // offset_along_normal, with its constants (256 ulps per unit of normal,
                // 2^-16 of the magnitude below 1/32 of it); packet_renderer_test catches any
                // drift.
                const I ulps = L::truncate(L::splat(kShadowIntScale) * nv[a]);
                const I bits = L::bits_of(p);
                const F moved = L::float_of(bits + L::select(p < L::splat(0.0f), -ulps, ulps));
                const F near_origin = p + L::splat(kShadowFloatScale) * magnitude_lanes * nv[a];
                L::store(surface.normal[a] + base, nv[a]);
                L::store(surface.shading_normal[a] + base, shading[a]);
                L::store(surface.point[a] + base, p);
                L::store(origin[a] + base,
                         L::select(L::abs(p) < L::splat(kShadowOrigin) * magnitude_lanes, near_origin, moved));
            }
        }
    }

    /// Lanes rays_to leaves out although their surface faces the light.
    struct LeftOut {
        int shading_away = 0;  ///< the shading normal faces away
        int dark = 0;          ///< the falloff is 0 there (outside a spot's cone, past a range)
    };

    /// Fills `out` with the shadow rays toward `light` of the hit lanes on its lit side
    /// (ShadowOrigin::faces and ray_to, lane by lane) whose shading normal faces it too and
    /// whose falloff is not 0; none toward a light of intensity 0. Returns the lanes left out.
    /// The rays left out are exactly those whose light adds nothing to the hit's colour:
    /// packet::shade adds a light's term only on lanes its geometric normal faces and whose
    /// shading normal faces it by the very cosine computed here (packet::light_cosine), and a
    /// term of intensity or falloff 0 (packet::light_falloff, the same function) is +0 (its
    /// factors are finite and the lit lanes' cosine positive), which leaves every colour's bits
    /// as they are.
    /// An area light's rays leave each lane's own point of it (light_lanes). A directional
    /// light's leave the offset origin toward it, t in [0, +inf): no point of it is nearer.
    /// `shading` is light l as the frame's shading reads it (TileShading::lights).
    LeftOut rays_to(const packet::ShadingLight& shading, std::size_t l, packet::RayPacket& out) const {
        using L = packet::simd::Lanes<packet::simd::kNativeLanes>;
        using F = L::F;
        constexpr int W = packet::simd::kNativeLanes;
        out.clear();
        LeftOut left;
        if (shading.intensity == 0.0f) return left;
        const glm::vec3& position = shading.position;
        const bool falls_off = shading.falls_off();
        const float* points = light_points(l);
        F lx = L::splat(position.x), ly = L::splat(position.y), lz = L::splat(position.z);
        for (int base = 0; base < packet::kPacketRays; base += W) {
            const std::uint32_t lanes = surface.hit.extract(base, W);
            if (lanes == 0) continue;
            if (points != nullptr) {
                lx = L::load(points + base);
                ly = L::load(points + packet::kPacketRays + base);
                lz = L::load(points + 2 * packet::kPacketRays + base);
            }
            const F light_at[3] = {lx, ly, lz};
            const F p[3] = {L::load(surface.point[0] + base), L::load(surface.point[1] + base),
                            L::load(surface.point[2] + base)};
            const F nx = L::load(surface.normal[0] + base), ny = L::load(surface.normal[1] + base),
                    nz = L::load(surface.normal[2] + base);
            F facing;
            if (shading.directional) {
                facing = nx * L::splat(shading.toward.x) + ny * L::splat(shading.toward.y) +
                         nz * L::splat(shading.toward.z);
            } else {
                const F to_x = lx - p[0], to_y = ly - p[1], to_z = lz - p[2];
                facing = nx * to_x + ny * to_y + nz * to_z;
            }
            const std::uint32_t faces = L::bits(facing > L::splat(0.0f)) & lanes;
            if (faces == 0) continue;
            const F s[3] = {L::load(surface.shading_normal[0] + base),
                            L::load(surface.shading_normal[1] + base),
                            L::load(surface.shading_normal[2] + base)};
            F unit[3];
            const std::uint32_t toward =
                L::bits(packet::light_cosine<W>(shading, p, s, light_at, unit) > L::splat(0.0f)) & faces;
            left.shading_away += std::popcount(faces & ~toward);
            std::uint32_t lit = toward;
            if (falls_off && lit != 0) {
                lit &= L::bits(packet::light_falloff<W>(shading, p, light_at, unit) > L::splat(0.0f));
                left.dark += std::popcount(toward & ~lit);
            }
            if (lit == 0) continue;
            const F ox = L::load(origin[0] + base), oy = L::load(origin[1] + base),
                    oz = L::load(origin[2] + base);
            if (shading.directional) {
                L::store(out.org_x + base, ox);
                L::store(out.org_y + base, oy);
                L::store(out.org_z + base, oz);
                L::store(out.dir_x + base, L::splat(shading.toward.x));
                L::store(out.dir_y + base, L::splat(shading.toward.y));
                L::store(out.dir_z + base, L::splat(shading.toward.z));
                L::store(out.tmin + base, L::splat(0.0f));
                L::store(out.tmax + base, L::splat(std::numeric_limits<float>::infinity()));
                out.active.words[base >> 6] |= std::uint64_t(lit) << (base & 63);
                continue;
            }
            // shadow_ray_end: push kShadowLightScale * D further along the normal.
            const F dx = L::abs(lx - ox), dy = L::abs(ly - oy), dz = L::abs(lz - oz);
            F d = dx;
            d = L::select(dy > d, dy, d);
            d = L::select(dz > d, dz, d);
            const F push = L::splat(kShadowLightScale) * d;
            const F ex = ox + push * nx, ey = oy + push * ny, ez = oz + push * nz;
            L::store(out.org_x + base, lx);
            L::store(out.org_y + base, ly);
            L::store(out.org_z + base, lz);
            L::store(out.dir_x + base, ex - lx);
            L::store(out.dir_y + base, ey - ly);
            L::store(out.dir_z + base, ez - lz);
            L::store(out.tmin + base, L::splat(0.0f));
            L::store(out.tmax + base, L::splat(1.0f));
            out.active.words[base >> 6] |= std::uint64_t(lit) << (base & 63);
        }
        return left;
    }
};

/// Whether Whitted's reflected and refracted directions computed with the shading normal
/// `shading` hold at a hit of a ray along `d` whose facing geometric normal is `n`: the ray
/// comes from the shading normal's side (d . shading < 0), the reflected direction leaves
/// above the geometric surface (reflected . n > 0) and the refracted one, when there is one
/// (not 0), goes below it (refracted . n < 0). Otherwise (a smooth normal bent past the ray, or
/// past the mirror direction near a silhouette) the whole split is made with `n` instead
/// (renderer.h, "Shading normals"), so no secondary ray starts into its own surface.
inline bool shading_split_holds(const glm::vec3& d, const glm::vec3& shading, const glm::vec3& n,
                                const glm::vec3& reflected, const glm::vec3& refracted) {
    const bool refracts = refracted != glm::vec3(0.0f);
    return glm::dot(d, shading) < 0.0f && glm::dot(reflected, n) > 0.0f &&
           (!refracts || glm::dot(refracted, n) < 0.0f);
}

/// One object's texture coordinates as shading reads them (borrowed from its mesh).
struct ObjectTexcoords {
    std::span<const glm::vec2> texcoords;  ///< per vertex, or empty: not textured
    std::span<const glm::uvec3> triangles;
};

/// What texture lookups need for a frame (docs/rendering.md "Textures"): the scene's textures, each
/// object's texture coordinates, and the camera's eye and per-pixel angle for the footprint
/// (texture_footprint).
struct SurfaceTextures {
    const TextureSet& set;
    std::span<const ObjectTexcoords> objects;  ///< per object, scene order
    glm::vec3 eye;
    float pixel_angle;  ///< radians per pixel: 2 tan(fov_y / 2) / height
};

/// What shading a tile needs besides the tile's own data; fixed for a frame.
struct TileShading {
    std::span<const packet::PhongMaterial> materials;
    std::span<const packet::ShadingLight> lights;
    float ambient;
    glm::vec3 background;
    int lanes;  ///< PacketConfig::lanes: the kernel's SIMD width (same bits either way)
    /// The frame's textures, or null when no material maps one.
    const SurfaceTextures* textures = nullptr;
    /// Per object, its material's transmittance, which shadow rays pass through
    /// (trace_tile_shadows); empty when no object is transmissive.
    std::span<const glm::vec3> glass = {};
    /// What rays that miss see (TraceSettings::environment), or null: the background.
    const EnvironmentMap* environment = nullptr;

    /// The colour of a ray along `direction` that meets nothing.
    glm::vec3 miss(const glm::vec3& direction) const {
        return environment != nullptr ? environment->radiance(direction) : background;
    }
};

/// texture_footprint for lookups [0, count), SIMD across them with its operations in its order
/// (so its bits): the distance from the eye, sqrt((x*x + y*y) + z*z) as glm::length, times
/// `pixel_angle`, times sqrt(texture_area / world_area); 0 where world_area is not positive.
/// The arrays hold whole vectors past `count` (entries there are overwritten).
inline void footprint_lanes(float pixel_angle, int count, float (&eye_offset)[3][packet::kPacketRays],
                            float (&texture_area)[packet::kPacketRays], float (&world_area)[packet::kPacketRays],
                            float (&width)[packet::kPacketRays]) {
    using L = packet::simd::Lanes<packet::simd::kNativeLanes>;
    using F = L::F;
    constexpr int W = packet::simd::kNativeLanes;
    const int padded = (count + W - 1) / W * W;
    for (int k = count; k < padded; ++k) {
        for (auto& axis : eye_offset) axis[k] = 0.0f;
        texture_area[k] = 0.0f;
        world_area[k] = 1.0f;
    }
    for (int k = 0; k < padded; k += W) {
        const F x = L::load(eye_offset[0] + k), y = L::load(eye_offset[1] + k), z = L::load(eye_offset[2] + k);
        const F distance = L::sqrt((x * x + y * y) + z * z);
        const F world = L::load(world_area + k);
        const F footprint = distance * L::splat(pixel_angle) * L::sqrt(L::load(texture_area + k) / world);
        L::store(width + k, L::select(world > L::splat(0.0f), footprint, L::splat(0.0f)));
    }
}

/// The diffuse factors of `origins`' hit lanes whose material maps a readable texture and
/// whose object has texture coordinates: the texture's linear colour at the hit's
/// interpolated coordinates (s, t) = (1 - u - v) st0 + u st1 + v st2 over the footprint
/// texture_footprint(|point - eye|, pixel_angle, twice the world area, twice the texture area).
/// The lanes' coordinates and footprints are found one by one, then looked up a material at a
/// time, SIMD across the lanes (TextureSet's batch diffuse). Null when no lane is textured.
/// Fills a per-thread buffer: valid until the thread's next call with the same slot. With
/// TextureSlot::emission, the same for the materials' emission maps.
inline const packet::DiffuseTint* tint_lanes(const SurfaceTextures& textures, const TileShadowOrigins& origins,
                                             TextureSlot slot = TextureSlot::diffuse) {
    thread_local packet::DiffuseTint tints[2];
    packet::DiffuseTint& tint = tints[slot == TextureSlot::diffuse ? 0 : 1];
    // The textured lanes' lookups, in lane order; then each material's, gathered in front.
    struct Lookups {
        alignas(64) float s[packet::kPacketRays], t[packet::kPacketRays], width[packet::kPacketRays];
        alignas(64) float rgb[3][packet::kPacketRays];
        // What the footprints are made of: the hit's offset from the eye and twice its
        // triangle's areas in texture and world space.
        alignas(64) float eye_offset[3][packet::kPacketRays];
        alignas(64) float texture_area[packet::kPacketRays], world_area[packet::kPacketRays];
        std::int32_t lane[packet::kPacketRays];
        std::uint32_t material[packet::kPacketRays];
    };
    thread_local Lookups all, group;
    const packet::SurfacePacket& surface = origins.surface;
    tint.lanes = packet::LaneMask{};
    int pending = 0;
    surface.hit.for_each([&](int lane) {
        const auto material = std::uint32_t(surface.material[lane]);
        if (!textures.set.maps(material, slot)) return;
        const ObjectTexcoords& uv = textures.objects[std::size_t(origins.object[lane])];
        if (uv.texcoords.empty()) return;
        const glm::uvec3& corner = uv.triangles[origins.prim[lane]];
        const glm::vec2 st0 = uv.texcoords[corner.x], st1 = uv.texcoords[corner.y], st2 = uv.texcoords[corner.z];
        const float u = origins.bary[0][lane], v = origins.bary[1][lane];
        const glm::vec2 st = (1.0f - u - v) * st0 + u * st1 + v * st2;
        const glm::vec2 e1 = st1 - st0, e2 = st2 - st0;
        all.s[pending] = st.x;
        all.t[pending] = st.y;
        for (int a = 0; a < 3; ++a) all.eye_offset[a][pending] = surface.point[a][lane] - textures.eye[a];
        all.texture_area[pending] = std::abs(e1.x * e2.y - e1.y * e2.x);
        all.world_area[pending] = origins.twice_area[lane];
        all.lane[pending] = lane;
        all.material[pending] = material;
        ++pending;
        tint.lanes.set(lane);
    });
    if (pending == 0) return nullptr;
    footprint_lanes(textures.pixel_angle, pending, all.eye_offset, all.texture_area, all.world_area, all.width);
    // A material at a time (a tile mostly shows one or two): its lookups gathered in front of
    // `group`, the rest kept in `all` for the next round.
    const std::uint32_t first_material = all.material[0];
    if (std::all_of(all.material + 1, all.material + pending,
                    [&](std::uint32_t m) { return m == first_material; })) {
        // One material (the common case): looked up in place.
        float* const rgb[3] = {all.rgb[0], all.rgb[1], all.rgb[2]};
        textures.set.lookup(slot, first_material, std::size_t(pending), all.s, all.t, all.width, rgb);
        for (int k = 0; k < pending; ++k) {
            for (int a = 0; a < 3; ++a) tint.rgb[a][all.lane[k]] = all.rgb[a][k];
        }
        return &tint;
    }
    while (pending > 0) {
        const std::uint32_t material = all.material[0];
        int count = 0, kept = 0;
        for (int k = 0; k < pending; ++k) {
            Lookups& to = all.material[k] == material ? group : all;
            const int at = all.material[k] == material ? count++ : kept++;
            to.s[at] = all.s[k];
            to.t[at] = all.t[k];
            to.width[at] = all.width[k];
            to.lane[at] = all.lane[k];
            to.material[at] = all.material[k];
        }
        pending = kept;
        float* const rgb[3] = {group.rgb[0], group.rgb[1], group.rgb[2]};
        textures.set.lookup(slot, material, std::size_t(count), group.s, group.t, group.width, rgb);
        for (int k = 0; k < count; ++k) {
            for (int a = 0; a < 3; ++a) tint.rgb[a][group.lane[k]] = group.rgb[a][k];
        }
    }
    return &tint;
}

/// The hit buffers' values for a pixel whose ray misses everything.
inline void write_miss(RenderedFrame& out, std::size_t p) {
    out.depth[p] = std::numeric_limits<float>::infinity();
    out.object[p] = -1;
    out.prim[p] = -1;
    out.normal[p] = glm::vec3(0.0f);
}

/// Shadow rays of a batch of hits: those cast, and those left out (TileShadowOrigins::rays_to)
/// because the hit's geometric normal or its shading normal faces away from the light, or the
/// light is dark.
struct ShadowCounts {
    std::size_t cast = 0, back_side = 0, shading_side = 0, dark_light = 0;

    /// Adds light `light`'s rays for `hits` hit lanes, of which rays_to cast `cast_rays` and
    /// left `left` out although their surface faces the light.
    void add(const packet::ShadingLight& light, std::size_t hits, std::size_t cast_rays,
             TileShadowOrigins::LeftOut left) {
        cast += cast_rays;
        if (light.intensity == 0.0f) {
            dark_light += hits;
        } else {
            shading_side += std::size_t(left.shading_away);
            dark_light += std::size_t(left.dark);
            back_side += hits - cast_rays - std::size_t(left.shading_away) - std::size_t(left.dark);
        }
    }
    ShadowCounts& operator+=(const ShadowCounts& o) {
        cast += o.cast;
        back_side += o.back_side;
        shading_side += o.shading_side;
        dark_light += o.dark_light;
        return *this;
    }
};

/// Shades one tile's hit lanes into `colors` (packet::shade, textured by tint_lanes;
/// `visible[l]`: the lanes light l reaches); other lanes are left as they are.
inline void shade_lanes(const TileShading& shading, const TileShadowOrigins& origins,
                        std::span<const packet::LaneMask> visible, packet::ShadedColors& colors) {
    const packet::SurfacePacket& surface = origins.surface;
    if (surface.hit.any()) {
        const packet::DiffuseTint* tint = shading.textures ? tint_lanes(*shading.textures, origins) : nullptr;
        const packet::DiffuseTint* glow = shading.textures && shading.textures->set.any_emission()
                                              ? tint_lanes(*shading.textures, origins, TextureSlot::emission)
                                              : nullptr;
        std::span<const packet::ShadingLight> lights = shading.lights;
        if (!origins.light_lanes.empty() || !origins.light_filter.empty()) {
            // Area lights: each lane lit from its own sample of the light; lanes lit through
            // glass: by what it lets through.
            thread_local std::vector<packet::ShadingLight> sampled;
            sampled.assign(lights.begin(), lights.end());
            for (std::size_t l = 0; l < sampled.size(); ++l) {
                sampled[l].lane_position = origins.light_points(l);
                sampled[l].lane_filter = origins.light_filter_of(l);
            }
            lights = sampled;
        }
        packet::shade(surface, shading.materials, lights, visible, shading.ambient, colors,
                      shading.lanes, tint, glow);
    }
}

/// Writes every pixel of the tile into `out`, whose buffers are already sized: colour (from
/// `colors` on the hit lanes), depth, object, prim and normal, or the background and the miss
/// values.
inline void write_tile(const TileShading& shading, const packet::Tile& tile,
                       const TileShadowOrigins& origins, const std::vector<bvh::InstanceHit>& hits,
                       const packet::ShadedColors& colors, RenderedFrame& out) {
    const packet::SurfacePacket& surface = origins.surface;
    const bool hit_buffers = !out.depth.empty();
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(out.width) + std::size_t(x);
            const int lane = packet::tile_lane(tile, x, y);
            const bool hit = surface.hit.test(lane);
            // A miss's direction is minus its view vector (compute_lanes fills every lane's).
            out.color[p] = hit ? glm::vec3(colors.rgb[0][lane], colors.rgb[1][lane],
                                           colors.rgb[2][lane])
                               : shading.miss(-glm::vec3(surface.view[0][lane], surface.view[1][lane],
                                                         surface.view[2][lane]));
            if (!hit_buffers) continue;
            if (!hit) {
                write_miss(out, p);
                continue;
            }
            const bvh::InstanceHit& h = hits[p];
            out.depth[p] = h.hit.t;
            out.object[p] = std::int32_t(h.object);
            out.prim[p] = std::int32_t(h.hit.prim);
            out.normal[p] = {surface.normal[0][lane], surface.normal[1][lane],
                             surface.normal[2][lane]};
        }
    }
}

/// Shades one tile's hits (shade_lanes) and writes every pixel of the tile into `out`
/// (write_tile). `colors` is scratch.
inline void shade_tile(const TileShading& shading, const packet::Tile& tile,
                       const TileShadowOrigins& origins, std::span<const packet::LaneMask> visible,
                       const std::vector<bvh::InstanceHit>& hits, packet::ShadedColors& colors,
                       RenderedFrame& out) {
    shade_lanes(shading, origins, visible, colors);
    write_tile(shading, tile, origins, hits, colors, out);
}

}  // namespace dynrt::detail
