// Light kinds (renderer.h "Lights"): spot cones, directional lights, inverse-square falloff,
// glTF's range window and light colours, against the exact reference renderer on a floor with
// two spheres, for the packet and the single-ray tracer; a light off by one degree of cone or
// without its falloff must fail the same comparison, so the comparison can catch a broken
// kernel. Then glTF KHR_lights_punctual lights on an animated node, posed every frame like
// the reference poses them, and the shadow rays left out where a light adds nothing.

#include "gltf_test_file.h"
#include "reference_shot.h"
#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/packet/pinhole.h"
#include "dynrt/scene/scene_error.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::reference {
namespace {

const std::string kFloorAndSpheres =
    "plane:8@0,-1,0,4#c0c0c0+sphere:800@-0.7,-0.4,0.2,0.6#e04020+sphere:800@0.9,-0.5,-0.4,0.5#2050e0";

Camera lights_camera() {
    Camera camera;
    camera.eye = glm::vec3(0.0f, 1.6f, 4.0f);
    camera.target = glm::vec3(0.0f, -0.6f, 0.0f);
    camera.fov_y_deg = 55.0f;
    return camera;
}

PointLight spot_light(float inner_deg, float outer_deg) {
    PointLight light{glm::vec3(0.3f, 2.5f, 0.5f), 0.9f};
    light.kind = PointLight::Kind::spot;
    light.direction = glm::normalize(glm::vec3(-0.2f, -1.0f, -0.1f));
    light.inner_cone = glm::radians(inner_deg);
    light.outer_cone = glm::radians(outer_deg);
    return light;
}

PointLight sun_light() {
    PointLight light;
    light.kind = PointLight::Kind::directional;
    light.direction = glm::normalize(glm::vec3(0.5f, -1.0f, -0.3f));
    light.intensity = 0.8f;
    light.color = glm::vec3(1.0f, 0.85f, 0.6f);
    return light;
}

PointLight bulb_light() {
    PointLight light{glm::vec3(-0.2f, 1.2f, 1.0f), 2.0f};
    light.inverse_square = true;
    light.range = 3.5f;
    light.color = glm::vec3(0.6f, 0.8f, 1.0f);
    return light;
}

RenderOptions lights_options(std::vector<PointLight> lights, Tracer tracer = Tracer::packet) {
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    options.tracer = tracer;
    options.lights = std::move(lights);
    return options;
}

ReferenceFrame lights_reference(const Scene& scene, const RenderOptions& options) {
    return test::reference_shot(scene, lights_camera(), options);
}

RenderedFrame lights_render(const Scene& scene, const RenderOptions& options) {
    return test::renderer_shot(scene, lights_camera(), options);
}

ComparisonOptions lights_tolerance() {
    ComparisonOptions t;
    t.color_abs_tol = 1e-3;
    return t;
}

struct LightCase {
    std::string name;
    std::vector<PointLight> lights;
};

void PrintTo(const LightCase& c, std::ostream* out) { *out << c.name; }

class LightKinds : public ::testing::TestWithParam<LightCase> {};

TEST_P(LightKinds, MatchTheExactReferenceWithBothTracers) {
    const Scene scene = load_scene(kFloorAndSpheres);
    const ReferenceFrame ref = lights_reference(scene, lights_options(GetParam().lights));
    // The light reaches some compared pixels and not others (its cone, range or shadows).
    int lit = 0, unlit = 0;
    const double ambient = RenderOptions{}.ambient;
    for (const ReferencePixel& p : ref.pixels) {
        if (!p.hit.is_hit() || p.shading_ambiguous) continue;
        (p.color.x > ambient * 0.8 + 1e-3 || p.color.z > ambient * 0.8 + 1e-3 ? lit : unlit)++;
    }
    EXPECT_GT(lit, 300);
    EXPECT_GT(unlit, 20);
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        SCOPED_TRACE(tracer == Tracer::packet ? "packet" : "single");
        const ImageComparison cmp = compare_images(lights_render(scene, lights_options(GetParam().lights, tracer)), ref, lights_tolerance());
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.color_checked, 64 * 48 / 2);
    }
}

