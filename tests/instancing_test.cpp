// Instancing (issue 43): a mesh's arrays shared by its copies (SharedArray); the procedural
// `kind:N*K` copies, glTF nodes that reference one mesh and `FILE*K` copies sharing it; the
// scene's bytes counting a shared array once; and the renderer carrying one tree for every
// rigid copy, and for static copies once the static group would pass its limit, with images
// that match the exact reference and, for rigid copies, the images of the same scene with
// every copy's tree built on its own.

#include "gltf_test_file.h"
#include "reference_shot.h"

#include "dynrt/reference/image_comparison.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_bytes.h"
#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/shared_array.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace dynrt::reference {
namespace {

RenderedFrame render(const Scene& scene, const RenderOptions& options, int f);
void expect_matches_reference(const Scene& scene, const RenderOptions& options, int f, const RenderedFrame& frame);

TEST(SharedArray, CopiesShareUntilOneIsWritten) {
    SharedArray<int> a = std::vector<int>{1, 2, 3};
    SharedArray<int> b = a;
    EXPECT_TRUE(a.shares_storage_with(b));
    EXPECT_EQ(a.holders(), 2);
    EXPECT_EQ(b.data(), a.data());
    // A read through a non-const array copies nothing.
    int sum = 0;
    for (const int v : b) sum += v;
    EXPECT_EQ(sum + b[1], 8);
    EXPECT_TRUE(a.shares_storage_with(b));
    // A write gives the writer its own copy; the other keeps the old elements.
    b.edit()[0] = 7;
    EXPECT_FALSE(a.shares_storage_with(b));
    EXPECT_EQ(a[0], 1);
    EXPECT_EQ(b[0], 7);
    b.push_back(4);
    EXPECT_EQ(b.size(), 4u);
    EXPECT_EQ(a.size(), 3u);
    // An unshared array is written in place.
    const int* before = b.data();
    b.edit()[1] = 9;
    EXPECT_EQ(b.data(), before);
    // Empty arrays hold nothing and share nothing.
    SharedArray<int> none;
    EXPECT_TRUE(none.empty());
    EXPECT_EQ(none.data(), nullptr);
    EXPECT_FALSE(none.shares_storage_with(SharedArray<int>()));
    EXPECT_TRUE(none.vector().empty());
    none.insert(none.end(), {5, 6});
    EXPECT_EQ(none, (SharedArray<int>{5, 6}));
}

TEST(SceneBytes, ASharedMeshCountsOnce) {
    Scene scene;
    Object& a = scene.objects.emplace_back();
    a.mesh.positions.resize(10);
    a.mesh.triangles.resize(4);
    scene.objects.push_back(scene.objects[0]);
    scene.objects.push_back(scene.objects[0]);
    const std::size_t mesh = 10 * 12 + 4 * 12;
    const std::size_t records = scene.objects.capacity() * sizeof(Object);
    EXPECT_EQ(scene_bytes(scene), mesh + records);
    // Each object's own figure is the whole mesh it holds.
    EXPECT_EQ(object_bytes(scene.objects[2]), mesh);
    // One copy written: its positions are its own now, and counted.
    scene.objects[1].mesh.positions.edit()[0].x = 1.0f;
    EXPECT_EQ(scene_bytes(scene), mesh + 10 * 12 + records);
}

TEST(ProceduralCopies, ShareOneMeshOnAGrid) {
    const Scene scene = load_scene("plane:1@0,-1,0,8+sphere:200*5#c04030");
    ASSERT_EQ(scene.objects.size(), 6u);
    const Object& first = scene.objects[1];
    EXPECT_EQ(first.name, "sphere:200*5#c04030[0]");
    EXPECT_EQ(scene.objects[5].name, "sphere:200*5#c04030[4]");
    EXPECT_FALSE(first.mesh.normals.empty());
    std::vector<glm::vec3> origins;
    for (std::size_t i = 1; i < scene.objects.size(); ++i) {
        const Object& copy = scene.objects[i];
        EXPECT_TRUE(copy.mesh.positions.shares_storage_with(first.mesh.positions));
        EXPECT_TRUE(copy.mesh.triangles.shares_storage_with(first.mesh.triangles));
        EXPECT_TRUE(copy.mesh.normals.shares_storage_with(first.mesh.normals));
        EXPECT_EQ(copy.material, first.material);
        const glm::vec3 origin(copy.transform[3]);
        for (const glm::vec3& other : origins) EXPECT_GT(glm::length(origin - other), 2.0f);
        origins.push_back(origin);
    }
    // The scene's triangles count every copy; its bytes one mesh.
    EXPECT_EQ(scene.triangle_count(), 2u + 5 * first.mesh.triangles.size());
    const Scene one = load_scene("plane:1@0,-1,0,8+sphere:200#c04030");
    EXPECT_LT(scene_bytes(scene), scene_bytes(one) + 5 * sizeof(Object));
}

TEST(ProceduralCopies, BadCountsAreNamed) {
    for (const std::string spec : {"sphere:10*0", "sphere:10*1000001", "sphere:10*x", "sphere:10*",
                                   "sphere:10@0,0,0*3", "sphere:10#ffffff*3"}) {
        SCOPED_TRACE(spec);
        try {
            load_scene(spec);
            ADD_FAILURE() << "accepted";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("'" + spec + "'"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("copies"), std::string::npos) << e.what();
        }
    }
}

TEST(GltfInstancing, NodesThatReferenceOneMeshShareItsArrays) {
    test::GltfTestFile file;
    // A quad of two triangles sharing an edge (indexed), so that its normals are computed: a
    // soup would keep none.
    const int mesh = file.add_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    file.doc()["meshes"][mesh]["primitives"][0]["indices"] =
        file.add_accessor(std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}, "SCALAR", test::kGltfUnsignedInt);
    file.add_node({{"name", "a"}, {"mesh", mesh}});
    file.add_node({{"name", "b"}, {"mesh", mesh}, {"translation", {3.0, 0.0, 0.0}}});
    file.add_node({{"name", "c"}, {"mesh", mesh}, {"scale", {2.0, 2.0, 2.0}}});
    const Scene scene = load_scene(file.write("instancing_shared_mesh.gltf").string());
    ASSERT_EQ(scene.objects.size(), 3u);
    for (const Object& object : scene.objects) {
        EXPECT_TRUE(object.mesh.positions.shares_storage_with(scene.objects[0].mesh.positions)) << object.name;
        EXPECT_TRUE(object.mesh.triangles.shares_storage_with(scene.objects[0].mesh.triangles)) << object.name;
        // Normals made for the first copy serve them all.
        EXPECT_FALSE(object.mesh.normals.empty()) << object.name;
        EXPECT_TRUE(object.mesh.normals.shares_storage_with(scene.objects[0].mesh.normals)) << object.name;
    }
    EXPECT_NE(scene.objects[1].transform, scene.objects[0].transform);
    // Drawn as three meshes of their own would be: the reference agrees.
    RenderOptions options;
    options.width = 48;
    options.height = 32;
    expect_matches_reference(scene, options, 0, render(scene, options, 0));
}

