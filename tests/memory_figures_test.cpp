// Memory as a report figure (issue 43; FrameStats' MemoryStats): the scene model's bytes
// counted exactly, the trees and the triangles they are built from as SceneAccel holds them,
// the renderer's total above both, the resident set read back, the report's "memory" object
// round-tripping (and absent from older reports), and `dynrt render`'s line per triangle.

#include "dynrt/bvh/triangle_source.h"
#include "moving_scene.h"

#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/report.h"
#include "dynrt/engine/resident_memory.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_bytes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <vector>
#include <string>

namespace dynrt {
namespace memory_figures_test {

TEST(SceneBytes, CountsEveryMeshArrayAndTexture) {
    Scene scene;
    Object& a = scene.objects.emplace_back();
    a.mesh.positions.resize(10);
    a.mesh.triangles.resize(7);
    a.mesh.normals.resize(10);
    a.mesh.texcoords.resize(10);
    Object& b = scene.objects.emplace_back();
    b.mesh.positions.resize(3);
    b.mesh.triangles.resize(1);
    Texture& t = scene.textures.emplace_back();
    t.encoded.resize(1000);
    const std::size_t arrays = 13 * 12 + 8 * 12 + 10 * 12 + 10 * 8 + 1000;
    const std::size_t records = scene.objects.capacity() * sizeof(Object) + scene.textures.capacity() * sizeof(Texture);
    EXPECT_EQ(scene_bytes(scene), arrays + records);
    // Capacity, not size: what stays allocated.
    b.mesh.positions.reserve(100);
    EXPECT_EQ(scene_bytes(scene), arrays + records + 97 * 12);
}

TEST(MemoryFigures, ARenderReportsTheSceneTheTreesAndTheProcess) {
    const Scene scene = test::moving_scene();
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    Renderer renderer(options);
    RenderedFrame frame;
    const Camera camera = default_camera(scene_bounds(scene));
    for (const int f : {0, 3}) {
        SCOPED_TRACE("frame " + std::to_string(f));
        renderer.render(scene, camera, f, frame);
        const FrameStats& s = frame.stats;
        EXPECT_EQ(s.scene_bytes, scene_bytes(scene));
        // Every triangle is in a wide tree's blocks (at least 36 bytes of corners each). A
        // moving object with index triples keeps the copy its tree is built from (36 bytes a
        // triangle, refitted from); the static group and a moving soup only an index into
        // their blocks (4 bytes).
        EXPECT_GE(s.tree_bytes, s.wide_tree_bytes);
        EXPECT_GE(s.tree_bytes, 36 * s.triangles);
        const auto copied = [&](const ObjectMemory& m) {
            return m.object >= 0 &&
                   !bvh::TriangleSource::is_soup(scene.objects[std::size_t(m.object)].mesh.triangles);
        };
        std::size_t copied_triangles = 0, soups = 0;
        for (const ObjectMemory& m : s.largest) {
            if (copied(m)) copied_triangles += m.triangles;
            if (m.object >= 0 && !copied(m)) ++soups;
        }
        ASSERT_GT(copied_triangles, 0u);
        ASSERT_GT(soups, 0u);
        EXPECT_EQ(s.build_triangle_bytes, 4 * (s.triangles - copied_triangles) + 36 * copied_triangles);
        EXPECT_GT(s.renderer_bytes, s.tree_bytes + s.build_triangle_bytes);
        // The holders: the static floor's group and the three moving objects, largest first,
        // each with its own counts.
        ASSERT_EQ(s.largest.size(), 4u);
        std::size_t trees = 0, triangles = 0;
        for (std::size_t k = 0; k < s.largest.size(); ++k) {
            const ObjectMemory& m = s.largest[k];
            if (k > 0) {
                EXPECT_GE(s.largest[k - 1].bytes(), m.bytes());
            }
            EXPECT_EQ(m.build_triangle_bytes, (copied(m) ? 36 : 4) * m.triangles) << m.name;
            trees += m.tree_bytes;
            triangles += m.triangles;
            if (m.object >= 0) {
                EXPECT_EQ(m.name, scene.objects[std::size_t(m.object)].name);
                EXPECT_EQ(m.scene_bytes, object_bytes(scene.objects[std::size_t(m.object)]));
            } else {
                EXPECT_EQ(m.name, "static objects (1)");
            }
        }
        EXPECT_EQ(triangles, s.triangles);
        EXPECT_LE(trees, s.tree_bytes);  // the top level besides
#ifdef __linux__
        EXPECT_GT(s.rss_bytes, s.renderer_bytes);
        EXPECT_GE(s.peak_rss_bytes, s.rss_bytes);
#endif
    }
}

TEST(MemoryFigures, TheReportRoundTripsThemAndReadsOlderReportsWithout) {
    FrameStats s;
    s.triangles = 1000;
    s.scene_bytes = 24000;
    s.tree_bytes = 66000;
    s.build_triangle_bytes = 36000;
    s.renderer_bytes = 150000;
    s.rss_bytes = 300000;
    s.peak_rss_bytes = 304000;
    s.largest = {ObjectMemory{-1, "static objects (3)", 800, 20000, 50000, 28800},
                 ObjectMemory{4, "robot", 200, 4000, 16000, 7200}};
    const std::string json = frame_report_json(s);
    const FrameStats back = parse_frame_report_json(json);
    EXPECT_EQ(back.scene_bytes, s.scene_bytes);
    EXPECT_EQ(back.tree_bytes, s.tree_bytes);
    EXPECT_EQ(back.build_triangle_bytes, s.build_triangle_bytes);
    EXPECT_EQ(back.renderer_bytes, s.renderer_bytes);
    EXPECT_EQ(back.rss_bytes, s.rss_bytes);
    EXPECT_EQ(back.peak_rss_bytes, s.peak_rss_bytes);
    ASSERT_EQ(back.largest.size(), 2u);
    EXPECT_EQ(back.largest[1].object, 4);
    EXPECT_EQ(back.largest[1].name, "robot");
    EXPECT_EQ(back.largest[1].triangles, 200u);
    EXPECT_EQ(back.largest[1].scene_bytes, 4000u);
    EXPECT_EQ(back.largest[1].tree_bytes, 16000u);
    EXPECT_EQ(back.largest[1].build_triangle_bytes, 7200u);
    nlohmann::json older = nlohmann::json::parse(json);
    older.erase("memory");
    const FrameStats old = parse_frame_report_json(older.dump());
    EXPECT_EQ(old.peak_rss_bytes, 0u);
    EXPECT_EQ(old.triangles, 1000u);
    std::ostringstream line;
    print_memory(line, {s});
    EXPECT_EQ(line.str(), "memory per triangle: scene 24 B, trees 66 B, build triangles 36 B, renderer in all 150 B; "
                          "resident peak 304 B (0.0 GB)\n"
                          "largest: static objects (3) 0.1 MB, robot 0.0 MB\n");
    std::ostringstream nothing;
    print_memory(nothing, {FrameStats{}});
    EXPECT_EQ(nothing.str(), "");
}

#ifdef __linux__
TEST(ResidentMemory, ReadsTheProcessAndRestartsItsPeak) {
    const ResidentMemory before = resident_memory();
    EXPECT_GT(before.current, 0u);
    EXPECT_GE(before.peak, before.current);
    {
        // 64 MB touched: the peak rises by about that.
        std::vector<char> big(64u << 20, 1);
        const ResidentMemory during = resident_memory();
        EXPECT_GE(during.peak, before.current + (48u << 20));
        volatile char sink = big[12345];
        (void)sink;
    }
#ifndef __SANITIZE_ADDRESS__  // AddressSanitizer keeps freed memory (its quarantine) resident
    if (restart_peak_resident()) {
        const ResidentMemory after = resident_memory();
        EXPECT_LT(after.peak, before.current + (32u << 20)) << "the peak did not start over";
    }
#endif
}

TEST(ResidentMemory, ReadsWhatTheMachineHasAvailable) {
    // Some memory is available, and no more than the machine has, as /proc/meminfo says.
    const std::size_t available = available_memory();
    EXPECT_GT(available, 0u);
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::size_t total_kb = 0;
    while (meminfo >> key >> total_kb && key != "MemTotal:") meminfo.ignore(256, '\n');
    EXPECT_LE(available, total_kb * 1024);
    EXPECT_GE(available, resident_memory().current / 1024) << "read in kilobytes, not bytes";
}
#endif

}  // namespace memory_figures_test
}  // namespace dynrt
