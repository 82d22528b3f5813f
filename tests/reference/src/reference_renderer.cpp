#include "dynrt/reference/reference_renderer.h"

#include "dynrt/engine/environment_lights.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/trigonometric.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dynrt::reference {

ReferenceShading shading_from(const Scene& scene, const RenderOptions& options) {
    ReferenceShading shading;
    shading.lights = effective_lights(scene, options);
    if (options.environment && options.environment_lights > 0) {
        // The environment's suns, as FramePipeline adds them.
        const std::vector<PointLight> suns = environment_lights(*options.environment, options.environment_lights);
        shading.lights.insert(shading.lights.end(), suns.begin(), suns.end());
    }
    shading.background = glm::dvec3(options.background);
    shading.environment = options.environment;
    shading.ambient = options.ambient;
    shading.max_depth = options.secondary.max_depth;
    shading.cutoff = options.secondary.cutoff;
    shading.smooth_normals = options.smooth_normals;
    if (TextureSet::needed(scene)) shading.textures = std::make_shared<const TextureSet>(scene, false);
    return shading;
}

ReferenceShading shading_from(const Scene& scene, const RenderOptions& options, const anim::PosedScene& posed) {
    ReferenceShading shading = shading_from(scene, options);
    for (PointLight& light : shading.lights) {
        if (light.node < 0) continue;
        // The node's matrix applied in double: the light's origin, and its axis normalised.
        const glm::dmat4& m = posed.node_world.at(std::size_t(light.node));
        light.position = glm::vec3(m * glm::dvec4(glm::dvec3(light.position), 1.0));
        light.direction = glm::vec3(glm::normalize(glm::dmat3(m) * glm::dvec3(light.direction)));
        light.edge_u = glm::vec3(glm::dmat3(m) * glm::dvec3(light.edge_u));
        light.edge_v = glm::vec3(glm::dmat3(m) * glm::dvec3(light.edge_v));
        light.node = -1;
    }
    return shading;
}

namespace {

double max_channel(const glm::dvec3& v) { return std::max({v.x, v.y, v.z}); }

/// A light's falloff at p, l the unit vector toward it (renderer.h "Lights", glTF's
/// KHR_lights_punctual formulas): 1 / d^2 when inverse_square, times clamp(1 - (d / range)^4,
/// 0, 1) when range > 0, times a spot's clamp((cos a - cos outer) / max(0.001, cos inner -
/// cos outer), 0, 1)^2 for the angle a between -l and its axis. 1 for a directional light.
double falloff(const PointLight& light, const glm::dvec3& p, const glm::dvec3& l) {
    if (light.kind == PointLight::Kind::directional) return 1.0;
    double factor = 1.0;
    const double d2 = glm::dot(glm::dvec3(light.position) - p, glm::dvec3(light.position) - p);
    if (light.inverse_square) factor /= d2;
    if (light.range > 0.0f) {
        const double r = d2 / (double(light.range) * double(light.range));
        factor *= std::clamp(1.0 - r * r, 0.0, 1.0);
    }
    if (light.kind == PointLight::Kind::spot) {
        const double cos_inner = std::cos(double(light.inner_cone)), cos_outer = std::cos(double(light.outer_cone));
        const double cone = std::clamp((glm::dot(-l, glm::dvec3(light.direction)) - cos_outer) /
                                           std::max(0.001, cos_inner - cos_outer),
                                       0.0, 1.0);
        factor *= cone * cone;
    }
    return factor;
}

/// One pixel's ray tree (the model and the ambiguity rules are in reference_renderer.h).
class PixelShader {
public:
    PixelShader(const Scene& scene, const ReferenceTracer& tracer, const ReferenceShading& shading,
                const Tolerances& tol, double pixel_angle)
        : scene_(scene), tracer_(tracer), shading_(shading), tol_(tol), pixel_angle_(pixel_angle) {
        // Shadow rays pass through transmissive objects, filtered by their transmittance.
        for (const Object& object : scene.objects) {
            const glm::dvec3 kt(scene.materials.at(object.material).transmittance);
            object_transmittance_.push_back(kt);
            glass_ = glass_ || kt != glm::dvec3(0.0);
        }
        // A term of Whitted's model: with max_depth 0 every surface blocks light.
        if (!glass_ || shading.max_depth == 0) object_transmittance_.clear();
    }