INSTANTIATE_TEST_SUITE_P(Lights, LightKinds,
                         ::testing::Values(LightCase{"spot", {spot_light(20.0f, 30.0f)}},
                                           LightCase{"directional", {sun_light()}},
                                           LightCase{"falloffRangeColour", {bulb_light()}},
                                           LightCase{"allThree", {spot_light(10.0f, 25.0f), sun_light(), bulb_light()}}),
                         [](const ::testing::TestParamInfo<LightCase>& info) { return info.param.name; });

// The comparison catches a kernel that gets a term wrong: a cone one degree wider, falloff
// dropped, a directional light treated as a point at its direction.
TEST(LightKinds, TheComparisonFailsForALightOffByADegreeOrWithoutFalloff) {
    const Scene scene = load_scene(kFloorAndSpheres);
    const auto mismatches = [&](const PointLight& truth, const PointLight& rendered) {
        const ImageComparison cmp =
            compare_images(lights_render(scene, lights_options({rendered})), lights_reference(scene, lights_options({truth})), lights_tolerance());
        return cmp.color_mismatches;
    };
    EXPECT_GT(mismatches(spot_light(20.0f, 30.0f), spot_light(20.0f, 31.0f)), 20);
    EXPECT_GT(mismatches(spot_light(20.0f, 30.0f), spot_light(21.0f, 30.0f)), 20);
    PointLight flat = bulb_light();
    flat.inverse_square = false;
    EXPECT_GT(mismatches(bulb_light(), flat), 100);
    PointLight unbounded = bulb_light();
    unbounded.range = 0.0f;
    EXPECT_GT(mismatches(bulb_light(), unbounded), 20);
    PointLight point = sun_light();
    point.kind = PointLight::Kind::point;
    point.position = -4.0f * point.direction;
    EXPECT_GT(mismatches(sun_light(), point), 100);
}

// Shadow rays are cast only where the light adds something: outside a spot's cone, past a
// range, nothing is traced (and the image is the same as if it were).
TEST(LightKinds, NoShadowRayOutsideTheConeOrPastTheRange) {
    const Scene scene = load_scene(kFloorAndSpheres);
    const RenderedFrame narrow = lights_render(scene, lights_options({spot_light(5.0f, 10.0f)}));
    const auto hits = [](const RenderedFrame& f) {
        return f.stats.shadow_rays + f.stats.shadow_rays_back_side + f.stats.shadow_rays_shading_side +
               f.stats.shadow_rays_dark_light;
    };
    EXPECT_GT(narrow.stats.shadow_rays_dark_light, hits(narrow) / 2);
    EXPECT_LT(narrow.stats.shadow_rays, hits(narrow) / 4);
    PointLight near = bulb_light();
    near.range = 1.0f;
    const RenderedFrame ranged = lights_render(scene, lights_options({near}));
    EXPECT_GT(ranged.stats.shadow_rays_dark_light, hits(ranged) / 2);
    const RenderedFrame wide = lights_render(scene, lights_options({spot_light(60.0f, 89.0f)}));
    EXPECT_EQ(wide.stats.shadow_rays_dark_light, 0u);
}

