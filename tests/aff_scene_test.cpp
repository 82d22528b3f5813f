// BART's AFF model turned into the scene model (engine/src/loaders/aff_scene.h): what becomes which
// object, node, class, camera and light, checked on snippets the tests write; then the three
// BART scenes, when ../shared/scenes/bart is there, load, classify as their motion says and
// render every sampled frame in agreement with the exact reference on their flattened triangles.

#include "loaders/aff_parser.h"
#include "loaders/aff_scene.h"
#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/engine/sequence.h"
#include "dynrt/scene/scene_error.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace dynrt {
namespace {

namespace fs = std::filesystem;

Scene convert(const std::string& text) {
    return aff::scene_from_aff(aff::parse_aff_text(text, "snippet.aff"), "snippet.aff");
}

std::string error_of(const std::string& text) {
    try {
        (void)convert(text);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "no error";
}

/// The pose settings that play `scene` at its own frame rate.
anim::PoseSettings own_rate(const Scene& scene) {
    anim::PoseSettings settings;
    settings.fps = scene.setup ? scene.setup->fps : anim::kDefaultFps;
    return settings;
}

/// Frame `frame` of `scene` at its own frame rate.
anim::PosedScene pose(const Scene& scene, int frame) {
    const anim::PoseSettings settings = own_rate(scene);
    anim::PosedScene posed;
    anim::pose_scene(scene, settings, frame, posed);
    return posed;
}

// Four keys make the smallest track: the first and last only shape the tangents, so with
// all tension, continuity and bias zero and keys 1 and 2 on a straight, evenly timed line the
// spline is that line.
const char* const kScene = R"(
v
from 0 0 10
at 0 0 0
up 0 1 0
angle 40
hither 0.01
resolution 64 48
b 0.1 0.2 0.3
a 1 3 5
l 0 5 0 0.3 0.6 0.9
fm 0 0 0  0.5 0.5 0.5  0.2 0.2 0.2  20 0 1
xs 2 2 2  0 0 1 90  1 0 0
{
  p 4
   0 0 0
   1 0 0
   1 1 0
   0 1 0
  x slider
  {
    xs 1 1 1  0 1 0 0  0 0 5
    {
      c 0 0 0 1  0 1 0 0
    }
  }
}
fm 0 0 0  0.9 0.1 0.1  0 0 0  10 0 1
tpa 3
 1
 0 0 0  0 0 1
 1 0 0  0 0 1
 0 1 0  0 0 1
 2
 0 0 2  0 0 1
 1 0 2  0 0 1
 0 1 2  0 0 1
 3
 0 0 4  0 0 1
 1 0 4  0 0 1
 0 1 4  0 0 1
k slider
{
  transl 4
   0  -1 0 0  0 0 0
   1   0 0 0  0 0 0
   3   2 0 0  0 0 0
   4   3 0 0  0 0 0
}
)";

TEST(AffScene, ObjectsPerAnchorAndMaterialWithStaticTransformsBakedIn) {
    const Scene scene = convert(kScene);
    // The quad (static), the cone under `slider` (rigid), the tpa triangle (morphing).
    ASSERT_EQ(scene.objects.size(), 3u);
    const Object& quad = scene.objects[0];
    EXPECT_EQ(quad.name, "static/fm0");
    EXPECT_EQ(quad.node, -1);
    EXPECT_EQ(quad.material, 1u);
    ASSERT_EQ(quad.mesh.triangles.size(), 2u);  // a fan from the first vertex
    EXPECT_EQ(quad.mesh.triangles[1], glm::uvec3(0, 2, 3));
    // xs: scale 2, then 90 degrees about z, then +1 in x: (1, 0, 0) -> (2, 0, 0) -> (0, 2, 0)
    // -> (1, 2, 0).
    EXPECT_NEAR(quad.mesh.positions[1].x, 1.0f, 1e-6f);
    EXPECT_NEAR(quad.mesh.positions[1].y, 2.0f, 1e-6f);

    const Object& cone = scene.objects[1];
    EXPECT_EQ(cone.name, "slider/fm0");
    ASSERT_GE(cone.node, 0);
    EXPECT_EQ(scene.nodes[std::size_t(cone.node)].name, "slider");
    // Apex radius 0: one apex vertex, one triangle per segment, no caps. The inner xs (+5 in z)
    // is baked in, the outer one belongs to the slider's parent node.
    EXPECT_EQ(cone.mesh.triangles.size(), std::size_t(aff::kAffConeSegments));
    EXPECT_EQ(cone.mesh.positions.size(), std::size_t(aff::kAffConeSegments + 1));
    EXPECT_FLOAT_EQ(cone.mesh.positions.back().z, 5.0f);
    EXPECT_FLOAT_EQ(cone.mesh.positions.back().y, 1.0f);

    const Object& tpa = scene.objects[2];
    EXPECT_EQ(tpa.material, 2u);
    ASSERT_TRUE(tpa.morph.has_value());
    EXPECT_EQ(tpa.morph->position_deltas.size(), 2u);

    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_FLOAT_EQ(scene.lights[0].intensity, 1.0f);  // a coloured light: its colour
    EXPECT_EQ(scene.lights[0].color, glm::vec3(0.3f, 0.6f, 0.9f));
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_FLOAT_EQ(scene.materials[2].diffuse.x, 0.9f);
    EXPECT_FLOAT_EQ(scene.materials[2].shininess, 10.0f);
}

TEST(AffScene, WhatTheModelLeavesOutIsListedForTheReport) {
    EXPECT_TRUE(convert("l 0 5 0 0.5 0.5 0.5\np 3\n0 0 0\n1 0 0\n0 1 0\n").ignored.empty());
    const Scene scene = convert(R"(
am 0.5 0.5 0.5
l 0 5 0  1 0.5 0.5
fm 0 0 0  1 1 1  0 0 0  10 0.5 1.3
tt wood.ppm
 0 0 0 0 0
 1 0 0 1 0
 0 1 0 0 1
pp 3
 0 0 1  0 0 1
 1 0 1  0 0 1
 0 1 1  0 0 1
)");
    // The textured triangle is mapped (its file is read at render time), not left out; the
    // light's colour and the ambient light are used now.
    EXPECT_TRUE(scene.ignored.empty()) << scene.ignored.front();
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0].color, glm::vec3(1.0f, 0.5f, 0.5f));
    EXPECT_EQ(scene.lights[0].intensity, 1.0f);
    // BART's ambient term: am times the material's ambient coefficients (here 0).
    ASSERT_TRUE(scene.materials.back().ambient.has_value());
    EXPECT_EQ(*scene.materials.back().ambient, glm::vec3(0.0f));
    const Scene lit = convert("am 0.5 0.25 1\nfm 0.2 0.4 0.6  1 1 1  0 0 0  10 0 0\np 3\n0 0 0\n1 0 0\n0 1 0\n");
    ASSERT_TRUE(lit.materials.back().ambient.has_value());
    EXPECT_FLOAT_EQ(lit.materials.back().ambient->x, 0.1f);
    EXPECT_FLOAT_EQ(lit.materials.back().ambient->y, 0.1f);
    EXPECT_FLOAT_EQ(lit.materials.back().ambient->z, 0.6f);
    // Without `am`, dynrt's own ambient fraction.
    EXPECT_FALSE(convert("fm 0.2 0.4 0.6  1 1 1  0 0 0  10 0 0\np 3\n0 0 0\n1 0 0\n0 1 0\n").materials.back().ambient);
}

