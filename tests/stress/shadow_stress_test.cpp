// Shadows under stress, through the Renderer (both tracers, and the two-level path through a
// rigid object's instance): no self-shadowing acne on a flat grid and a tessellated sphere lit
// from nearly in the surface's plane, and no light leaking into a closed box lit from outside,
// with the camera inside, at scales 1e-6 ... 1e6 and far from the origin. Shadow rays run from
// the light to the hit point pushed off the surface by engine/include/dynrt/engine/shadow_ray_offset.h.
//
// Acne and leaks are judged against the exact reference renderer: a pixel whose hit and
// shading the reference says are determined must have the reference's colour; darker is acne,
// brighter is a leak. Inside the closed box no pixel may be lit at all.

#include "stress_geometry.h"
#include "scale_sweep.h"
#include "stress_mode.h"

#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

/// A number for a procedural spec: shortest round trip, without the '+' the grammar refuses.
std::string spec_number(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    std::string s = buf;
    const auto plus = s.find('+');
    if (plus != std::string::npos) s.erase(plus, 1);
    return s;
}

/// How a rendered frame compares with the reference, pixel by pixel.
struct ShadowCount {
    int pixels_checked = 0;  ///< hit and shading determined, same triangle as the reference
    int acne = 0;            ///< darker than the reference: a shadow that should not be there
    int leaks = 0;           ///< brighter: light that should be blocked
    int unambiguous_mismatches = 0;
    std::string first;
};

ShadowCount compare_shadows(const RenderedFrame& got, const reference::ReferenceFrame& ref, double tol) {
    ShadowCount out;
    reference::ComparisonOptions options;
    options.color_abs_tol = tol;
    const reference::ImageComparison cmp = reference::compare_images(got, ref, options);
    out.unambiguous_mismatches = cmp.unambiguous_mismatches;
    if (cmp.unambiguous_mismatches != 0) out.first = cmp.summary();
    for (int y = 0; y < ref.height; ++y) {
        for (int x = 0; x < ref.width; ++x) {
            const reference::ReferencePixel& p = ref.at(x, y);
            const std::size_t i = std::size_t(y) * std::size_t(ref.width) + std::size_t(x);
            if (!p.hit.is_hit() || p.hit.ambiguity != reference::Ambiguity::kNone || p.shading_ambiguous) continue;
            if (got.prim[i] != p.hit.prim || got.object[i] != p.hit.object) continue;
            ++out.pixels_checked;
            const glm::dvec3 diff = glm::dvec3(got.color[i]) - p.color;
            const double lo = std::min({diff.x, diff.y, diff.z}), hi = std::max({diff.x, diff.y, diff.z});
            if (lo < -tol) ++out.acne;
            if (hi > tol) ++out.leaks;
            if ((lo < -tol || hi > tol) && out.first.empty()) {
                out.first = "(" + std::to_string(x) + "," + std::to_string(y) + ") got " + std::to_string(got.color[i].x) +
                            " reference " + std::to_string(p.color.x);
            }
        }
    }
    return out;
}

/// A light at `distance` from `c`, `elevation_deg` above the plane y = c.y, at `azimuth_deg`.
glm::vec3 grazing_light(glm::dvec3 c, double distance, double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * std::numbers::pi / 180.0, a = azimuth_deg * std::numbers::pi / 180.0;
    return glm::vec3(c + distance * glm::dvec3(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)));
}

/// The exact reference's frame of `scene` at `frame`, with the lights and size of `options`.
reference::ReferenceFrame reference_frame(const Scene& scene, int frame, const Camera& camera,
                                          const RenderOptions& options) {
    anim::PosedScene posed;
    anim::pose_scene(scene, frame, posed);
    const reference::ReferenceTracer tracer(scene, posed);
    return reference::render_reference(scene, tracer, camera, options.width, options.height,
                                       reference::shading_from(scene, options));
}