    ReferencePixel shade_camera_ray(const bvh::Ray& ray) {
        pixel_ = ReferencePixel{};
        pixel_.hit = tracer_.closest(ray, tol_);
        if (!pixel_.hit.is_hit()) {
            pixel_.color = miss(glm::dvec3(ray.dir));
            return pixel_;
        }
        const glm::dvec3 org(ray.org), dir(ray.dir);
        eye_ = org;
        const glm::dvec3 p = org + pixel_.hit.t * dir;
        // The camera ray is the renderer's own float ray: no deviation.
        pixel_.color = shade_hit(pixel_.hit, p, dir, 0, glm::dvec3(1.0), 0.0, 0.0);
        return pixel_;
    }

private:
    /// What a ray along `dir` that meets nothing sees.
    glm::dvec3 miss(const glm::dvec3& dir) const {
        return shading_.environment ? glm::dvec3(shading_.environment->radiance(glm::vec3(glm::normalize(dir))))
                                    : shading_.background;
    }

    /// Colour of a secondary ray of depth `depth` >= 1 with path weight `weight`.
    glm::dvec3 trace(const RayD& ray, TriangleRef from, int depth, const glm::dvec3& weight,
                     const RayDeviation& deviation) {
        const ReferenceHit hit = tracer_.closest_leaving(ray, from, deviation, tol_);
        if (hit.ambiguity != Ambiguity::kNone) pixel_.shading_ambiguous = true;
        if (!hit.is_hit()) return miss(ray.dir);
        const glm::dvec3 p = ray.org + hit.t * ray.dir;
        const double lateral = deviation.lateral + hit.t * deviation.angle;
        return shade_hit(hit, p, ray.dir, depth, weight, lateral, deviation.angle);
    }

    /// The reflected and refracted weights and directions at a hit (the model at the top of
    /// reference_renderer.h), made with `normal`.
    struct Split {
        glm::dvec3 wr{0.0}, wt{0.0};
        glm::dvec3 reflected{0.0}, refracted{0.0};
        double cos_i = 0.0, cos_t = 0.0, sin2_t = 0.0;
        bool refracts = false, total_internal = false;
    };

    static Split split_with(const Material& material, const glm::dvec3& d, const glm::dvec3& normal,
                            double eta) {
        Split s;
        s.cos_i = -glm::dot(d, normal);
        s.reflected = glm::normalize(d - 2.0 * glm::dot(d, normal) * normal);
        const glm::dvec3 kr(material.reflectance), kt(material.transmittance);
        s.wr = kr;
        if (kt == glm::dvec3(0.0)) return s;
        s.sin2_t = eta * eta * (1.0 - s.cos_i * s.cos_i);
        if (s.sin2_t > 1.0) {
            s.wr = kr + kt;
            s.total_internal = true;
            return s;
        }
        s.cos_t = std::sqrt(1.0 - s.sin2_t);
        // Unpolarised Fresnel reflectance; a ray in the surface's plane (both cosines 0,
        // flagged by the caller) reflects fully.
        const double s_den = eta * s.cos_i + s.cos_t, p_den = s.cos_i + eta * s.cos_t;
        const double rs = s_den > 0.0 ? (eta * s.cos_i - s.cos_t) / s_den : 1.0;
        const double rp = p_den > 0.0 ? (s.cos_i - eta * s.cos_t) / p_den : 1.0;
        const double fresnel = 0.5 * (rs * rs + rp * rp);
        s.wr = kr + fresnel * kt;
        s.wt = (1.0 - fresnel) * kt;
        s.refracted = glm::normalize(eta * d + (eta * s.cos_i - s.cos_t) * normal);
        s.refracts = true;
        return s;
    }