// Materials (aff_scene.h): the specular colour is also the reflectance (NFF/SPD), T the grey
// transmittance, the file's ior the ior, with BART's 0.0 for opaque materials read as 1.
TEST(AffScene, MaterialsKeepReflectanceTransmittanceAndIor) {
    const Scene scene = convert(R"(
fm 0.1 0.1 0.1  0.5 0.6 0.7  0.1 0.2 0.3  20 0.4 1.33
p 3
0 0 0
1 0 0
0 1 0
fm 0 0 0  0.5 0.5 0.5  0.4 0.4 0.4  255 0.0 0.0
p 3
0 0 1
1 0 1
0 1 1
f 1 0.5 0  0.6 0.3  20  0.25 1.5
p 3
0 0 2
1 0 2
0 1 2
fm 0 0 0  0.5 0.5 0.5  0.2 0.2 0.2  10 1.5 -2
p 3
0 0 3
1 0 3
0 1 3
)");
    ASSERT_EQ(scene.materials.size(), 5u);  // the default, then fm0..fm3
    const Material& glass = scene.materials[1];
    EXPECT_EQ(glass.name, "fm0");
    EXPECT_EQ(glass.diffuse, glm::vec3(0.5f, 0.6f, 0.7f));  // unchanged by the new fields
    EXPECT_EQ(glass.specular, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_FLOAT_EQ(glass.shininess, 20.0f);
    EXPECT_EQ(glass.reflectance, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(glass.transmittance, glm::vec3(0.4f));
    EXPECT_FLOAT_EQ(glass.ior, 1.33f);
    EXPECT_TRUE(glass.traces_secondary());

    const Material& opaque = scene.materials[2];  // as BART writes an opaque material
    EXPECT_EQ(opaque.reflectance, glm::vec3(0.4f));
    EXPECT_EQ(opaque.transmittance, glm::vec3(0.0f));
    EXPECT_EQ(opaque.ior, 1.0f);

    // `f r g b Kd Ks shine T ior`: specular (and so reflectance) is colour * Ks.
    const Material& nff = scene.materials[3];
    EXPECT_EQ(nff.diffuse, glm::vec3(0.6f, 0.3f, 0.0f));
    EXPECT_EQ(nff.specular, glm::vec3(0.3f, 0.15f, 0.0f));
    EXPECT_EQ(nff.reflectance, nff.specular);
    EXPECT_EQ(nff.transmittance, glm::vec3(0.25f));
    EXPECT_FLOAT_EQ(nff.ior, 1.5f);

    // T is a weight, clamped to [0, 1] like the colours; any ior <= 0 reads as 1.
    const Material& clamped = scene.materials[4];
    EXPECT_EQ(clamped.transmittance, glm::vec3(1.0f));
    EXPECT_EQ(clamped.ior, 1.0f);

    for (std::size_t o = 0; o < scene.objects.size(); ++o) EXPECT_EQ(scene.objects[o].material, o + 1);
    // Nothing about transmittance or refraction is reported as left out any more.
    for (const std::string& line : scene.ignored) EXPECT_EQ(line.find("refraction"), std::string::npos) << line;
}

TEST(AffScene, NonFiniteTransmittanceAndIorAreErrorsNamingMaterialAndObject) {
    const auto load_error = [](const std::string& material) {
        try {
            (void)load_aff_text(material + "\np 3\n0 0 0\n1 0 0\n0 1 0\n", "snippet.aff");
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(load_error("fm 0 0 0  1 1 1  0 0 0  10 0.5 inf"),
              "snippet.aff: object 'static/fm0': material 'fm0' (index 1): ior inf must be finite and > 0");
    EXPECT_EQ(load_error("fm 0 0 0  1 1 1  0 0 0  10 nan 1.5"),
              "snippet.aff: object 'static/fm0': material 'fm0' (index 1): transmittance (nan, nan, nan) "
              "must be finite and >= 0");
    EXPECT_EQ(load_error("fm 0 0 0  1 1 1  0 nan 0  10 0 1.5"),
              "snippet.aff: object 'static/fm0': material 'fm0' (index 1): reflectance (0, nan, 0) "
              "must be finite and >= 0");
    EXPECT_EQ(load_error("fm 0 0 0  1 1 1  0 0 0  10 0.5 1.5"), "no error");
}

TEST(AffScene, ClassesFollowTheData) {
    const Scene scene = convert(kScene);
    const anim::ScenePoser poser(scene, own_rate(scene));
    EXPECT_EQ(poser.derived_class(0), anim::MotionClass::static_);
    EXPECT_EQ(poser.derived_class(1), anim::MotionClass::rigid);
    EXPECT_EQ(poser.derived_class(2), anim::MotionClass::deformable);
}

TEST(AffScene, FramesRunFromStartToEndAndKeysInterpolateAsBartSays) {
    const Scene scene = convert(kScene);
    ASSERT_TRUE(scene.setup.has_value());
    // a 1 3 5: frames 0..4 at times 1, 1.5, 2, 2.5, 3; dynrt's frame f is f / fps = f / 2 s
    // after the start.
    EXPECT_DOUBLE_EQ(scene.setup->fps, 2.0);
    EXPECT_EQ(scene.setup->frame_count, 5);
    EXPECT_EQ(scene.setup->width, 64);
    EXPECT_EQ(scene.setup->height, 48);
    EXPECT_EQ(scene.setup->background, glm::vec3(0.1f, 0.2f, 0.3f));
    for (int f = 0; f < 5; ++f) {
        SCOPED_TRACE("frame " + std::to_string(f));
        const double t = 1.0 + 0.5 * f;
        const anim::PosedScene posed = pose(scene, f);
        // The slider runs along x from 0 at t = 1 to 2 at t = 3 on a straight, evenly timed
        // spline; under the outer xs (scale 2, 90 degrees about z, +1 in x) x becomes y.
        const glm::dvec3 apex = glm::dvec3(posed.objects[1].transform * glm::dvec4(glm::dvec3(scene.objects[1].mesh.positions.back()), 1.0));
        const double slide = t - 1.0;
        EXPECT_NEAR(apex.x, 1.0 - 2.0 * 1.0, 1e-6);  // the apex's y = 1 in the slider's frame
        EXPECT_NEAR(apex.y, 2.0 * slide, 1e-6);
        EXPECT_NEAR(apex.z, 2.0 * 5.0, 1e-6);
        // The tpa triangle moves linearly from z = 0 at t = 1 to 2 at t = 2 and 4 at t = 3.
        const double z = 2.0 * (t - 1.0);
        for (const glm::vec3& p : posed.objects[2].positions) EXPECT_NEAR(p.z, z, 1e-6);
    }
    // Before and after the keys: clamped.
    EXPECT_NEAR(pose(scene, -3).objects[2].positions[0].z, 0.0, 1e-6);
    EXPECT_NEAR(pose(scene, 40).objects[2].positions[0].z, 4.0, 1e-6);
}

TEST(AffScene, ViewpointBecomesTheScenesCamera) {
    const Scene scene = convert(kScene);
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_NEAR(scene.cameras[0].yfov_rad, 40.0 * 3.14159265358979323846 / 180.0, 1e-12);
    EXPECT_DOUBLE_EQ(scene.cameras[0].aspect_ratio, 64.0 / 48.0);
    const anim::PosedScene posed = pose(scene, 0);
    ASSERT_TRUE(posed.camera.has_value());
    EXPECT_NEAR(glm::length(posed.camera->eye - glm::dvec3(0, 0, 10)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(posed.camera->forward - glm::dvec3(0, 0, -1)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(posed.camera->up - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
}

TEST(AffScene, AnimatedCameraFollowsItsKeys) {
    const Scene scene = convert(std::string(kScene) + R"(
k camera
{
  transl 4
   0  0 0 9  0 0 0
   1  0 0 10  0 0 0
   3  0 0 12  0 0 0
   4  0 0 13  0 0 0
}
)");
    EXPECT_NEAR(pose(scene, 0).camera->eye.z, 10.0, 1e-9);
    EXPECT_NEAR(pose(scene, 2).camera->eye.z, 11.0, 1e-9);
    // No rotation keys: the view direction stays the one `v` gives, as in BART's previewer.
    EXPECT_NEAR(glm::length(pose(scene, 2).camera->forward - glm::dvec3(0, 0, -1)), 0.0, 1e-12);
}

TEST(AffScene, WhatTheSceneModelCannotHoldIsAnErrorNamingFileAndLine) {
    const auto expect_error = [](const std::string& text, const std::string& what) {
        const std::string e = error_of(text);
        EXPECT_NE(e.find("snippet.aff"), std::string::npos) << e;
        EXPECT_NE(e.find(what), std::string::npos) << e;
    };
    expect_error("la lamp 0 1 0\np 3\n0 0 0\n1 0 0\n0 1 0\n", "snippet.aff:1: 'la lamp': animated lights are not supported");
    // A light under an animated transform hangs on its node, posed every frame.
    const Scene carried = convert("x arm\n{\nl 0 1 0\n}\nk arm\n{\ntransl 4\n0 0 0 0 0 0 0\n1 0 0 0 0 0 0\n2 1 0 0 0 0 0\n"
                                  "3 1 0 0 0 0 0\n}\np 3\n0 0 0\n1 0 0\n0 1 0\n");
    ASSERT_EQ(carried.lights.size(), 1u);
    ASSERT_GE(carried.lights[0].node, 0);
    EXPECT_LT(std::size_t(carried.lights[0].node), carried.nodes.size());
    expect_error("xs 1 1 1  0 0 0 30  0 0 0\n{\n}\n", "snippet.aff:1: 'xs' rotates about a zero axis");
    expect_error("tpa 2\n1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n",
                 "snippet.aff:1: 'tpa' key times must increase");
    expect_error("v\nfrom 0 0 0\nat 0 1 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\n",
                 "'up' is parallel to the view direction");
    expect_error("p 3\n0 0 0\n1 nan 0\n0 1 0\n", "snippet.aff:1: vertex (1, nan, 0) is not finite");
    expect_error("c 0 0 0 1  0 0 0 1\n", "snippet.aff:1: 'c' needs distinct base and apex");
    expect_error("v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 100000 8\n",
                 "resolution 100000x8 is larger than 16384 a side");
}

TEST(AffScene, LoadSceneReadsAffFilesAndChecksThem) {
    const fs::path dir = fs::path(::testing::TempDir()) / "dynrt_aff_scene_test";
    fs::create_directories(dir);
    const fs::path file = dir / "only_a_view.AFF";
    std::ofstream(file) << "v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\n";
    try {
        (void)load_scene(file.string());
        FAIL() << "a scene without triangles loaded";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("only_a_view.AFF"), std::string::npos) << e.what();
    }
    std::ofstream(file, std::ios::app) << "p 3\n0 0 0\n1 0 0\n0 1 0\n";
    EXPECT_EQ(load_scene(file.string()).triangle_count(), 1u);
}

// ---- The BART scenes, when ../shared/scenes/bart is there ----

struct BartCase {
    const char* name;
    const char* file;
    std::size_t triangles;  ///< after tessellating the museum's cones
    int frame_count;
    anim::MotionClass most_general;  ///< the most general class any object has
    int frames[3];                   ///< checked against the reference
};

void PrintTo(const BartCase& c, std::ostream* out) { *out << c.name; }

class BartScene : public ::testing::TestWithParam<BartCase> {
protected:
    void SetUp() override {
        path_ = fs::path(DYNRT_SHARED_SCENES_DIR) / "bart" / GetParam().file;
        if (!fs::exists(path_)) GTEST_SKIP() << path_ << " does not exist";
    }
    fs::path path_;
};

TEST_P(BartScene, LoadsWithItsOwnViewFramesAndClasses) {
    const BartCase& c = GetParam();
    const Scene scene = load_scene(path_.string());
    EXPECT_EQ(scene.triangle_count(), c.triangles);
    ASSERT_TRUE(scene.setup.has_value());
    EXPECT_EQ(scene.setup->frame_count, c.frame_count);
    EXPECT_EQ(scene.cameras.size(), 1u);
    const anim::ScenePoser poser(scene, own_rate(scene));
    anim::MotionClass most = anim::MotionClass::static_;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) most = std::max(most, poser.derived_class(i));
    EXPECT_EQ(most, c.most_general);
    // Every frame of the sequence poses to finite positions (pose throws otherwise) and a
    // camera; spot-check the ends and the middle.
    anim::PosedScene posed;
    for (int f : {0, c.frame_count / 2, c.frame_count - 1}) {
        poser.pose(f, posed);
        ASSERT_TRUE(posed.camera.has_value());
    }
}

// Heavy: the reference is brute force over every triangle for every ray (skipped under the
// sanitizers, see scripts/test.sh).
TEST_P(BartScene, HeavyFramesAgreeWithTheExactReference) {
    const BartCase& c = GetParam();
    const Scene scene = load_scene(path_.string());
    RenderOptions options;
    options.width = 20;
    options.height = 15;
    options.pose.fps = scene.setup->fps;
    options.background = scene.setup->background;
    Renderer renderer(options);
    RenderedFrame frame;
    for (const int f : c.frames) {
        SCOPED_TRACE("frame " + std::to_string(f));
        renderer.update(scene, f);
        const Camera camera = camera_from_scene(*renderer.posed().camera);
        renderer.trace(camera, frame);
        anim::PosedScene posed;
        anim::pose_scene(scene, options.pose, f, posed);
        const reference::ReferenceTracer tracer(scene, posed);
        const reference::ReferenceFrame ref = reference::render_reference(
            scene, tracer, camera, options.width, options.height, reference::shading_from(scene, options));
        const reference::ImageComparison cmp = reference::compare_images(frame, ref);
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.pixels - cmp.hit_mismatches, 0);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Bart, BartScene,
    ::testing::Values(
        BartCase{"kitchen", "kitchen/kitchen.aff", 110561, 800, anim::MotionClass::rigid, {0, 400, 799}},
        BartCase{"robots", "robots/Robot.aff", 71708, 800, anim::MotionClass::rigid, {0, 400, 799}},
        // Museum: a 10,000-triangle mesh, 133 polygons fanned into 274 triangles, 10 `tt`
        // triangles, 8 cylinders of 2 triangles per segment and 1,024 `tpa` triangles.
        BartCase{"museum", "museum/museum5.aff", 10000 + 274 + 10 + 8 * 2 * aff::kAffConeSegments + 1024, 300,
                 anim::MotionClass::deformable, {0, 150, 299}}),
    [](const ::testing::TestParamInfo<BartCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace dynrt
