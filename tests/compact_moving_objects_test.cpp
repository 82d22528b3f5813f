// Moving objects' trees with compact leaves (UpdatePolicy::compact_moving_objects, `--leaves
// compact`): their leaves read the posed vertices in place. Over a sequence that refits,
// rebuilds and keeps them (a waving indexed sphere, an exploding soup, a sphere treated as
// exploding, under each update method) every frame is the same as with full blocks bit for bit
// (colour, depth, object, triangle and normal of every pixel), for packets and single rays, and
// matches the exact reference; the trees hold fewer bytes, and an indexed mesh keeps no copy of
// its triangles. Switching the layout between frames swaps the trees at once.

#include "dynrt/reference/image_comparison.h"

#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene.h"

#include "reference_shot.h"
#include "same_frame.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dynrt {
namespace {


const std::string kWaving = "sphere:3000@0,0,0,1";
const std::string kSoup = "soup:2000";
const std::string kTreatedExploding = "sphere:800@-1.8,0.3,0,0.6";

/// The three moving objects over a static plane.
Scene compact_test_scene() {
    Scene scene = load_scene(kWaving + "+" + kSoup + "+" + kTreatedExploding + "+plane:1@0,-1.5,0,8");
    anim::add_procedural_motions(
        scene, std::vector<std::string>{"wave:" + kWaving, "explode:" + kSoup, "wave:" + kTreatedExploding});
    return scene;
}

RenderOptions compact_test_options(const Scene& scene, UpdateMethod method) {
    RenderOptions options;
    options.width = 72;
    options.height = 56;
    options.method = method;
    options.rebuild_threshold = 0.05;  // threshold: refits and rebuilds both
    options.pose.class_overrides =
        anim::parse_class_overrides(scene, std::vector<std::string>{kTreatedExploding + "=exploding"});
    return options;
}

TEST(CompactMovingObjects, DrawEveryFrameAsFullBlocksDoAndHoldFewerBytes) {
    const Scene scene = compact_test_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    // Frame 4 twice: nothing moves, and the kept trees view this update's vertices.
    const std::vector<int> frames{0, 1, 2, 4, 4, 7, 12};
    for (const UpdateMethod method : {UpdateMethod::automatic, UpdateMethod::threshold, UpdateMethod::fast}) {
        for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
            SCOPED_TRACE("method " + std::to_string(int(method)) + (tracer == Tracer::packet ? ", packets" : ", single rays"));
            RenderOptions options = compact_test_options(scene, method);
            options.tracer = tracer;
            Renderer full_renderer(options);
            RenderOptions compact = options;
            compact.compact_moving_objects = true;
            Renderer compact_renderer(compact);
            std::size_t refitted = 0, rebuilt = 0, skipped = 0;
            for (std::size_t k = 0; k < frames.size(); ++k) {
                const int f = frames[k];
                SCOPED_TRACE("frame " + std::to_string(f));
                const test::FramePair frame = test::render_alike(full_renderer, compact_renderer, scene, camera, f);
                const RenderedFrame& full_frame = frame.reference;
                const RenderedFrame& compact_frame = frame.candidate;
                ASSERT_EQ(compact_frame.stats.exploding_objects, 1u);
                ASSERT_EQ(compact_frame.stats.deformable_objects, 2u);
                if (k > 0) {
                    refitted += compact_frame.stats.objects_refitted;
                    rebuilt += compact_frame.stats.objects_rebuilt;
                    skipped += compact_frame.stats.objects_skipped;
                }
                if (f == 0) {
                    // The blocks' 36 bytes of corners a triangle (less the unused lanes'
                    // share) are gone, and the indexed spheres' copies of their triangles.
                    const std::size_t moving = compact_frame.stats.deformable_triangles + compact_frame.stats.exploding_triangles;
                    EXPECT_LT(compact_frame.stats.tree_bytes + 30 * moving, full_frame.stats.tree_bytes);
                    EXPECT_LT(100 * compact_frame.stats.build_triangle_bytes, full_frame.stats.build_triangle_bytes);
                }
                if (k == 3 && tracer == Tracer::packet) {
                    const reference::ImageComparison cmp =
                        reference::compare_images(compact_frame, test::reference_shot(scene, camera, options, nullptr, f));
                    EXPECT_TRUE(cmp.passed()) << cmp.summary();
                }
            }
            // The sequence did what it is here for.
            EXPECT_GT(rebuilt, 0u);
            if (method != UpdateMethod::fast) {
                EXPECT_GT(refitted, 0u);
            }
            EXPECT_GT(skipped, 0u);  // the plane, and every object on the repeated frame
        }
    }
}

TEST(CompactMovingObjects, SwitchingTheLayoutBetweenFramesSwapsTheTrees) {
    const Scene scene = compact_test_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    const RenderOptions options = compact_test_options(scene, UpdateMethod::threshold);
    Renderer reference(options), switching(options);
    for (int f = 0; f < 8; ++f) {
        SCOPED_TRACE("frame " + std::to_string(f));
        RenderOptions now = options;
        now.compact_moving_objects = f >= 2 && f < 5;
        switching.set_options(now);
        const test::FramePair frame = test::render_alike(reference, switching, scene, camera, f);
        const RenderedFrame& expected = frame.reference;
        const RenderedFrame& got = frame.candidate;
        // A refit keeps the layout a tree has: the switch rebuilds each moving tree once.
        if (f == 2 || f == 5) {
            EXPECT_EQ(got.stats.objects_rebuilt, 3u);
        }
        if (f == 3) {
            EXPECT_LT(got.stats.tree_bytes, expected.stats.tree_bytes);
        }
    }
}

}  // namespace
}  // namespace dynrt
