#pragma once
// The reference renderer: the same camera rays and the same Phong formula as dynrt::Renderer
// (renderer.h, top comment), evaluated in double precision on the exact reference hits, with a
// per-pixel note of which parts of the answer a float renderer may legitimately get otherwise.

#include "dynrt/reference/reference_tracer.h"

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace dynrt::reference {

/// What the shading formula needs besides the geometry.
struct ReferenceShading {
    std::vector<PointLight> lights;
    glm::dvec3 background{0.0};
    double ambient = 0.0;
};

/// The lights, background and ambient a dynrt::Renderer with `options` uses on `scene`
/// (effective_lights decides the default light).
ReferenceShading shading_from(const Scene& scene, const RenderOptions& options);

struct ReferencePixel {
    ReferenceHit hit;
    glm::dvec3 color{0.0};
    /// Unit geometric normal of the hit triangle, turned to face the eye; 0 on a miss.
    glm::dvec3 normal{0.0};
    /// Some light's contribution is ambiguous: its shadow ray is ambiguous, or n . l is within
    /// the terminator tolerance of 0. Colour comparisons skip such pixels.
    bool shading_ambiguous = false;
};

/// Row-major, y = 0 the top row, like RenderedFrame.
struct ReferenceFrame {
    int width = 0;
    int height = 0;
    std::vector<ReferencePixel> pixels;

    /// Pixel (x, y); precondition 0 <= x < width, 0 <= y < height.
    const ReferencePixel& at(int x, int y) const {
        return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(x)];
    }
};

/// Renders `width` x `height` pixels of `scene` (whose posed geometry `tracer` was built from)
/// through `camera`, with packet::PinholeRays' float rays. At a hit: n the unit geometric normal facing
/// the eye, p = org + t dir from the exact t, and for each light with n . l > 0 a shadow
/// segment from p to the light excluding the hit triangle (ReferenceTracer::occluded).
/// Rows run in parallel on the caller's oneTBB arena. Throws std::invalid_argument for a
/// degenerate camera or image, std::out_of_range for an object's material index out of range.
ReferenceFrame render_reference(const Scene& scene, const ReferenceTracer& tracer,
                                const Camera& camera, int width, int height,
                                const ReferenceShading& shading, const Tolerances& tol = {});

/// A pixel of an image, x to the right, y = 0 the top row.
struct PixelCoord {
    int x = 0;
    int y = 0;
};

/// The reference for the listed pixels of a `width` x `height` image only, one ReferencePixel
/// per entry of `pixels` in the same order, each exactly as render_reference computes it (same
/// rays, same shading). For images too large to render in full by brute force. Pixels run in
/// parallel on the caller's oneTBB arena. Throws as render_reference does, and
/// std::out_of_range for a pixel outside the image.
std::vector<ReferencePixel> render_reference_pixels(const Scene& scene,
                                                    const ReferenceTracer& tracer,
                                                    const Camera& camera, int width, int height,
                                                    std::span<const PixelCoord> pixels,
                                                    const ReferenceShading& shading,
                                                    const Tolerances& tol = {});

}  // namespace dynrt::reference