TEST(GltfInstancing, MeshesThatReadTheSameAccessorsShareTheirArrays) {
    // Four glTF meshes over one quad's accessors (as MetalRoughSpheres' 102 meshes are one
    // sphere's): the first two read the same positions, normals and indices; the third the
    // same positions with other indices; the fourth morphs the same positions by a target.
    test::GltfTestFile file;
    const int quad = file.add_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    nlohmann::json& primitive = file.doc()["meshes"][quad]["primitives"][0];
    primitive["indices"] =
        file.add_accessor(std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}, "SCALAR", test::kGltfUnsignedInt);
    primitive["attributes"]["NORMAL"] = file.add_floats({0, 0, 2, 0, 0, 2, 0, 0, 2, 0, 0, 2}, "VEC3");
    const nlohmann::json same = file.doc()["meshes"][quad];
    file.doc()["meshes"].push_back(same);
    nlohmann::json other_indices = same;
    other_indices["primitives"][0]["indices"] =
        file.add_accessor(std::vector<std::uint32_t>{0, 1, 3}, "SCALAR", test::kGltfUnsignedInt);
    file.doc()["meshes"].push_back(other_indices);
    nlohmann::json morphed = same;
    morphed["primitives"][0]["targets"] = nlohmann::json::array(
        {{{"POSITION", file.add_floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3")}}});
    morphed["weights"] = {1.0};
    file.doc()["meshes"].push_back(morphed);
    for (int m = 0; m < 4; ++m) {
        file.add_node({{"name", "n" + std::to_string(m)}, {"mesh", m}, {"translation", {2.0 * m, 0.0, 0.0}}});
    }
    const Scene scene = load_scene(file.write("instancing_shared_accessors.gltf").string());
    ASSERT_EQ(scene.objects.size(), 4u);
    const Mesh& first = scene.objects[0].mesh;
    const Mesh& second = scene.objects[1].mesh;
    EXPECT_TRUE(second.positions.shares_storage_with(first.positions));
    EXPECT_TRUE(second.triangles.shares_storage_with(first.triangles));
    EXPECT_TRUE(second.normals.shares_storage_with(first.normals));
    // Normalised once, as read.
    EXPECT_EQ(first.normals[0], glm::vec3(0, 0, 1));
    const Mesh& third = scene.objects[2].mesh;
    EXPECT_TRUE(third.positions.shares_storage_with(first.positions));
    EXPECT_FALSE(third.triangles.shares_storage_with(first.triangles));
    EXPECT_EQ(third.triangles.size(), 1u);
    // The morphed mesh's vertices are its own, and the others' are left as they were.
    const Mesh& fourth = scene.objects[3].mesh;
    EXPECT_FALSE(fourth.positions.shares_storage_with(first.positions));
    EXPECT_EQ(fourth.positions[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(first.positions[0], glm::vec3(0, 0, 0));
    RenderOptions options;
    options.width = 48;
    options.height = 32;
    expect_matches_reference(scene, options, 0, render(scene, options, 0));
}

TEST(FileCopies, ShareTheFilesMeshesOnAGrid) {
    const std::filesystem::path obj = std::filesystem::path(::testing::TempDir()) / "instancing_two_quads.obj";
    {
        std::ofstream out(obj);
        out << "o first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"
               "o second\nv 0 0 1\nv 1 0 1\nv 1 1 1\nf 5 6 7\n";
    }
    const Scene one = load_scene(obj.string());
    const Scene scene = load_scene(obj.string() + "*9");
    ASSERT_EQ(scene.objects.size(), 9 * one.objects.size());
    EXPECT_EQ(scene.triangle_count(), 9 * one.triangle_count());
    for (std::size_t k = 0; k < 9; ++k) {
        for (std::size_t i = 0; i < one.objects.size(); ++i) {
            const Object& copy = scene.objects[k * one.objects.size() + i];
            EXPECT_EQ(copy.name, one.objects[i].name + "[" + std::to_string(k) + "]");
            EXPECT_EQ(copy.node, -1);
            EXPECT_EQ(copy.mesh.positions, one.objects[i].mesh.positions);
            EXPECT_TRUE(copy.mesh.positions.shares_storage_with(scene.objects[i].mesh.positions));
            // The copies stand apart: their boxes' centres at least a box apart.
            if (k > 0) {
                const glm::vec3 a(copy.transform[3]), b(scene.objects[i].transform[3]);
                EXPECT_GT(glm::length(glm::vec2(a.x - b.x, a.z - b.z)), 1.0f);
            }
        }
    }
    EXPECT_LT(scene_bytes(scene), scene_bytes(one) + 18 * sizeof(Object));
    // Counts out of range, and a file that animates, are refused by name.
    for (const std::string& bad : {obj.string() + "*0", obj.string() + "*1000001",
                                  obj.string() + "*99999999999999999999999"}) {
        SCOPED_TRACE(bad);
        try {
            load_scene(bad);
            ADD_FAILURE() << "accepted";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("copies"), std::string::npos) << e.what();
        }
    }
    const std::string animated = std::string(DYNRT_SOURCE_DIR) + "/tests/data/animated_cube.fbx*2";
    try {
        load_scene(animated);
        ADD_FAILURE() << "accepted";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("clips, skins or morph targets"), std::string::npos) << e.what();
    }
}

/// `scene` with every copy's arrays made its own: the same triangles, no sharing.
Scene unshared(Scene scene) {
    for (Object& object : scene.objects) {
        object.mesh.positions.edit();
        object.mesh.triangles.edit();
        object.mesh.normals.edit();
    }
    return scene;
}

/// dynrt's frame `f` of `scene` from its default camera.
RenderedFrame render(const Scene& scene, const RenderOptions& options, int f) {
    return test::renderer_shot(scene, default_camera(scene_bounds(scene)), options, f);
}

void expect_matches_reference(const Scene& scene, const RenderOptions& options, int f, const RenderedFrame& frame) {
    const ImageComparison cmp =
        compare_images(frame, test::reference_shot(scene, default_camera(scene_bounds(scene)), options, nullptr, f));
    EXPECT_TRUE(cmp.passed()) << cmp.summary();
    EXPECT_GT(cmp.pixels - cmp.hit_mismatches, cmp.pixels / 4);
}

TEST(Instancing, RigidCopiesCarryOneTreeAndDrawAsIfEachHadItsOwn) {
    Scene scene = load_scene("plane:1@0,-1,0,8+soup:400*6#40c060");
    std::vector<std::string> motions;
    for (std::size_t i = 1; i < scene.objects.size(); ++i) motions.push_back("rigid:" + scene.objects[i].name);
    anim::add_procedural_motions(scene, motions);
    const Scene separate = unshared(scene);
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        options.tracer = tracer;
        for (const int f : {0, 5}) {
            SCOPED_TRACE("frame " + std::to_string(f));
            const RenderedFrame shared = render(scene, options, f);
            const RenderedFrame own = render(separate, options, f);
            // The same tree, bit for bit, under each copy's transform: the same image.
            EXPECT_EQ(shared.color, own.color);
            EXPECT_EQ(shared.depth, own.depth);
            EXPECT_EQ(shared.object, own.object);
            EXPECT_EQ(shared.prim, own.prim);
            EXPECT_EQ(shared.stats.rigid_objects, 6u);
            EXPECT_EQ(shared.stats.objects_rebuilt + 5, own.stats.objects_rebuilt);
            // One soup's tree and triangles instead of six.
            const std::size_t soup_tree = (own.stats.tree_bytes - shared.stats.tree_bytes) / 5;
            EXPECT_GT(soup_tree, 400u * 36);
            EXPECT_EQ(shared.stats.triangles, own.stats.triangles);
            expect_matches_reference(scene, options, f, shared);
        }
    }
}

TEST(Instancing, StaticCopiesPastTheLimitStayInstancesAndMatchTheReference) {
    const Scene scene = load_scene("plane:1@0,-1,0,8+soup:300*9#40c060");
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    const RenderedFrame merged = render(scene, options, 0);
    options.static_group_limit = 100;  // less than the copies hold: they stay instances
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        options.tracer = tracer;
        const RenderedFrame kept = render(scene, options, 0);
        const FrameStats& s = kept.stats;
        // Counted as the static objects they are, built once for nine.
        EXPECT_EQ(s.static_objects, 10u);
        EXPECT_EQ(s.rigid_objects, 0u);
        EXPECT_EQ(s.triangles, merged.stats.triangles);
        EXPECT_LT(s.tree_bytes, merged.stats.tree_bytes / 4);
        expect_matches_reference(scene, options, 0, kept);
        // Held still: the next frames build nothing.
        Renderer renderer(options);
        RenderedFrame frame;
        const Camera camera = default_camera(scene_bounds(scene));
        renderer.render(scene, camera, 0, frame);
        renderer.render(scene, camera, 1, frame);
        EXPECT_EQ(frame.stats.objects_rebuilt, 0u);
        EXPECT_EQ(frame.stats.objects_refitted, 0u);
        // Nothing moved: the top level over the copies is kept, not rebuilt.
        EXPECT_EQ(frame.stats.top_level_ms, 0.0);
    }
}

}  // namespace
}  // namespace dynrt::reference
