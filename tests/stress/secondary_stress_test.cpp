// Reflection and refraction rays under stress, through the Renderer (both tracers, and the
// two-level path through a rigid object's instance): their origins are the hit point pushed
// off the surface along the geometric normal (offset_along_normal), to the side the ray
// leaves on, at scales 1e-6 ... 1e6 and far from the origin.
//
// The scenes are chosen so that the exact answer is known without a reference: a perfect
// mirror (reflectance 1, no diffuse or specular) alone in the world, and a closed box of
// clear glass of index 1 (transmittance 1: rays pass straight through). Every pixel that sees
// them must be exactly the background: a secondary ray that hits its own surface again (acne)
// or fails to leave the glass ends in a black local term or at the depth limit, and the pixel
// comes out darker.

#include "stress_geometry.h"
#include "scale_sweep.h"
#include "stress_mode.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

/// A scene of one object, `mesh`, of one material that has no local colour at all.
Scene one_object(const ClosedMesh& mesh, const Material& material) {
    Scene scene;
    scene.source = "secondary stress";
    scene.materials.push_back(material);
    Object object;
    object.name = "surface";
    object.mesh.positions = mesh.vertices;
    for (const auto& f : mesh.faces) object.mesh.triangles.emplace_back(f[0], f[1], f[2]);
    scene.objects.push_back(object);
    return scene;
}

/// A two-triangle square in the plane y = 0, [-1, 1] in x and z, facing +y.
ClosedMesh square() {
    ClosedMesh m;
    m.vertices = {{-1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, 1.0f}, {-1.0f, 0.0f, 1.0f}};
    m.faces = {{0, 2, 1}, {0, 3, 2}};
    return m;
}

struct Count {
    int pixels_on_surface = 0;
    int wrong = 0;
    std::string first;
};

/// Renders `scene` (rigidly turned at frame 3 when `instanced`) with both tracers and checks
/// that every pixel on the surface is the background, bit for bit.
Count render_and_check(Scene scene, bool instanced, const Camera& camera, int size, const std::string& what) {
    if (instanced) {
        const std::string specs[] = {"rigid"};
        anim::add_procedural_motions(scene, specs);
    }
    Count count;
    for (const Tracer kind : {Tracer::packet, Tracer::single}) {
        RenderOptions options;
        options.width = options.height = size;
        options.tracer = kind;
        options.background = glm::vec3(0.25f, 0.5f, 0.75f);
        options.lights = {{camera.eye, 1.0f}};
        Renderer renderer(options);
        RenderedFrame got;
        renderer.render(scene, camera, instanced ? 3 : 0, got);
        for (std::size_t i = 0; i < got.color.size(); ++i) {
            if (got.object[i] < 0) continue;
            ++count.pixels_on_surface;
            if (got.color[i] == options.background) continue;
            if (count.wrong++ == 0) {
                count.first = what + (kind == Tracer::packet ? " packet" : " single") + ": pixel " +
                              std::to_string(i) + " is (" + std::to_string(got.color[i].x) + ", " +
                              std::to_string(got.color[i].y) + ", " + std::to_string(got.color[i].z) + ")";
            }
        }
    }
    return count;
}

/// Renders `unit` (a mesh about 1 across, at the origin) of `material` over the scale sweep,
/// static and rigid, from each of `eyes` looking at `target` (both in units of the scene's
/// scale, around its centre), and expects every pixel on the surface to be the background,
/// and the surface to fill a good part of the images (else the check means little).
void sweep_and_check(const ClosedMesh& unit, const Material& material, std::span<const glm::dvec3> eyes,
                     glm::dvec3 target, float fov_y_deg, const char* what) {
    const int size = int(scaled(32, 3));
    int pixels = 0, wrong = 0, renders = 0;
    for (const Sweep& sweep : scale_sweep()) {
        const glm::dvec3 c = offset_of(sweep);
        const Scene scene = one_object(transformed(unit, sweep.scale, c), material);
        for (const bool instanced : {false, true}) {
            for (const glm::dvec3& eye : eyes) {
                Camera camera;
                camera.eye = glm::vec3(c + sweep.scale * eye);
                camera.target = glm::vec3(c + sweep.scale * target);
                camera.fov_y_deg = fov_y_deg;
                const std::string where = "scale " + std::to_string(sweep.scale) + " offset " +
                                          std::to_string(sweep.offset) + (instanced ? " rigid" : "");
                const Count count = render_and_check(scene, instanced, camera, size, where);
                EXPECT_EQ(count.wrong, 0) << count.first;
                pixels += count.pixels_on_surface;
                wrong += count.wrong;
                ++renders;
            }
        }
    }
    EXPECT_GT(pixels, renders * size * size / 8);
    std::printf("secondary rays, %s: %d renders x 2 tracers, %d pixels on it, %d not the background\n", what,
                renders, pixels, wrong);
}

TEST(SecondaryStress, MirrorReflectsOnlyTheWorldAtEveryScale) {
    Material mirror;
    mirror.diffuse = glm::vec3(0.0f);
    mirror.specular = glm::vec3(0.0f);
    mirror.reflectance = glm::vec3(1.0f);
    // From steeply above down to nearly grazing.
    const glm::dvec3 eyes[] = {{0.3, 2.0, 0.4}, {0.2, 0.3, 2.5}, {0.0, 0.02, 3.0}};
    sweep_and_check(square(), mirror, eyes, glm::dvec3(0.0), 60.0f, "mirror");
}

TEST(SecondaryStress, ClearGlassBoxPassesEveryRayAtEveryScale) {
    Material glass;
    glass.diffuse = glm::vec3(0.0f);
    glass.specular = glm::vec3(0.0f);
    glass.transmittance = glm::vec3(1.0f);
    glass.ior = 1.0f;
    const glm::dvec3 eyes[] = {{2.5, 1.5, 3.0}, {0.1, -0.05, 0.15}};  // outside, inside
    sweep_and_check(box_mesh(3, glm::vec3(-1.0f, -0.75f, -1.25f), glm::vec3(1.0f, 0.75f, 1.25f)), glass, eyes,
                    glm::dvec3(-0.2, 0.1, -0.3), 90.0f, "clear glass box");
}

}  // namespace
}  // namespace dynrt::stress
