// ShadingGeometry's static normals (engine/src/update/shading_geometry.h): those FixedPositions
// holds are borrowed, not copied, and taken again at every update; those it makes in its
// scratch are copied when the static group is built, and a borrowed object that comes back
// in the scratch is copied from then on. What shading reads is the current normals either way.

#include "update/scene_accel.h"
#include "update/shading_geometry.h"

#include <gtest/gtest.h>

#include <vector>

namespace dynrt {
namespace shading_geometry_test {

/// Two static objects: object 0's normals held by this FixedPositions (as at the identity),
/// object 1's made in the caller's scratch (as under a transform); `in_scratch[0]` makes
/// object 0's come from the scratch too.
class TwoStatics final : public FixedPositions {
public:
    std::vector<glm::vec3> held{{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
    std::vector<glm::vec3> made{{0, 0, -1}, {0, -1, 0}, {-1, 0, 0}};
    /// Object 0's normals after a change: other storage (as a mesh given new normals).
    std::vector<glm::vec3> held_later{{0.6f, 0.8f, 0.0f}, {0, 1, 0}, {1, 0, 0}};
    bool later = false;
    bool in_scratch[2] = {false, true};

    std::span<const glm::vec3> object_space(std::size_t) const override { return {}; }
    std::span<const glm::vec3> world(std::size_t, std::vector<glm::vec3>&) const override { return {}; }
    std::span<const glm::vec3> world_normals(std::size_t object, std::vector<glm::vec3>& scratch) const override {
        const std::vector<glm::vec3>& own = later ? held_later : held;
        if (!in_scratch[object]) return own;
        scratch = object == 0 ? own : made;
        return scratch;
    }
};

Scene two_triangles() {
    Scene scene;
    for (int k = 0; k < 2; ++k) {
        Object& o = scene.objects.emplace_back();
        o.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        o.mesh.triangles = {{0, 1, 2}};
    }
    return scene;
}

TEST(ShadingGeometry, BorrowsStaticNormalsItsPositionsHoldAndCopiesTheRest) {
    const Scene scene = two_triangles();
    const std::vector<ObjectState> states(2);  // static
    TwoStatics fixed;
    ShadingGeometry shading;
    std::vector<glm::vec3> scratch;
    for (std::size_t i = 0; i < 2; ++i) {
        const std::span<const glm::vec3> n = fixed.world_normals(i, scratch);
        shading.keep_static_normals(i, n, n.data() != scratch.data());
    }
    shading.refresh(scene, states, fixed);
    glm::vec3 out[3];
    ASSERT_TRUE(shading.world_vertex_normals(0, 0, out));
    EXPECT_EQ(out[0], fixed.held[0]);
    ASSERT_TRUE(shading.world_vertex_normals(1, 0, out));
    EXPECT_EQ(out[2], fixed.made[2]);
    // Only object 1's normals are held: 3 of them.
    const std::size_t records = shading.memory_bytes() - 3 * sizeof(glm::vec3);
    // Object 0's normals are now other storage (a library API mesh given new normals): the
    // next update takes them; object 1's copy keeps what it was given at the build.
    fixed.later = true;
    fixed.made[2] = glm::vec3(0.0f, 0.6f, 0.8f);
    shading.refresh(scene, states, fixed);
    ASSERT_TRUE(shading.world_vertex_normals(0, 0, out));
    EXPECT_EQ(out[0], glm::vec3(0.6f, 0.8f, 0.0f));
    ASSERT_TRUE(shading.world_vertex_normals(1, 0, out));
    EXPECT_EQ(out[2], glm::vec3(-1, 0, 0));
    // Object 0 now comes in the scratch: copied, so it outlives the scratch's next use.
    fixed.in_scratch[0] = true;
    shading.refresh(scene, states, fixed);
    EXPECT_GE(shading.memory_bytes(), records + 6 * sizeof(glm::vec3));
    fixed.held_later[0] = glm::vec3(1, 0, 0);
    ASSERT_TRUE(shading.world_vertex_normals(0, 0, out));
    EXPECT_EQ(out[0], glm::vec3(0.6f, 0.8f, 0.0f));
}

}  // namespace shading_geometry_test
}  // namespace dynrt
