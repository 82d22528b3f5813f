#pragma once
// The reference renderer: the same camera rays, the same Phong formula and the same Whitted
// reflection and refraction rays as dynrt::Renderer (renderer.h, top comment), evaluated in
// double precision on the exact reference hits, with a per-pixel note of which parts of the
// answer a float renderer may legitimately get otherwise.
//
// The model, in double. A hit of a ray with unit direction d at distance t lies at the exact
// point p = org + t d; n is the triangle's unit winding normal N, negated when it points along
// d. The shading normal s (renderer.h, "Shading normals"), with smooth_normals and the posed
// vertex normals the ReferenceTracer holds: the vertex normals interpolated with the exact
// barycentrics, normalised, negated when s . n < 0, or n itself when there are none or the
// interpolated squared length is at most kMinShadingNormalLength2. A light is shadow-tested
// where n . l > 0 and adds its Phong terms, made with s, where also s . l > 0. Shadow segments
// are as for camera hits (ReferenceTracer::occluded from p, excluding the hit triangle). When
// the ray's depth is below max_depth and the material has reflectance kr or transmittance kt:
// the ray enters when N . d < 0 (eta = 1 / ior) and leaves otherwise (eta = ior); the split
// below is made with s, or with n where that split fails (d . s >= 0, or the reflected
// direction has . n <= 0, or the refracted one . n >= 0); with that normal m,
// cos_i = -d . m, sin2_t = eta^2 (1 - cos_i^2). kt = 0 gives wr = kr;
// sin2_t > 1 gives wr = kr + kt (total internal reflection); otherwise, with cos_t =
// sqrt(1 - sin2_t), the unpolarised Fresnel reflectance F = (rs^2 + rp^2) / 2, rs =
// (eta cos_i - cos_t) / (eta cos_i + cos_t), rp = (cos_i - eta cos_t) / (cos_i + eta cos_t),
// gives wr = kr + F kt and wt = (1 - F) kt. The reflected ray normalize(d - 2 (d . m) m) and
// the refracted ray normalize(eta d + (eta cos_i - cos_t) m) start at p itself and exclude the
// hit triangle (ReferenceTracer::closest_leaving) where the renderer offsets its origins; each
// is traced when the product of the weights along its path has a channel >= cutoff, and adds
// its weight times its colour (the background on a miss).
//
// Ambiguity. ReferencePixel::hit tells how far the camera ray's hit is determined, as before;
// shading_ambiguous is set when anything else in the pixel's ray tree is open:
//  - at any hit of the tree, a light's n . l within Tolerances::terminator of 0, or its shadow
//    segment ambiguous;
//  - a secondary ray's closest hit not kNone (near an edge, a graze, two layers, anything
//    within its origin zone), judged with the deviation its float counterpart may have;
//  - a hit spawning secondary rays at grazing incidence (cos_i < terminator), or on a
//    transmissive surface with |sin2_t - 1| < Tolerances::critical (the critical angle);
//  - a secondary ray whose path weight's largest channel lies within cutoff_rel * cutoff of
//    the cutoff;
//  - textures: a hit where the texture's colour, looked up within the distance the float hit
//    point may lie off the exact one (as for the shading normal below, in texture units),
//    changes by enough to move the colour, weighted by the path, by more than
//    Tolerances::shading_color;
//  - smooth shading: an interpolated normal near kMinShadingNormalLength2 or nearly in the
//    surface (|s . n| < terminator); the split's test within terminator of its boundary
//    (|d . s|, |reflected . n|, |refracted . n|); and a hit where the shading normal may turn,
//    between the exact hit point and the float one (Tolerances::barycentric_rel of the scale,
//    plus a secondary ray's deviation seen on the surface), enough to move the colour,
//    weighted by the path, by more than Tolerances::shading_color (the turn is bounded by the
//    vertex normals' spread over the triangle's heights; the colour's sensitivity by
//    sum I (kd + 4 shininess ks (r.v)^(shininess - 1))).
// How far a float secondary ray may deviate from the exact one (RayDeviation, beyond the float
// test's own resolution): camera rays not at all, as the reference traces the renderer's own
// float rays. At a hit of a ray deviating sideways by L = lateral + t angle there, the float
// hit point may lie L / cos_i from p along the surface, and the shadow segments widen their
// origin tolerance by that much. A child ray then deviates sideways by the renderer's offset
// (Tolerances::shadow_rel * (scale + |p|), as for shadow rays) plus L (reflection keeps the
// sideways offset of parallel rays, refraction scales it by up to cos_t / cos_i), its origin
// by the offset plus L / cos_i along it, and its direction by the parent's angle plus
// Tolerances::direction_rel, both times refraction's magnification max(1, eta, eta cos_i /
// cos_t) for a refracted ray; with smooth normals, also by 4 times the shading normal's possible
// turn (|d(reflected)| <= 4 |ds|), magnified alike. Errors compound along a path, so deep
// bounces are judged more loosely. With max_depth = 0, or no reflective or transmissive
// material, every pixel is what the Phong-only reference gave, bit for bit.

