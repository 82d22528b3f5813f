#include "dynrt/reference/reference_renderer.h"

#include <glm/geometric.hpp>

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
    shading.background = glm::dvec3(options.background);
    shading.ambient = options.ambient;
    shading.max_depth = options.secondary.max_depth;
    shading.cutoff = options.secondary.cutoff;
    return shading;
}

namespace {

double max_channel(const glm::dvec3& v) { return std::max({v.x, v.y, v.z}); }

/// One pixel's ray tree (the model and the ambiguity rules are in reference_renderer.h).
class PixelShader {
public:
    PixelShader(const Scene& scene, const ReferenceTracer& tracer, const ReferenceShading& shading,
                const Tolerances& tol)
        : scene_(scene), tracer_(tracer), shading_(shading), tol_(tol) {}

    ReferencePixel shade_camera_ray(const bvh::Ray& ray) {
        pixel_ = ReferencePixel{};
        pixel_.hit = tracer_.closest(ray, tol_);
        if (!pixel_.hit.is_hit()) {
            pixel_.color = shading_.background;
            return pixel_;
        }
        const glm::dvec3 org(ray.org), dir(ray.dir);
        const glm::dvec3 p = org + pixel_.hit.t * dir;
        // The camera ray is the renderer's own float ray: no deviation.
        pixel_.color = shade_hit(pixel_.hit, p, dir, 0, glm::dvec3(1.0), 0.0, 0.0);
        return pixel_;
    }

private:
    /// Colour of a secondary ray of depth `depth` >= 1 with path weight `weight`.
    glm::dvec3 trace(const RayD& ray, TriangleRef from, int depth, const glm::dvec3& weight,
                     const RayDeviation& deviation) {
        const ReferenceHit hit = tracer_.closest_leaving(ray, from, deviation, tol_);
        if (hit.ambiguity != Ambiguity::kNone) pixel_.shading_ambiguous = true;
        if (!hit.is_hit()) return shading_.background;
        const glm::dvec3 p = ray.org + hit.t * ray.dir;
        const double lateral = deviation.lateral + hit.t * deviation.angle;
        return shade_hit(hit, p, ray.dir, depth, weight, lateral, deviation.angle);
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
        const double cos_i = glm::dot(view, n);
        // Where the float ray may have met the surface instead: its sideways deviation seen
        // on the surface (a graze is flagged below, so its clamp only bounds the work).
        const double point_error = lateral / std::max(cos_i, tol_.terminator);

        const Object& object = scene_.objects.at(static_cast<std::size_t>(hit.object));
        const Material& material = scene_.materials.at(object.material);
        const glm::dvec3 kd(material.diffuse), ks(material.specular);
        const double shininess = material.shininess;

        glm::dvec3 color = shading_.ambient * kd;
        for (const PointLight& light : shading_.lights) {
            const glm::dvec3 light_pos(light.position);
            const glm::dvec3 l = glm::normalize(light_pos - p);
            const double n_dot_l = glm::dot(n, l);
            if (std::abs(n_dot_l) < tol_.terminator) pixel_.shading_ambiguous = true;
            if (!(n_dot_l > 0.0)) continue;
            const ReferenceOcclusion occlusion =
                tracer_.occluded(p, light_pos, tri, tol_, point_error);
            if (occlusion.ambiguous) pixel_.shading_ambiguous = true;
            if (occlusion.occluded) continue;
            const glm::dvec3 r = 2.0 * n_dot_l * n - l;
            const double r_dot_v = std::max(0.0, glm::dot(r, view));
            color += double(light.intensity) * (kd * n_dot_l + ks * std::pow(r_dot_v, shininess));
        }
        if (depth >= shading_.max_depth || !material.traces_secondary()) return color;

        // ---- Whitted's secondary rays --------------------------------------------------------
        const glm::dvec3 d = -view;
        if (cos_i < tol_.terminator) pixel_.shading_ambiguous = true;
        const bool entering = glm::dot(winding, d) < 0.0;
        const double ior = material.ior;
        const double eta = entering ? 1.0 / ior : ior;
        const glm::dvec3 kr(material.reflectance), kt(material.transmittance);
        glm::dvec3 wr = kr, wt(0.0);
        double cos_t = 0.0;
        bool refracts = false;
        if (kt != glm::dvec3(0.0)) {
            const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
            if (std::abs(sin2_t - 1.0) < tol_.critical) pixel_.shading_ambiguous = true;
            const std::uint32_t bit = depth < 32 ? 1u << depth : 0u;
            if (sin2_t > 1.0) {
                wr = kr + kt;
                pixel_.total_internal_at |= bit;
            } else {
                cos_t = std::sqrt(1.0 - sin2_t);
                // Unpolarised Fresnel reflectance; a ray in the surface's plane (both cosines
                // 0, flagged above) reflects fully.
                const double s_den = eta * cos_i + cos_t, p_den = cos_i + eta * cos_t;
                const double rs = s_den > 0.0 ? (eta * cos_i - cos_t) / s_den : 1.0;
                const double rp = p_den > 0.0 ? (cos_i - eta * cos_t) / p_den : 1.0;
                const double fresnel = 0.5 * (rs * rs + rp * rp);
                wr = kr + fresnel * kt;
                wt = (1.0 - fresnel) * kt;
                refracts = true;
                pixel_.refracted_at |= bit;
            }
        }

        // The float renderer starts its rays off its own hit point, pushed off the surface.
        const double push = tol_.shadow_rel * (tracer_.scale_at(p) + glm::length(p));
        auto traced = [&](const glm::dvec3& path_weight) {
            const double w = max_channel(path_weight);
            if (std::abs(w - shading_.cutoff) <= tol_.cutoff_rel * shading_.cutoff) {
                pixel_.shading_ambiguous = true;
            }
            return w >= shading_.cutoff;
        };
        if (traced(weight * wr)) {
            const RayD reflected{p, glm::normalize(d - 2.0 * glm::dot(d, n) * n)};
            const RayDeviation deviation{push + lateral, angle + tol_.direction_rel,
                                         push + point_error};
            color += wr * trace(reflected, tri, depth + 1, weight * wr, deviation);
        }
        if (refracts && traced(weight * wt)) {
            const RayD refracted{p, glm::normalize(eta * d + (eta * cos_i - cos_t) * n)};
            // How much refraction magnifies angles (d theta_t / d theta_i = eta cos_i / cos_t in
            // the plane of incidence, eta across it) and sideways offsets (cos_t / cos_i).
            const double magnify =
                std::max({1.0, eta, eta * cos_i / std::max(cos_t, tol_.terminator)});
            const double widen = std::max(1.0, cos_t / std::max(cos_i, tol_.terminator));
            const RayDeviation deviation{push + lateral * widen,
                                         magnify * (angle + tol_.direction_rel),
                                         push + point_error};
            color += wt * trace(refracted, tri, depth + 1, weight * wt, deviation);
        }
        return color;
    }

    const Scene& scene_;
    const ReferenceTracer& tracer_;
    const ReferenceShading& shading_;
    const Tolerances& tol_;
    ReferencePixel pixel_;
};

ReferencePixel shade(const Scene& scene, const ReferenceTracer& tracer, const bvh::Ray& ray,
                     const ReferenceShading& shading, const Tolerances& tol) {
    return PixelShader(scene, tracer, shading, tol).shade_camera_ray(ray);
}

}  // namespace

ReferenceFrame render_reference(const Scene& scene, const ReferenceTracer& tracer,
                                const Camera& camera, int width, int height,
                                const ReferenceShading& shading, const Tolerances& tol) {
    const packet::PinholeRays rays(camera, width, height);  // validates camera and size
    ReferenceFrame frame;
    frame.width = width;
    frame.height = height;
    frame.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int x = 0; x < width; ++x) {
                frame.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                             static_cast<std::size_t>(x)] =
                    shade(scene, tracer, rays.ray(x, y), shading, tol);
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
                                             shading, tol);
                          }
                      });
    return out;
}

}  // namespace dynrt::reference
