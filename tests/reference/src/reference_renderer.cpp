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
    return shading;
}

namespace {

ReferencePixel shade(const Scene& scene, const ReferenceTracer& tracer, const bvh::Ray& ray,
                     const ReferenceShading& shading, const Tolerances& tol) {
    ReferencePixel pixel;
    pixel.hit = tracer.closest(ray, tol);
    if (!pixel.hit.is_hit()) {
        pixel.color = shading.background;
        return pixel;
    }
    const TriangleRef tri{pixel.hit.object, pixel.hit.prim};
    const glm::dvec3 org(ray.org), dir(ray.dir);
    const glm::dvec3 p = org + pixel.hit.t * dir;
    glm::dvec3 n = tracer.normal(tri);
    if (glm::dot(n, dir) > 0.0) n = -n;
    pixel.normal = n;
    const glm::dvec3 view = -glm::normalize(dir);

    const Object& object = scene.objects.at(static_cast<std::size_t>(pixel.hit.object));
    const Material& material = scene.materials.at(object.material);
    const glm::dvec3 kd(material.diffuse), ks(material.specular);
    const double shininess = material.shininess;

    glm::dvec3 color = shading.ambient * kd;
    for (const PointLight& light : shading.lights) {
        const glm::dvec3 light_pos(light.position);
        const glm::dvec3 l = glm::normalize(light_pos - p);
        const double n_dot_l = glm::dot(n, l);
        if (std::abs(n_dot_l) < tol.terminator) pixel.shading_ambiguous = true;
        if (!(n_dot_l > 0.0)) continue;
        const ReferenceOcclusion occlusion = tracer.occluded(p, light_pos, tri, tol);
        if (occlusion.ambiguous) pixel.shading_ambiguous = true;
        if (occlusion.occluded) continue;
        const glm::dvec3 r = 2.0 * n_dot_l * n - l;
        const double r_dot_v = std::max(0.0, glm::dot(r, view));
        color += double(light.intensity) * (kd * n_dot_l + ks * std::pow(r_dot_v, shininess));
    }
    pixel.color = color;
    return pixel;
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
