// Reading a tree's triangles back from its blocks (bvh/include/dynrt/bvh/block_triangles.h),
// which lets the engine's static group free the copy it built from: every triangle must come
// back bit for bit, the degenerate ones the tree left out included, from either builder; a
// tree without blocks is not indexed; and the engine's shading reads a static scene's corners
// through it (SceneAccel::world_triangle equal to the scene's own vertices).

#include "dynrt/bvh/block_triangles.h"
#include "dynrt/bvh/triangle_bvh.h"

#include "bvh_test_geometry.h"
#include "update/scene_accel.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace dynrt::bvh {
namespace {

bool same_bits(const Triangle& a, const Triangle& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::vector<Triangle> soup_with_degenerates() {
    std::vector<Triangle> tris = testing::random_soup(7, 3001, 10.0f, 0.3f, glm::vec3(-1e4f, 2e3f, 5.0f));
    // Zero-area ones (a point, and three collinear corners) at the front, the middle and the end.
    for (const std::size_t i : {std::size_t{0}, std::size_t{1500}, tris.size() - 1}) {
        tris[i].v1 = tris[i].v0;
        tris[i].v2 = tris[i].v0;
    }
    tris[700] = Triangle{glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(2.0f, 3.0f, 4.0f), glm::vec3(3.0f, 5.0f, 7.0f)};
    return tris;
}

class BlockTrianglesBuilders : public ::testing::TestWithParam<BuildMethod> {};

TEST_P(BlockTrianglesBuilders, GiveBackEveryTriangleBitForBit) {
    const std::vector<Triangle> tris = soup_with_degenerates();
    BuildConfig config;
    config.method = GetParam();
    const TriangleBvh tree = build_triangle_bvh(tris, config);
    ASSERT_FALSE(tree.wide.empty());
    ASSERT_EQ(tree.degenerate_skipped, 4u);
    const BlockTriangles index = BlockTriangles::index(tree, tris);
    ASSERT_TRUE(index.indexed());
    ASSERT_EQ(index.size(), tris.size());
    std::size_t wrong = 0;
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
        index.prefetch(tree, i);
        wrong += same_bits(index.at(tree, i), tris[i]) ? 0 : 1;
    }
    EXPECT_EQ(wrong, 0u);
    // Four bytes a triangle, plus the left-out ones' copies.
    EXPECT_EQ(index.bytes(), tris.size() * 4 + 4 * sizeof(Triangle));
}

INSTANTIATE_TEST_SUITE_P(Builders, BlockTrianglesBuilders,
                         ::testing::Values(BuildMethod::binned_sah, BuildMethod::morton));

TEST(BlockTriangles, ATreeWithoutBlocksIsNotIndexed) {
    const std::vector<Triangle> tris = testing::random_soup(3, 100);
    BuildConfig config;
    config.wide = false;
    const TriangleBvh binary = build_triangle_bvh(tris, config);
    EXPECT_FALSE(BlockTriangles::index(binary, tris).indexed());
    // Nothing to index is indexed: no triangles, or only degenerate ones.
    const TriangleBvh none = build_triangle_bvh(std::vector<Triangle>{}, BuildConfig{});
    EXPECT_TRUE(BlockTriangles::index(none, {}).indexed());
    const std::vector<Triangle> flat(3, Triangle{glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(2.0f)});
    const TriangleBvh skipped = build_triangle_bvh(flat, BuildConfig{});
    const BlockTriangles index = BlockTriangles::index(skipped, flat);
    ASSERT_TRUE(index.indexed());
    for (std::uint32_t i = 0; i < 3; ++i) EXPECT_TRUE(same_bits(index.at(skipped, i), flat[i]));
}

}  // namespace
}  // namespace dynrt::bvh

namespace dynrt {
namespace {

TEST(StaticGroup, KeepsNoCopyOfItsTrianglesAndShadesFromItsBlocks) {
    // Two static objects (the group, in world space) and a moving soup (read in place, its
    // triangles read back from its own tree's blocks too).
    Scene scene = load_scene("sphere:2000@0,0,0,1+sphere:500@3,0,0,0.5+soup:300@0,3,0,1");
    std::vector<ObjectState> states(scene.objects.size());
    for (std::size_t i = 0; i < states.size(); ++i) {
        states[i].motion_class = i == 2 ? anim::MotionClass::exploding : anim::MotionClass::static_;
        states[i].world_positions = scene.objects[i].mesh.positions;
        states[i].changed = true;
    }
    struct Identity final : FixedPositions {
        const Scene& scene;
        explicit Identity(const Scene& s) : scene(s) {}
        std::span<const glm::vec3> object_space(std::size_t i) const override { return scene.objects[i].mesh.positions; }
        std::span<const glm::vec3> world(std::size_t i, std::vector<glm::vec3>&) const override {
            return scene.objects[i].mesh.positions;
        }
    } fixed(scene);
    const std::size_t statics = scene.objects[0].mesh.triangles.size() + scene.objects[1].mesh.triangles.size();
    for (const bool wide : {true, false}) {
        SCOPED_TRACE(wide ? "wide tree" : "binary tree (the group keeps a gathered copy)");
        SceneAccel accel;
        UpdateStats stats;
        TreeShape shape;
        UpdatePolicy policy;
        policy.build.wide = wide;
        accel.update(scene, states, fixed, policy, stats, shape);
        MemoryStats memory;
        accel.memory_figures(memory);
        EXPECT_EQ(memory.build_triangle_bytes, (wide ? 4 : 36) * (statics + scene.objects[2].mesh.triangles.size()));
        EXPECT_EQ(shape.triangles, statics + scene.objects[2].mesh.triangles.size());
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            const Mesh& mesh = scene.objects[i].mesh;
            for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
                const bvh::Triangle tri = accel.world_triangle(i, t);
                const glm::uvec3& v = mesh.triangles[t];
                ASSERT_EQ(tri.v0, mesh.positions[v.x]) << "object " << i << " triangle " << t;
                ASSERT_EQ(tri.v1, mesh.positions[v.y]) << "object " << i << " triangle " << t;
                ASSERT_EQ(tri.v2, mesh.positions[v.z]) << "object " << i << " triangle " << t;
            }
        }
        // The occluder cache reads the group's triangles by the group's own numbering.
        const std::uint32_t group = std::uint32_t(scene.objects.size());
        const std::uint32_t first_of_second = std::uint32_t(scene.objects[0].mesh.triangles.size());
        const std::optional<bvh::Triangle> t = accel.tree_triangle(group, first_of_second);
        ASSERT_TRUE(t.has_value());
        EXPECT_EQ(t->v0, scene.objects[1].mesh.positions[scene.objects[1].mesh.triangles[0].x]);
        EXPECT_FALSE(accel.tree_triangle(group, std::uint32_t(statics)).has_value());
    }
}

}  // namespace
}  // namespace dynrt