/// Renders `scene` at `frame` with each tracer and compares with the reference; returns the
/// summed counts and expects no acne and no leak, and, when `hits_determined`, no unambiguous
/// hit mismatch either.
///
/// A rigid object is traced in its object space, through a float transform of the ray, while
/// the reference sees its vertices posed in double and rounded: where the object sits 1000
/// times its size from the origin, transforming the ray origin cancels two terms 1000 times
/// larger than the result, and the two differ by ~1e-4 of the object's size (depth off by
/// 3e-4, a silhouette pixel flipping): the precision float coordinates that far out have
/// anyway, but more than the reference's tolerances, which scale with the distance from the
/// ray's origin, not with the coordinates. Those renders are checked for acne and leaks only.
ShadowCount render_and_compare(const Scene& scene, int frame, const Camera& camera, const std::vector<PointLight>& lights,
                               int size, const std::string& what, bool hits_determined) {
    RenderOptions options;
    options.width = options.height = size;
    options.lights = lights;
    anim::PosedScene posed;
    anim::pose_scene(scene, frame, posed);
    const reference::ReferenceTracer tracer(scene, posed);
    const reference::ReferenceFrame ref =
        reference::render_reference(scene, tracer, camera, size, size, reference::shading_from(scene, options));
    ShadowCount total;
    for (const Tracer kind : {Tracer::packet, Tracer::single}) {
        options.tracer = kind;
        Renderer renderer(options);
        RenderedFrame got;
        renderer.render(scene, camera, frame, got);
        // Lit and unlit differ by kd (n . l) >= 0.8 sin(0.25 degrees) = 3.5e-3 here; float
        // shading errors are ~1e-6.
        const ShadowCount count = compare_shadows(got, ref, 1e-3);
        EXPECT_EQ(count.acne, 0) << what << ", " << (kind == Tracer::packet ? "packet" : "single") << ": " << count.first;
        EXPECT_EQ(count.leaks, 0) << what << ", " << (kind == Tracer::packet ? "packet" : "single") << ": " << count.first;
        if (hits_determined) {
            EXPECT_EQ(count.unambiguous_mismatches, 0) << what << ": " << count.first;
        }
        total.pixels_checked += count.pixels_checked;
        total.acne += count.acne;
        total.leaks += count.leaks;
        total.unambiguous_mismatches += count.unambiguous_mismatches;
    }
    return total;
}

TEST(ShadowStress, NoAcneAtGrazingLightOnFlatAndCurvedSurfaces) {
    const int size = int(scaled(40, 3));
    int renders = 0;
    ShadowCount total;
    for (const Sweep& sweep : scale_sweep()) {
        const glm::dvec3 c = offset_of(sweep);
        const std::string place = "@" + spec_number(c.x) + "," + spec_number(c.y) + "," + spec_number(c.z) + "," +
                                  spec_number(sweep.scale);
        for (const std::string kind : {"plane:8", "sphere:300"}) {
            Scene scene = load_scene(kind + place);
            // Frame 3 of a rigid turn: the object is traced through its instance transform.
            for (const bool instanced : {false, true}) {
                if (instanced) {
                    const std::string specs[] = {"rigid"};
                    anim::add_procedural_motions(scene, specs);
                }
                const int frame = instanced ? 3 : 0;
                Camera camera;
                camera.eye = glm::vec3(c + sweep.scale * glm::dvec3(0.4, 1.6, 1.9));
                camera.target = glm::vec3(c);
                camera.fov_y_deg = 55.0f;
                for (const double elevation : {3.0, 0.75, 0.25}) {
                    for (const double distance : {4.0, 400.0}) {
                        const std::vector<PointLight> lights = {
                            {grazing_light(c, distance * sweep.scale, elevation, 30.0), 1.0f}};
                        const std::string what = kind + place + (instanced ? " rigid" : "") + ", light elevation " +
                                                 std::to_string(elevation) + " distance " + std::to_string(distance);
                        SCOPED_TRACE(what);
                        const ShadowCount count = render_and_compare(scene, frame, camera, lights, size, what,
                                                                     !instanced || sweep.offset == 0.0);
                        total.pixels_checked += count.pixels_checked;
                        total.acne += count.acne;
                        total.leaks += count.leaks;
                        total.unambiguous_mismatches += count.unambiguous_mismatches;
                        ++renders;
                    }
                }
            }
        }
    }
    std::printf("shadows, grazing light: %d renders x 2 tracers, %d pixels checked, %d acne, %d leaks; %d hit "
                "mismatches with the reference (rigid objects far from the origin only)\n",
                renders, total.pixels_checked, total.acne, total.leaks, total.unambiguous_mismatches);
    RecordProperty("pixels_checked", total.pixels_checked);
    RecordProperty("acne", total.acne);
}