    /// The shading normal at `hit` (facing geometric normal n): its triangle's vertex normals
    /// interpolated with the exact barycentrics, normalised and turned to n's side, or n
    /// without them (flat shading, none posed, or too short). `rate` gets a bound on how fast
    /// it turns per unit of distance along the surface (0 for n), for the deviation budget.
    glm::dvec3 shading_normal(TriangleRef tri, const ReferenceHit& hit, const glm::dvec3& n, double& rate) {
        rate = 0.0;
        glm::dvec3 vn[3];
        if (!shading_.smooth_normals || !tracer_.vertex_normals(tri, vn)) return n;
        const glm::dvec3 s = (1.0 - hit.u - hit.v) * vn[0] + hit.u * vn[1] + hit.v * vn[2];
        const double length2 = glm::dot(s, s);
        // The renderer's threshold, in float: near it either normal may be taken.
        if (std::abs(length2 - double(kMinShadingNormalLength2)) < double(kMinShadingNormalLength2)) {
            pixel_.shading_ambiguous = true;
        }
        if (!(length2 > double(kMinShadingNormalLength2))) return n;
        const glm::dvec3 unit = s / std::sqrt(length2);
        const double side = glm::dot(unit, n);
        if (std::abs(side) < tol_.terminator) pixel_.shading_ambiguous = true;
        // |grad u| = |v2 - v0| / |N| and |grad v| = |v1 - v0| / |N|, N = (v1 - v0) x (v2 - v0).
        glm::dvec3 v[3];
        tracer_.vertices(tri, v);
        const double twice_area = glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));
        rate = (glm::length(vn[1] - vn[0]) * glm::length(v[2] - v[0]) +
                glm::length(vn[2] - vn[0]) * glm::length(v[1] - v[0])) /
               (twice_area * std::sqrt(length2));
        return side < 0.0 ? -unit : unit;
    }

    /// Colour at hit `hit` (point p) of a ray along `dir` (any length) of depth `depth` and
    /// path weight `weight`, whose float counterpart deviates sideways by `lateral` at the hit
    /// and in direction by `angle`.
    glm::dvec3 shade_hit(const ReferenceHit& hit, const glm::dvec3& p, const glm::dvec3& dir,
                         int depth, const glm::dvec3& weight, double lateral, double angle) {
        const TriangleRef tri{hit.object, hit.prim};
        const glm::dvec3 winding = tracer_.normal(tri);
        const glm::dvec3 n = glm::dot(winding, dir) > 0.0 ? -winding : winding;
        if (depth == 0) pixel_.normal = n;
        const glm::dvec3 view = -glm::normalize(dir);
        const double cos_g = glm::dot(view, n);
        // Where the float ray may have met the surface instead: its sideways deviation seen
        // on the surface (a graze is flagged below, so its clamp only bounds the work).
        const double point_error = lateral / std::max(cos_g, tol_.terminator);
        double normal_rate = 0.0;
        const glm::dvec3 ns = shading_normal(tri, hit, n, normal_rate);

        const Object& object = scene_.objects.at(static_cast<std::size_t>(hit.object));
        const Material& material = scene_.materials.at(object.material);
        glm::dvec3 kd(material.diffuse);
        const glm::dvec3 ks(material.specular);
        const double shininess = material.shininess;
        // The texture's colour, and how much it may differ where the float renderer looks.
        double texture_change = 0.0;
        glm::dvec3 tint(1.0);  // the texture's colour, 1 where there is none
        const double base_kd_max = max_channel(kd);
        glm::dvec3 glow(1.0);  // the emission map's colour, 1 where there is none
        if (shading_.textures && shading_.textures->maps(object.material, TextureSlot::emission) &&
            !object.mesh.texcoords.empty()) {
            const glm::uvec3& corner = object.mesh.triangles.at(static_cast<std::size_t>(hit.prim));
            const glm::dvec2 st0(object.mesh.texcoords[corner.x]), st1(object.mesh.texcoords[corner.y]),
                st2(object.mesh.texcoords[corner.z]);
            const glm::dvec2 st = (1.0 - hit.u - hit.v) * st0 + hit.u * st1 + hit.v * st2;
            const glm::dvec2 e1 = st1 - st0, e2 = st2 - st0;
            glm::dvec3 v[3];
            tracer_.vertices(tri, v);
            const float width = texture_footprint(float(glm::length(p - eye_)), float(pixel_angle_),
                                                  float(glm::length(glm::cross(v[1] - v[0], v[2] - v[0]))),
                                                  float(std::abs(e1.x * e2.y - e1.y * e2.x)));
            glow = glm::dvec3(shading_.textures->emission(object.material, glm::vec2(st), width));
        }
        if (shading_.textures && shading_.textures->maps(object.material) && !object.mesh.texcoords.empty()) {
            const glm::uvec3& corner = object.mesh.triangles.at(static_cast<std::size_t>(hit.prim));
            const glm::dvec2 st0(object.mesh.texcoords[corner.x]), st1(object.mesh.texcoords[corner.y]),
                st2(object.mesh.texcoords[corner.z]);
            const glm::dvec2 st = (1.0 - hit.u - hit.v) * st0 + hit.u * st1 + hit.v * st2;
            const glm::dvec2 e1 = st1 - st0, e2 = st2 - st0;
            const double twice_texture = std::abs(e1.x * e2.y - e1.y * e2.x);
            glm::dvec3 v[3];
            tracer_.vertices(tri, v);
            const double twice_world = glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));
            const float width = texture_footprint(float(glm::length(p - eye_)), float(pixel_angle_),
                                                  float(twice_world), float(twice_texture));
            const glm::vec3 texel = shading_.textures->diffuse(object.material, glm::vec2(st), width);
            kd *= glm::dvec3(texel);
            tint = glm::dvec3(texel);
            const double st_error = std::sqrt(twice_texture / std::max(twice_world, 1e-300)) *
                                    (point_error + tol_.barycentric_rel * tracer_.scale_at(p));
            for (const glm::dvec2 offset : {glm::dvec2(st_error, 0.0), glm::dvec2(-st_error, 0.0),
                                            glm::dvec2(0.0, st_error), glm::dvec2(0.0, -st_error)}) {
                const glm::vec3 there = shading_.textures->diffuse(object.material, glm::vec2(st + offset), width);
                texture_change = std::max(texture_change, max_channel(glm::abs(glm::dvec3(there - texel))));
            }
        }

        // The ambient term: the material's own colour (BART's am times ka) or a fraction of kd.
        glm::dvec3 color = material.ambient ? glm::dvec3(*material.ambient) * tint : shading_.ambient * kd;
        // How much the colour may change per unit of turn of the shading normal: for each
        // lit light, I (kd + 4 p ks (r.v)^(p - 1)), as |d(s.l)| <= |ds| and |d(r.v)| <= 4 |ds|.
        double sensitivity = 0.0, diffuse_light = shading_.ambient;
        const double kd_max = max_channel(kd), ks_max = max_channel(ks);
        for (const PointLight& light : shading_.lights) {
            // The unit vector toward the light, and the far end of the shadow segment: a
            // directional light's lies so far along it that it leaves every scene.
            const bool directional = light.kind == PointLight::Kind::directional;
            const glm::dvec3 light_pos = directional
                ? p - glm::dvec3(light.direction) * (1e7 * (1.0 + glm::length(p) + tracer_.scale_at(p)))
                : glm::dvec3(light.position);
            const glm::dvec3 l = directional ? -glm::dvec3(light.direction) : glm::normalize(light_pos - p);
            const double intensity = double(light.intensity) * falloff(light, p, l);
            if (!(intensity > 0.0)) continue;
            // The shadow ray is cast by the geometric normal's side, the terms lit with the
            // shading normal's (continuous at its own n . l = 0).
            const double facing = glm::dot(n, l);
            if (std::abs(facing) < tol_.terminator) pixel_.shading_ambiguous = true;
            if (!(facing > 0.0)) continue;
            const ReferenceOcclusion occlusion =
                tracer_.occluded(p, light_pos, tri, tol_, point_error, object_transmittance_);
            if (occlusion.ambiguous) pixel_.shading_ambiguous = true;
            if (occlusion.occluded) continue;
            const double n_dot_l = glm::dot(ns, l);
            if (!(n_dot_l > 0.0)) continue;
            const glm::dvec3 r = 2.0 * n_dot_l * ns - l;
            const double r_dot_v = std::max(0.0, glm::dot(r, view));
            const glm::dvec3 light_color = intensity * glm::dvec3(light.color) * occlusion.transmittance;
            color += light_color * (kd * n_dot_l + ks * std::pow(r_dot_v, shininess));
            const double brightest = max_channel(light_color);
            diffuse_light += brightest * n_dot_l;
            sensitivity += brightest *
                           (kd_max + 4.0 * shininess * ks_max * std::pow(r_dot_v, std::max(shininess - 1.0, 0.0)));
        }
        color += glm::dvec3(material.emission) * glow;  // after the lights, as packet::shade adds it
        // Where the float renderer takes its shading normal: barycentric_rel * scale away on
        // the same ray, plus point_error for a deviating secondary ray.
        const double normal_error = normal_rate * (point_error + tol_.barycentric_rel * tracer_.scale_at(p));
        if (max_channel(weight) * sensitivity * normal_error > tol_.shading_color) pixel_.shading_ambiguous = true;
        if (max_channel(weight) * base_kd_max * texture_change * diffuse_light > tol_.shading_color) {
            pixel_.shading_ambiguous = true;
        }
        if (depth >= shading_.max_depth || !material.traces_secondary()) return color;

        // ---- Whitted's secondary rays --------------------------------------------------------
        const glm::dvec3 d = -view;
        if (cos_g < tol_.terminator) pixel_.shading_ambiguous = true;
        const bool entering = glm::dot(winding, d) < 0.0;
        const double ior = material.ior;
        const double eta = entering ? 1.0 / ior : ior;
        // With the shading normal, unless a direction would leave the wrong side of the
        // geometric surface (the renderer's shading_split_holds); near that boundary either
        // split may be made.
        Split split = split_with(material, d, ns, eta);
        if (ns != n) {
            const double into = glm::dot(split.reflected, n);
            const double out = split.refracts ? glm::dot(split.refracted, n) : -1.0;
            if (std::abs(split.cos_i) < tol_.terminator || std::abs(into) < tol_.terminator ||
                std::abs(out) < tol_.terminator) {
                pixel_.shading_ambiguous = true;
            }
            if (!(split.cos_i > 0.0 && into > 0.0 && out < 0.0)) split = split_with(material, d, n, eta);
        }
        if (split.cos_i < tol_.terminator) pixel_.shading_ambiguous = true;
        if (material.transmittance != glm::vec3(0.0f)) {
            if (std::abs(split.sin2_t - 1.0) < tol_.critical) pixel_.shading_ambiguous = true;
            const std::uint32_t bit = depth < 32 ? 1u << depth : 0u;
            if (split.total_internal) pixel_.total_internal_at |= bit;
            if (split.refracts) pixel_.refracted_at |= bit;
        }
        const glm::dvec3 wr = split.wr, wt = split.wt;
        const double cos_i = split.cos_i, cos_t = split.cos_t;

        // The float renderer starts its rays off its own hit point, pushed off the surface.
        const double push = tol_.shadow_rel * (tracer_.scale_at(p) + glm::length(p));
        // Its shading normal is interpolated at its own hit point (normal_error above);
        // reflecting turns the direction by up to 4 times the normal's error
        // (|d(d - 2 (d.n) n)| <= 4 |dn| for unit d and n).
        const double normal_angle = 4.0 * normal_error;
        auto traced = [&](const glm::dvec3& path_weight) {
            const double w = max_channel(path_weight);
            if (std::abs(w - shading_.cutoff) <= tol_.cutoff_rel * shading_.cutoff) {
                pixel_.shading_ambiguous = true;
            }
            return w >= shading_.cutoff;
        };
        if (traced(weight * wr)) {
            const RayD reflected{p, split.reflected};
            const RayDeviation deviation{push + lateral, angle + tol_.direction_rel + normal_angle,
                                         push + point_error};
            color += wr * trace(reflected, tri, depth + 1, weight * wr, deviation);
        }
        if (split.refracts && traced(weight * wt)) {
            const RayD refracted{p, split.refracted};
            // How much refraction magnifies angles (d theta_t / d theta_i = eta cos_i / cos_t in
            // the plane of incidence, eta across it) and sideways offsets (cos_t / cos_i).
            const double magnify =
                std::max({1.0, eta, eta * cos_i / std::max(cos_t, tol_.terminator)});
            const double widen = std::max(1.0, cos_t / std::max(cos_i, tol_.terminator));
            const RayDeviation deviation{push + lateral * widen,
                                         magnify * (angle + tol_.direction_rel + normal_angle),
                                         push + point_error};
            color += wt * trace(refracted, tri, depth + 1, weight * wt, deviation);
        }
        return color;
    }

    const Scene& scene_;
    /// Per object, its material's transmittance; empty when nothing is transmissive.
    std::vector<glm::dvec3> object_transmittance_;
    bool glass_ = false;
    const ReferenceTracer& tracer_;
    const ReferenceShading& shading_;
    const Tolerances& tol_;
    /// Radians per pixel (2 tan(fov_y / 2) / height) and the camera ray's origin: the texture
    /// footprint's cone.
    double pixel_angle_;
    glm::dvec3 eye_{0.0};
    ReferencePixel pixel_;
};