TEST(LightKinds, BadLightsAreRefusedNamingThem) {
    const Scene scene = load_scene(kFloorAndSpheres);
    const auto refused = [&](PointLight light, const std::string& fragment) {
        light.name = "lamp";
        Renderer renderer(lights_options({light}));
        RenderedFrame frame;
        try {
            renderer.render(scene, lights_camera(), 0, frame);
            ADD_FAILURE() << "accepted; expected " << fragment;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("light 'lamp'"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    refused(spot_light(30.0f, 20.0f), "0 <= inner < outer");
    refused(spot_light(10.0f, 95.0f), "0 <= inner < outer <= pi/2");
    PointLight dark = bulb_light();
    dark.intensity = -1.0f;
    refused(dark, "intensity");
    PointLight tinted = bulb_light();
    tinted.color = glm::vec3(1.0f, -0.5f, 0.0f);
    refused(tinted, "colour");
    PointLight pointless = sun_light();
    pointless.direction = glm::vec3(0.0f);
    refused(pointless, "direction");
    PointLight far = bulb_light();
    far.range = -2.0f;
    refused(far, "range");
}

// Shadows through glass (renderer.h "Lights"): a shadow ray blocked only by transmissive
// surfaces reaches its light filtered by their transmittance, so an orange glass ball casts an
// orange shadow, not a black one; an opaque ball still casts a black one. Both tracers match
// the reference, which filters its shadow segments alike, with a point and a directional
// light, and the floor in the ball's shadow is lit, and orange.
Scene glass_ball_scene(glm::vec3 transmittance) {
    Scene scene = load_scene("plane:8@0,-1,0,4#c0c0c0+sphere:800@0,-0.3,0,0.6#ffffff");
    Material& ball = scene.materials[scene.objects[1].material];
    ball.diffuse = glm::vec3(0.02f);
    ball.transmittance = transmittance;
    ball.ior = 1.3f;
    return scene;
}

TEST(GlassShadows, AreColouredByTheTransmittanceAndMatchTheReference) {
    const glm::vec3 orange(0.9f, 0.5f, 0.1f);
    const Scene scene = glass_ball_scene(orange);
    // Lights behind and beside the ball, so that its shadow falls toward the camera.
    PointLight above{glm::vec3(-1.2f, 2.5f, -1.4f), 0.9f};
    PointLight sun = sun_light();
    sun.direction = glm::normalize(glm::vec3(0.5f, -1.0f, 0.6f));
    sun.color = glm::vec3(1.0f);
    for (const PointLight& light : {above, sun}) {
        SCOPED_TRACE(light.kind == PointLight::Kind::directional ? "directional" : "point");
        const ReferenceFrame ref = lights_reference(scene, lights_options({light}));
        for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
            SCOPED_TRACE(tracer == Tracer::packet ? "packet" : "single");
            const RenderedFrame frame = lights_render(scene, lights_options({light}, tracer));
            const ImageComparison cmp = compare_images(frame, ref, lights_tolerance());
            EXPECT_TRUE(cmp.passed()) << cmp.summary();
            EXPECT_GT(cmp.color_checked, 64 * 48 / 3);
            // The floor pixels whose shadow ray crosses the ball: lit through it, orange.
            const packet::PinholeRays rays(lights_camera(), frame.width, frame.height);
            int filtered = 0, open = 0;
            for (int y = 0; y < frame.height; ++y) {
                for (int x = 0; x < frame.width; ++x) {
                    const ReferencePixel& p = ref.at(x, y);
                    if (p.hit.object != 0) continue;
                    if (p.shading_ambiguous) {
                        ++open;
                        continue;
                    }
                    const glm::dvec3 at = glm::dvec3(rays.ray(x, y).org) + p.hit.t * glm::dvec3(rays.ray(x, y).dir);
                    const glm::dvec3 to = light.kind == PointLight::Kind::directional
                                              ? -glm::dvec3(light.direction)
                                              : glm::normalize(glm::dvec3(light.position) - at);
                    // Through the ball's centre region (radius 0.6 at (0, -0.3, 0)).
                    const glm::dvec3 c(0.0, -0.3, 0.0);
                    const double along = glm::dot(c - at, to);
                    if (glm::length(c - at - along * to) > 0.4) continue;
                    const glm::vec3 rgb = frame.color[std::size_t(y) * std::size_t(frame.width) + std::size_t(x)];
                    const float ambient = RenderOptions{}.ambient * 0.75f;  // the floor's a * kd
                    EXPECT_GT(rgb.x - ambient, 2.0f * (rgb.z - ambient)) << x << "," << y;
                    EXPECT_GT(rgb.x, ambient + 0.1f) << x << "," << y;
                    ++filtered;
                }
            }
            EXPECT_GT(filtered, 20) << open << " floor pixels open";
        }
    }
    // An opaque ball's shadow stays dark: the same pixels get the ambient term alone.
    const Scene opaque = glass_ball_scene(glm::vec3(0.0f));
    const ImageComparison cmp = compare_images(lights_render(opaque, lights_options({above})),
                                               lights_reference(opaque, lights_options({above})), lights_tolerance());
    EXPECT_TRUE(cmp.passed()) << cmp.summary();
}

// A glTF spot on a node that moves: every frame's light is where the node puts it, in the
// renderer as in the reference (which poses it on its own, in double).
TEST(GltfLights, ASpotOnAnAnimatedNodeFollowsItEveryFrame) {
    test::GltfTestFile f;
    // A floor quad 8 x 8 at y = -1 (two triangles, wound to face +y).
    const int floor = f.add_mesh({-4, -1, -4, -4, -1, 4, 4, -1, 4, -4, -1, -4, 4, -1, 4, 4, -1, -4}, {}, nullptr,
                                 "floor");
    f.add_node({{"name", "floor"}, {"mesh", floor}});
    f.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
    f.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"name", "torch"}, {"type", "spot"}, {"intensity", 20.0}, {"color", {1.0, 0.9, 0.7}},
         {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.45}}}}};
    // The node points its -Z down (a quarter turn about x) and slides along x.
    const float s = std::sqrt(0.5f);
    const int torch = f.add_node({{"name", "torch node"},
                                  {"rotation", {-s, 0.0, 0.0, s}},
                                  {"translation", {-1.5, 1.5, 0.0}},
                                  {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    f.add_animation("Slide", {{torch, "translation", {0.0f, 1.0f}, {-1.5f, 1.5f, 0.0f, 1.5f, 1.5f, 0.0f}}});
    const Scene scene = load_scene(f.write("moving_spot.gltf").string());
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0].name, "torch");
    EXPECT_EQ(scene.lights[0].kind, PointLight::Kind::spot);
    EXPECT_TRUE(scene.lights[0].inverse_square);
    EXPECT_FLOAT_EQ(scene.lights[0].intensity, float(20.0 / std::numbers::pi));
    EXPECT_TRUE(scene.ignored.empty()) << scene.ignored.front();

    RenderOptions options;
    options.width = 48;
    options.height = 48;
    options.pose.fps = 4.0;
    Camera camera;
    camera.eye = glm::vec3(0.0f, 4.0f, 3.0f);
    camera.target = glm::vec3(0.0f, -1.0f, 0.0f);
    camera.fov_y_deg = 70.0f;
    Renderer renderer(options);
    RenderedFrame frame;
    std::vector<RenderedFrame> frames;
    for (const int at : {0, 2, 4}) {
        SCOPED_TRACE("frame " + std::to_string(at));
        renderer.render(scene, camera, at, frame);
        anim::PosedScene posed;
        anim::pose_scene(scene, options.pose, at, posed);
        const ReferenceTracer tracer(scene, posed);
        const ReferenceFrame ref = render_reference(scene, tracer, camera, options.width, options.height,
                                                    shading_from(scene, options, posed));
        const ImageComparison cmp = compare_images(frame, ref, lights_tolerance());
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.color_checked, 48 * 48 / 2);
        frames.push_back(frame);
    }
    // The lit spot moved: frames 0 and 4 differ in many pixels.
    int differ = 0;
    for (std::size_t p = 0; p < frames[0].color.size(); ++p) {
        differ += glm::length(frames[0].color[p] - frames[2].color[p]) > 0.05f;
    }
    EXPECT_GT(differ, 100);
}

}  // namespace
}  // namespace dynrt::reference
