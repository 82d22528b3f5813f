// Animated sequences through the per-frame update: every frame of a render that keeps its
// trees across frames (static objects built once, rigid ones instanced, deformable ones
// refitted or rebuilt, exploding ones rebuilt) must agree with the exact reference on a
// flattened copy of that frame's triangles, for each class, for forced classes, for both
// tracers; and the report must say what was done to each object.

#include "gltf_test_file.h"
#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace dynrt::reference {
namespace {

// A static ground plane, a sphere turning about its centre (rigid), a sphere in a wave
// (deformable) and a soup flying apart (deformable too: the same triangles, moved; the
// variants and the report test force it to exploding, where it is rebuilt every frame).
const std::string kPlane = "plane:8@0,-1,0,4#808080";
const std::string kRigid = "sphere:600@-0.8,-0.4,0.3,0.6#e04020";
const std::string kWave = "sphere:300@1.2,-0.5,-0.6,0.5#2050e0";
const std::string kExplode = "soup:600@-0.6,-1,-2,1.4#40c060";

Scene animated_scene() {
    Scene scene = load_scene(kPlane + "+" + kRigid + "+" + kWave + "+" + kExplode);
    const std::vector<std::string> motions{"rigid:" + kRigid, "wave:" + kWave, "explode:" + kExplode};
    anim::add_procedural_motions(scene, motions);
    return scene;
}

struct Variant {
    std::string name;
    Tracer tracer = Tracer::packet;
    /// With UpdateMethod::threshold: 0 rebuilds deformable objects on any degradation; +inf
    /// only ever refits.
    double rebuild_threshold = 0.3;
    std::vector<std::string> treat;
    UpdateMethod method = UpdateMethod::automatic;
};

void PrintTo(const Variant& v, std::ostream* out) { *out << v.name; }

class AnimatedRender : public ::testing::TestWithParam<Variant> {};

// Frames in the order a sequence plays them, with a repeat (no work) and a jump back.
constexpr int kFrames[] = {0, 1, 2, 3, 3, 8, 20, 4};

TEST_P(AnimatedRender, EveryFrameMatchesTheExactReference) {
    const Variant& variant = GetParam();
    const Scene scene = animated_scene();
    RenderOptions options;
    options.width = 48;
    options.height = 40;
    options.tracer = variant.tracer;
    options.rebuild_threshold = variant.rebuild_threshold;
    options.method = variant.method;
    options.pose.class_overrides = anim::parse_class_overrides(scene, variant.treat);
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer renderer(options);
    RenderedFrame frame;
    for (const int f : kFrames) {
        SCOPED_TRACE("frame " + std::to_string(f));
        renderer.render(scene, camera, f, frame);
        anim::PosedScene posed;
        anim::pose_scene(scene, options.pose, f, posed);
        const ReferenceTracer tracer(scene, posed);
        const ReferenceFrame ref = render_reference(scene, tracer, camera, options.width,
                                                    options.height, shading_from(scene, options));
        const ImageComparison cmp = compare_images(frame, ref);
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
        EXPECT_GT(cmp.pixels - cmp.hit_mismatches, 0);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Classes, AnimatedRender,
    ::testing::Values(
        Variant{"packet_default", Tracer::packet, 0.3, {}},
        Variant{"single_default", Tracer::single, 0.3, {}},
        Variant{"packet_explode_exploding", Tracer::packet, 0.3, {kExplode + "=exploding"}},
        Variant{"single_explode_exploding", Tracer::single, 0.3, {kExplode + "=exploding"}},
        Variant{"packet_always_rebuild", Tracer::packet, 0.0, {}, UpdateMethod::threshold},
        Variant{"packet_never_rebuild", Tracer::packet, std::numeric_limits<double>::infinity(), {},
                UpdateMethod::threshold},
        // Every update method: the fast (Morton) builder's trees every frame, with the
        // exploding soup too, the binned SAH builder's every frame, refits only.
        Variant{"packet_fast", Tracer::packet, 0.3, {}, UpdateMethod::fast},
        Variant{"single_fast", Tracer::single, 0.3, {}, UpdateMethod::fast},
        Variant{"packet_fast_exploding", Tracer::packet, 0.3, {kExplode + "=exploding"},
                UpdateMethod::fast},
        Variant{"packet_sah", Tracer::packet, 0.3, {}, UpdateMethod::sah},
        Variant{"packet_refit", Tracer::packet, 0.3, {kExplode + "=exploding"},
                UpdateMethod::refit},
        Variant{"packet_all_exploding", Tracer::packet, 0.3,
                {kPlane + "=exploding", kRigid + "=exploding", kWave + "=exploding",
                 kExplode + "=exploding"}},
        Variant{"single_raised", Tracer::single, 0.3,
                {kPlane + "=rigid", kRigid + "=deformable"}}),
    [](const ::testing::TestParamInfo<Variant>& info) { return info.param.name; });

TEST(AnimatedRender, ReportSaysWhatEachObjectCost) {
    const Scene scene = animated_scene();
    RenderOptions options;
    options.width = 32;
    options.height = 32;
    // One object of each class: the soup's explode alone would make it deformable.
    options.pose.class_overrides =
        anim::parse_class_overrides(scene, std::vector<std::string>{kExplode + "=exploding"});
    // Refits stand: a fixed method, since the automatic one's choices depend on measured times.
    options.method = UpdateMethod::threshold;
    options.rebuild_threshold = std::numeric_limits<double>::infinity();
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer renderer(options);
    RenderedFrame frame;

    renderer.render(scene, camera, 0, frame);
    const FrameStats first = frame.stats;
    EXPECT_EQ(first.static_objects, 1u);
    EXPECT_EQ(first.rigid_objects, 1u);
    EXPECT_EQ(first.deformable_objects, 1u);
    EXPECT_EQ(first.exploding_objects, 1u);
    EXPECT_EQ(first.static_triangles + first.rigid_triangles + first.deformable_triangles +
                  first.exploding_triangles,
              scene.triangle_count());
    ASSERT_EQ(first.rebuilds.size(), 4u);
    for (const TreeRebuild& r : first.rebuilds) EXPECT_EQ(r.reason, RebuildReason::first_build) << r.name;
    EXPECT_EQ(first.objects_rebuilt, 4u);

    // Frame 1: the plane and the rigid sphere cost no bottom-level work, the wave is refitted,
    // the soup rebuilt.
    renderer.render(scene, camera, 1, frame);
    const FrameStats second = frame.stats;
    EXPECT_EQ(second.objects_skipped, 2u);
    EXPECT_EQ(second.objects_refitted, 1u);
    EXPECT_EQ(second.triangles_refitted, scene.objects[2].mesh.triangles.size());
    ASSERT_EQ(second.rebuilds.size(), 1u);
    EXPECT_EQ(second.rebuilds[0].name, kExplode);
    EXPECT_EQ(second.rebuilds[0].reason, RebuildReason::exploding);
    EXPECT_EQ(second.triangles_rebuilt, scene.objects[3].mesh.triangles.size());

    // The same frame again: nothing changed, so no object is touched.
    renderer.render(scene, camera, 1, frame);
    EXPECT_EQ(frame.stats.objects_skipped, 4u);
    EXPECT_EQ(frame.stats.objects_refitted, 0u);
    EXPECT_EQ(frame.stats.objects_rebuilt, 0u);
    EXPECT_TRUE(frame.stats.rebuilds.empty());
    EXPECT_EQ(frame.stats.refit_ms + frame.stats.rebuild_ms, 0.0);
}

TEST(AnimatedRender, DegradedRefitsAreRebuiltAndSaySo) {
    Scene scene = load_scene("sphere:2000");
    const std::vector<std::string> motions{"wave"};
    anim::add_procedural_motions(scene, motions);
    RenderOptions options;
    options.width = 16;
    options.height = 16;
    options.method = UpdateMethod::threshold;
    options.rebuild_threshold = 0.0;  // any degradation triggers a rebuild
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    int degraded = 0;
    for (int f = 1; f <= 12; ++f) {
        renderer.render(scene, camera, f, frame);
        EXPECT_EQ(frame.stats.objects_refitted, 1u);
        for (const TreeRebuild& r : frame.stats.rebuilds) {
            EXPECT_EQ(r.reason, RebuildReason::sah_degraded);
            EXPECT_GT(r.sah_refitted, r.sah_at_last_build);
            ++degraded;
        }
    }
    // A wave both raises and lowers the cost from frame to frame; with threshold 0 at least
    // one frame must have been rebuilt.
    EXPECT_GT(degraded, 0);
}

TEST(AnimatedRender, AnimatedDataThatMovesNoVertexCostsNoRefit) {
    // A morph target whose deltas are all zero, with animated weights: the animation data
    // says "deformable, changed" every frame, the vertices never move.
    test::GltfTestFile f;
    const int target = f.add_floats({0, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC3");
    const int mesh = f.add_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, nlohmann::json::object(),
                                nlohmann::json::array({nlohmann::json{{"POSITION", target}}}), "flat");
    const int node = f.add_node({{"name", "flat"}, {"mesh", mesh}});
    f.add_animation("Breathe", {{node, "weights", {0, 1}, {0, 1}}});
    const Scene scene = load_scene(f.write("still_morph.gltf").string());
    RenderOptions options;
    options.width = 8;
    options.height = 8;
    Renderer renderer(options);
    RenderedFrame frame;
    const Camera camera = default_camera(scene_bounds(scene));
    renderer.render(scene, camera, 0, frame);
    renderer.render(scene, camera, 6, frame);
    EXPECT_EQ(frame.stats.deformable_objects, 1u);
    EXPECT_EQ(frame.stats.objects_skipped, 1u);
    EXPECT_EQ(frame.stats.objects_refitted, 0u);
    EXPECT_EQ(frame.stats.objects_rebuilt, 0u);
}

// A skinned glTF sequence under every update method: the skinned mesh is deformable, so its
// tree is refitted, rebuilt fast (Morton) or rebuilt with the binned SAH; every frame must
// still match the reference.
TEST(AnimatedRender, SkinnedSequenceMatchesTheReferenceUnderEveryMethod) {
    const std::string path = std::string(DYNRT_SHARED_SCENES_DIR) + "/cesiumman/CesiumMan.glb";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " does not exist";
    const Scene scene = load_scene(path);
    const Camera camera = default_camera(scene_bounds(scene));
    for (UpdateMethod method : {UpdateMethod::automatic, UpdateMethod::fast, UpdateMethod::sah,
                                UpdateMethod::refit}) {
        RenderOptions options;
        options.width = 40;
        options.height = 40;
        options.method = method;
        Renderer renderer(options);
        RenderedFrame frame;
        for (const int f : {0, 5, 10, 17}) {
            SCOPED_TRACE(std::string(update_method_name(method)) + ", frame " + std::to_string(f));
            renderer.render(scene, camera, f, frame);
            anim::PosedScene posed;
            anim::pose_scene(scene, options.pose, f, posed);
            const ReferenceTracer tracer(scene, posed);
            const ImageComparison cmp =
                compare_images(frame, render_reference(scene, tracer, camera, options.width,
                                                       options.height, shading_from(scene, options)));
            EXPECT_TRUE(cmp.passed()) << cmp.summary();
            EXPECT_GT(cmp.pixels - cmp.hit_mismatches, 0);
            if (f > 0 && method == UpdateMethod::fast) {
                ASSERT_EQ(frame.stats.rebuilds.size(), 1u);
                EXPECT_EQ(frame.stats.rebuilds[0].builder, "morton");
            }
        }
    }
}

// The automatic method says what it chose for every changed deformable or exploding object,
// with the predictions behind it; the fixed methods choose nothing.
TEST(AnimatedRender, AutomaticMethodSaysWhatItChoseAndWhy) {
    const Scene scene = animated_scene();
    RenderOptions options;
    options.width = 24;
    options.height = 24;
    const std::vector<std::string> treat{kExplode + "=exploding"};
    options.pose.class_overrides = anim::parse_class_overrides(scene, treat);
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    EXPECT_TRUE(frame.stats.choices.empty());  // first builds: nothing to choose between
    renderer.render(scene, camera, 1, frame);
    ASSERT_EQ(frame.stats.choices.size(), 2u);  // the wave and the exploding soup
    for (const TreeChoice& c : frame.stats.choices) {
        if (c.name == kWave) {
            // Which one depends on the measured times (a slow machine or a sanitizer changes
            // them); the reason must match the choice either way.
            if (c.chosen == "refit") {
                EXPECT_NE(c.why.find(" < rebuild"), std::string::npos) << c.why;
            } else {
                EXPECT_NE(c.why.find(">= "), std::string::npos) << c.chosen << ": " << c.why;
            }
        } else {
            EXPECT_EQ(c.name, kExplode);
            EXPECT_TRUE(c.chosen == "rebuild (fast)" || c.chosen == "rebuild (sah)") << c.chosen;
            EXPECT_NE(c.why.find("fast"), std::string::npos) << c.why;
        }
    }
    options.method = UpdateMethod::fast;
    Renderer fixed(options);
    fixed.render(scene, camera, 0, frame);
    fixed.render(scene, camera, 1, frame);
    EXPECT_TRUE(frame.stats.choices.empty());
    EXPECT_EQ(frame.stats.objects_refitted, 0u);
    EXPECT_EQ(frame.stats.objects_rebuilt, 2u);
}

TEST(AnimatedRender, EditingASceneNeedsReset) {
    Scene scene = load_scene("sphere:500");
    RenderOptions options;
    options.width = 24;
    options.height = 24;
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer renderer(options);
    RenderedFrame before, after;
    renderer.render(scene, camera, 0, before);
    for (glm::vec3& p : scene.objects[0].mesh.positions.edit()) p *= 0.5f;
    renderer.reset();
    renderer.render(scene, camera, 0, after);
    EXPECT_EQ(after.stats.objects_rebuilt, 1u);
    EXPECT_NE(before.depth, after.depth);
    EXPECT_THROW(Renderer(options).trace(camera, after), std::logic_error);
}

}  // namespace
}  // namespace dynrt::reference