ReferencePixel shade(const Scene& scene, const ReferenceTracer& tracer, const bvh::Ray& ray,
                     const ReferenceShading& shading, const Tolerances& tol, double pixel_angle) {
    return PixelShader(scene, tracer, shading, tol, pixel_angle).shade_camera_ray(ray);
}

/// The texture footprint's angle per pixel, as FramePipeline computes it (in float there).
double pixel_angle_of(const Camera& camera, int height) {
    return double(2.0f * std::tan(0.5f * glm::radians(camera.fov_y_deg)) / float(std::max(height, 1)));
}

}  // namespace

ReferenceFrame render_reference(const Scene& scene, const ReferenceTracer& tracer,
                                const Camera& camera, int width, int height,
                                const ReferenceShading& shading, const Tolerances& tol) {
    const packet::PinholeRays rays(camera, width, height);  // validates camera and size
    const double pixel_angle = pixel_angle_of(camera, height);
    ReferenceFrame frame;
    frame.width = width;
    frame.height = height;
    frame.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int x = 0; x < width; ++x) {
                frame.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                             static_cast<std::size_t>(x)] =
                    shade(scene, tracer, rays.ray(x, y), shading, tol, pixel_angle);
            }
        }
    });
    return frame;
}

std::vector<ReferencePixel> render_reference_pixels(const Scene& scene,
                                                    const ReferenceTracer& tracer,
                                                    const Camera& camera, int width, int height,
                                                    std::span<const PixelCoord> pixels,
                                                    const ReferenceShading& shading,
                                                    const Tolerances& tol) {
    const packet::PinholeRays rays(camera, width, height);  // validates camera and size
    const double pixel_angle = pixel_angle_of(camera, height);
    for (const PixelCoord& p : pixels) {
        if (p.x < 0 || p.x >= width || p.y < 0 || p.y >= height) {
            throw std::out_of_range("render_reference_pixels: pixel (" + std::to_string(p.x) +
                                    "," + std::to_string(p.y) + ") is outside the " +
                                    std::to_string(width) + "x" + std::to_string(height) +
                                    " image");
        }
    }
    std::vector<ReferencePixel> out(pixels.size());
    // Brute force costs about the same per pixel: small grains balance well.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              out[i] = shade(scene, tracer, rays.ray(pixels[i].x, pixels[i].y),
                                             shading, tol, pixel_angle);
                          }
                      });
    return out;
}

}  // namespace dynrt::reference
