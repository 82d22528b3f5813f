// Cut-out materials (glTF alphaMode MASK; dynrt/engine/alpha_mask.h), against the exact
// reference renderer: a checkered screen the camera sees through, a canopy out of view whose
// holes only the shadow rays pass through, and the screen seen in a mirror floor, for the
// packet and the single-ray tracer. Each comparison is also run with the cut-outs made opaque
// and must then fail: a tracer that ignored cut-outs on any kind of ray would be caught.

#include "reference_shot.h"
#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <string>
#include <vector>

namespace dynrt::reference {
namespace {

/// An 8x8 RGBA texture: orange, alpha 0 and 1 in 2x2 checks.
Texture checker_texture() {
    Texture texture;
    texture.name = "checker";
    texture.texels = TexelArray{.width = 8, .height = 8, .channels = 4, .floating = false, .bytes = {}};
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
            const bool solid = ((x / 2) + (y / 2)) % 2 == 0;
            for (unsigned char value : {255, 140, 40}) texture.texels.bytes.push_back(value);
            texture.texels.bytes.push_back(solid ? 255 : 0);
        }
    }
    return texture;
}

/// A quad from `corner` spanning `across` and `up`, texture coordinates 0 to `repeat` over it.
Object quad(const std::string& name, glm::vec3 corner, glm::vec3 across, glm::vec3 up, float repeat,
            std::uint32_t material) {
    Object object;
    object.name = name;
    object.mesh.positions = {corner, corner + across, corner + across + up, corner + up};
    object.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    object.mesh.texcoords = {{0.0f, repeat}, {repeat, repeat}, {repeat, 0.0f}, {0.0f, 0.0f}};
    object.material = material;
    return object;
}

struct AlphaCase {
    std::string name;
    bool screen = false;  ///< a checkered screen in view
    bool canopy = false;  ///< a checkered canopy above the view, between the light and the floor
    bool mirror = false;  ///< the floor reflects
};

void PrintTo(const AlphaCase& c, std::ostream* out) { *out << c.name; }

/// The floor and two spheres, and the case's cut-outs (material "cut", a MASK at 1/2).
Scene alpha_scene(const AlphaCase& c) {
    Scene scene = load_scene("plane:8@0,-1,0,4#c0c0c0+sphere:800@-0.5,-0.4,-0.6,0.6#e04020+"
                             "sphere:800@0.9,-0.5,-0.4,0.5#2050e0");
    if (c.mirror) scene.materials[scene.objects[0].material].reflectance = glm::vec3(0.4f);
    scene.textures.push_back(checker_texture());
    Material cut{.name = "cut", .diffuse = glm::vec3(1.0f)};
    cut.diffuse_map = TextureMap{.texture = std::uint32_t(scene.textures.size() - 1)};
    cut.alpha_cutoff = 0.5f;
    scene.materials.push_back(cut);
    const auto m = std::uint32_t(scene.materials.size() - 1);
    if (c.screen) scene.objects.push_back(quad("screen", {-1.4f, -1.0f, 0.4f}, {2.8f, 0.0f, 0.0f}, {0.0f, 1.5f, 0.0f}, 3.0f, m));
    if (c.canopy) scene.objects.push_back(quad("canopy", {-2.5f, 2.2f, 2.0f}, {5.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -5.0f}, 4.0f, m));
    return scene;
}

/// The same scene with its cut-outs opaque.
Scene without_cutouts(Scene scene) {
    for (Material& m : scene.materials) m.alpha_cutoff.reset();
    return scene;
}

Camera alpha_camera() {
    Camera camera;
    camera.eye = glm::vec3(0.0f, 1.4f, 4.0f);
    camera.target = glm::vec3(0.0f, -0.6f, 0.0f);
    camera.fov_y_deg = 55.0f;
    return camera;
}

RenderOptions alpha_options(Tracer tracer = Tracer::packet) {
    RenderOptions options;
    options.width = 96;
    options.height = 72;
    options.tracer = tracer;
    options.lights = {PointLight{glm::vec3(0.6f, 3.5f, 1.2f), 0.9f}};
    options.secondary.max_depth = 3;
    return options;
}

ReferenceFrame alpha_reference(const Scene& scene, const RenderOptions& options) {
    return test::reference_shot(scene, alpha_camera(), options);
}

RenderedFrame alpha_render(const Scene& scene, const RenderOptions& options) {
    return test::renderer_shot(scene, alpha_camera(), options);
}

ComparisonOptions alpha_tolerance() {
    ComparisonOptions t;
    t.color_abs_tol = 1e-3;
    return t;
}

class Cutouts : public ::testing::TestWithParam<AlphaCase> {};

TEST_P(Cutouts, MatchTheExactReferenceWithBothTracers) {
    const Scene scene = alpha_scene(GetParam());
    const ReferenceFrame ref = alpha_reference(scene, alpha_options());
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        SCOPED_TRACE(tracer == Tracer::packet ? "packet" : "single");
        const ImageComparison cmp = compare_images(alpha_render(scene, alpha_options(tracer)), ref, alpha_tolerance());
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.color_checked, 96 * 72 * 3 / 4);
    }
    // The cut-outs matter: with them opaque, the same comparison fails on many pixels.
    const ImageComparison opaque =
        compare_images(alpha_render(without_cutouts(scene), alpha_options()), ref, alpha_tolerance());
    EXPECT_GT(opaque.color_mismatches + opaque.unambiguous_mismatches, 200) << opaque.summary();
}

INSTANTIATE_TEST_SUITE_P(Alpha, Cutouts,
                         ::testing::Values(AlphaCase{"screenInView", true, false, false},
                                           AlphaCase{"canopyShadowsOnly", false, true, false},
                                           AlphaCase{"screenAndCanopyInAMirror", true, true, true}),
                         [](const ::testing::TestParamInfo<AlphaCase>& info) { return info.param.name; });

// A cut-out cut everywhere (its alpha below the cutoff, no texture) is not there at all: the
// image is the one without it, bit for bit (each ray is traced on from just past it, and
// finds the same hit behind with the same test).
TEST(Cutouts, AWhollyCutSurfaceLeavesTheImageAsWithoutIt) {
    const AlphaCase both{"both", true, true, true};
    Scene scene = alpha_scene(both);
    scene.materials.back().diffuse_map.reset();
    scene.materials.back().base_alpha = 0.25f;
    Scene bare = alpha_scene(AlphaCase{"none", false, false, true});
    const RenderedFrame with = alpha_render(scene, alpha_options());
    const RenderedFrame without = alpha_render(bare, alpha_options());
    EXPECT_EQ(with.color, without.color);
    // And at alpha 1/2 (not below the cutoff) it is there.
    scene.materials.back().base_alpha = 0.5f;
    EXPECT_NE(alpha_render(scene, alpha_options()).color, without.color);
}

TEST(Cutouts, AlphaOutsideZeroToOneIsRefusedNamingTheMaterial) {
    Scene scene = alpha_scene(AlphaCase{"screen", true, false, false});
    const auto refused = [&](const std::string& fragment) {
        try {
            check_scene(scene);
            ADD_FAILURE() << "accepted; expected " << fragment;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("material 'cut'"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    scene.materials.back().alpha_cutoff = 1.5f;
    refused("alpha cutoff 1.5 must be in [0, 1]");
    scene.materials.back().alpha_cutoff = 0.5f;
    scene.materials.back().base_alpha = -0.25f;
    refused("base alpha -0.25 must be in [0, 1]");
}

}  // namespace
}  // namespace dynrt::reference