#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/texture_set.h"
#include "dynrt/scene/scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace dynrt::reference {

/// What the shading formula needs besides the geometry.
struct ReferenceShading {
    std::vector<PointLight> lights;
    glm::dvec3 background{0.0};
    /// What rays that miss see by direction (TraceSettings::environment, the renderer's own
    /// lookup at the exact direction rounded to float), or null: the background.
    std::shared_ptr<const EnvironmentMap> environment;
    double ambient = 0.0;
    /// Deepest secondary ray (SecondaryRays::max_depth, same default): 0 shades camera hits
    /// only, as before secondary rays.
    int max_depth = SecondaryRays{}.max_depth;
    /// A secondary ray is traced when a channel of its path weight is >= this
    /// (SecondaryRays::cutoff, same default).
    double cutoff = SecondaryRays{}.cutoff;
    /// Shade with the posed vertex normals where the tracer has them
    /// (TraceSettings::smooth_normals, same default); false: every hit with its geometric
    /// normal.
    bool smooth_normals = TraceSettings{}.smooth_normals;
    /// The scene's textures (the renderer's own lookups, dynrt/engine/texture_set.h), or null
    /// when no material maps one: a textured material's kd is its diffuse colour times the
    /// texture's colour at the exact hit's texture coordinates, over the footprint
    /// texture_footprint gives at the exact distance from the eye.
    std::shared_ptr<const TextureSet> textures;
};

/// The lights, background, ambient, secondary-ray settings, normals and textures a
/// dynrt::Renderer with `options` uses on `scene` (effective_lights decides the default light;
/// the textures are opened again, quietly: the renderer reports unreadable ones).
ReferenceShading shading_from(const Scene& scene, const RenderOptions& options);
/// The same at a posed frame: lights on a node (PointLight::node) placed by its matrix there.
ReferenceShading shading_from(const Scene& scene, const RenderOptions& options, const anim::PosedScene& posed);

struct ReferencePixel {
    ReferenceHit hit;
    glm::dvec3 color{0.0};
    /// Unit geometric normal of the hit triangle, turned to face the eye (not the shading
    /// normal, like RenderedFrame::normal); 0 on a miss.
    glm::dvec3 normal{0.0};
    /// Anything in the colour beyond the camera hit is ambiguous (the rules are at the top of
    /// this file): a light's visibility or n . l sign at any hit, a secondary ray's hit, a
    /// total internal reflection, a cutoff decision. Colour comparisons skip such pixels.
    bool shading_ambiguous = false;
    /// Bit k set: a hit of a depth-k ray (0: the camera ray) spawned secondary rays on a
    /// transmissive surface and refracted (sin2_t <= 1).
    std::uint32_t refracted_at = 0;
    /// Bit k set: likewise, but reflected totally (sin2_t > 1).
    std::uint32_t total_internal_at = 0;
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
/// the eye, s the shading normal (above), p = org + t dir from the exact t, and for each light
/// with n . l > 0 a shadow segment from p to the light excluding the hit triangle
/// (ReferenceTracer::occluded), lit with s; then
/// the secondary rays of the model above, recursively up to shading.max_depth.
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