TEST(ShadowStress, NoLightLeaksIntoAClosedBox) {
    const int size = int(scaled(32, 3));
    const ClosedMesh unit_box = box_mesh(4, glm::vec3(-1.0f, -0.75f, -1.25f), glm::vec3(1.0f, 0.75f, 1.25f));
    int renders = 0, pixels = 0, lit = 0, lit_open = 0;
    for (const Sweep& sweep : scale_sweep()) {
        const glm::dvec3 c = offset_of(sweep);
        const ClosedMesh box = transformed(unit_box, sweep.scale, c);
        ASSERT_TRUE(is_closed(box.triangles()));
        for (const bool instanced : {false, true}) {
            Scene scene;
            scene.source = "stress";
            scene.materials.push_back(Material{});
            Object object;
            object.name = "box";
            object.mesh.positions = box.vertices;
            for (const auto& f : box.faces) object.mesh.triangles.emplace_back(f[0], f[1], f[2]);
            scene.objects.push_back(object);
            if (instanced) {
                const std::string specs[] = {"rigid"};
                anim::add_procedural_motions(scene, specs);
            }
            const double s = sweep.scale;
            // Outside: on an axis, off a corner, far away, and nearly in the planes of faces
            // (just inside the plane of the +y face, so its inner side is barely lit).
            const glm::dvec3 light_spots[] = {{3.0, 0.1, 0.2},  {2.5, 2.0, -2.2},  {-300.0, 40.0, 90.0},
                                              {2.5, 0.74999, 0.3}, {0.2, -0.3, 1.2500001 + 2.0}, {-2.0, 0.75, 1.25}};
            for (const glm::dvec3& spot : light_spots) {
                const std::vector<PointLight> lights = {{glm::vec3(c + s * spot), 1.0f}};
                for (const glm::dvec3 look : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0),
                                              glm::dvec3(0, -0.3, 1), glm::dvec3(0.2, 0.1, -1)}) {
                    Camera camera;
                    camera.eye = glm::vec3(c + s * glm::dvec3(0.1, -0.05, 0.15));
                    camera.target = glm::vec3(c + s * (glm::dvec3(0.1, -0.05, 0.15) + look));
                    camera.up = std::fabs(look.y) > 0.9 ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
                    camera.fov_y_deg = 100.0f;
                    for (const Tracer kind : {Tracer::packet, Tracer::single}) {
                        RenderOptions options;
                        options.width = options.height = size;
                        options.lights = lights;
                        options.tracer = kind;
                        Renderer renderer(options);
                        RenderedFrame got;
                        renderer.render(scene, camera, instanced ? 5 : 0, got);
                        // Unlit: exactly the ambient term (no light reaches any pixel). A lit
                        // pixel is a leak unless the exact reference says its light is open:
                        // a hit point within float rounding of an inner corner may round
                        // through the neighbouring wall, which no offset along its own normal
                        // prevents (seen in the --stress mode only, boxes 1000 sizes out).
                        const glm::vec3 ambient = options.ambient * scene.materials[0].diffuse;
                        int lit_here = 0;
                        std::string first;
                        std::optional<reference::ReferenceFrame> ref;
                        for (std::size_t i = 0; i < got.color.size(); ++i) {
                            EXPECT_GE(got.object[i], 0) << "a ray escaped the box";
                            ++pixels;
                            const glm::vec3 d = got.color[i] - ambient;
                            if (std::max({d.x, d.y, d.z}) <= 1e-5f) continue;
                            if (!ref) ref = reference_frame(scene, instanced ? 5 : 0, camera, options);
                            const reference::ReferencePixel& r = ref->pixels[i];
                            if (r.shading_ambiguous || r.hit.ambiguity != reference::Ambiguity::kNone ||
                                r.hit.prim != got.prim[i]) {
                                ++lit_open;
                                continue;
                            }
                            if (lit_here++ == 0) first = "pixel " + std::to_string(i) + " prim " + std::to_string(got.prim[i]);
                        }
                        lit += lit_here;
                        EXPECT_EQ(lit_here, 0) << "scale " << s << " offset " << sweep.offset << (instanced ? " rigid" : "")
                                               << " light (" << spot.x << ", " << spot.y << ", " << spot.z << ") "
                                               << (kind == Tracer::packet ? "packet" : "single") << ": " << first;
                        ++renders;
                    }
                }
            }
        }
    }
    std::printf("shadows, closed box: %d renders, %d pixels inside, %d lit (leaks), %d lit where the reference "
                "says the light is open\n",
                renders, pixels, lit, lit_open);
    RecordProperty("lit_open", lit_open);
    RecordProperty("pixels", pixels);
    RecordProperty("leaks", lit);
}

}  // namespace
}  // namespace dynrt::stress
