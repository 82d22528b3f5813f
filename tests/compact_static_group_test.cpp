// The static group with compact leaves (UpdatePolicy::compact_static_group, `--leaves
// compact`), quantised nodes (UpdatePolicy::quantized_static_group, `--nodes quantized`) or
// both: every frame the same as with full blocks and float nodes bit for bit (colour, depth,
// object, triangle and normal of every pixel), for packets and single rays, over static objects
// at the identity (their leaves read the scene's own vertices) and under transforms (vertices
// the group makes and holds), on later frames too; and the tree's bytes fall by the blocks'
// vertices or half the nodes. Matched against the exact reference as well, so that "the same
// as full blocks" cannot hide an error both share.

#include "dynrt/reference/image_comparison.h"

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

using test::expect_same_frame;

TEST(CompactStaticGroup, DrawsEveryFrameAsFullBlocksDoAndHoldsFewerBytes) {
    // A plane and a sphere at the identity, nine transformed soups, and the bundled glTF
    // scene's static objects (nodes under transforms, shared meshes).
    for (const std::string& spec : {std::string("plane:1@0,-1,0,8+sphere:2000+soup:300*9#40c060"), std::string()}) {
        SCOPED_TRACE(spec.empty() ? "bundled scene" : spec);
        const Scene scene = load_scene(spec.empty() ? default_scene_path().string() : spec);
        const Camera camera = default_camera(scene_bounds(scene));
        RenderOptions options;
        options.width = 80;
        options.height = 60;
        for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
            options.tracer = tracer;
            Renderer full_renderer(options);
            // Compact leaves, quantised nodes (`--nodes quantized`) and both.
            struct Layout {
                bool compact, quantized;
            };
            for (const Layout layout : {Layout{true, false}, Layout{false, true}, Layout{true, true}}) {
                SCOPED_TRACE(std::string(layout.compact ? "compact leaves" : "full blocks") +
                             (layout.quantized ? ", quantised nodes" : ""));
                RenderOptions other = options;
                other.compact_static_group = layout.compact;
                other.quantized_static_group = layout.quantized;
                Renderer compact_renderer(other);
                for (int f : {0, 1, 5}) {
                    SCOPED_TRACE("frame " + std::to_string(f));
                    const test::FramePair frame = test::render_alike(full_renderer, compact_renderer, scene, camera, f);
                    const RenderedFrame& full = frame.reference;
                    const RenderedFrame& compact = frame.candidate;
                    EXPECT_GT(compact.stats.static_objects, 0u);
                    EXPECT_EQ(compact.stats.triangles, full.stats.triangles);
                    if (f != 0) continue;
                    if (layout.compact) {
                        // The blocks' 36 bytes of corners a triangle (less the unused lanes'
                        // share) are gone, the scene's vertices read instead.
                        EXPECT_LT(compact.stats.tree_bytes + 30 * compact.stats.static_triangles,
                                  full.stats.tree_bytes);
                    } else {
                        // Half of each node's 256 bytes: at least 128 bytes per 32 triangles
                        // (eight leaves of four a node at best).
                        EXPECT_LE(compact.stats.tree_bytes + 4 * compact.stats.static_triangles,
                                  full.stats.tree_bytes);
                    }
                    const reference::ImageComparison cmp = reference::compare_images(compact, test::reference_shot(scene, camera, options));
                    EXPECT_TRUE(cmp.passed()) << cmp.summary();
                }
            }
        }
    }
}

TEST(CompactStaticGroup, WithoutTheWideTreeTheGroupKeepsItsOwnTriangles) {
    // Compact leaves are the wide tree's: asked for with the binary tree (--bvh binary), the
    // group gathers its triangles from what the build read, before letting it go (a read of
    // freed vertices here is what ASan would report).
    const Scene scene = load_scene("plane:1@0,-1,0,8+soup:300*4");
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = 48;
    options.height = 32;
    options.build.wide = false;
    RenderedFrame full, compact;
    Renderer(options).render(scene, camera, 0, full);
    options.compact_static_group = true;
    Renderer(options).render(scene, camera, 0, compact);
    expect_same_frame(compact, full);
    EXPECT_EQ(compact.stats.tree_bytes, full.stats.tree_bytes);
}

}  // namespace
}  // namespace dynrt
