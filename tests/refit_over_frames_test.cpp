// A deformable object refitted frame after frame keeps a valid tree: after every refit each
// node contains its children and its triangles, over many frames of the procedural wave and
// explode motions (both deformable, so the renderer refits them too; explode's boxes grow
// fastest).

#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/bvh/triangle_bvh.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dynrt {
namespace {

std::vector<bvh::Triangle> triangles_of(const Scene& scene, const anim::PosedScene& posed) {
    std::vector<bvh::Triangle> tris;
    const std::vector<glm::vec3>& p = posed.objects[0].positions;
    for (const glm::uvec3& t : scene.objects[0].mesh.triangles) tris.push_back({p[t.x], p[t.y], p[t.z]});
    return tris;
}

void refit_for_frames(const std::string& motion, int frames) {
    SCOPED_TRACE(motion);
    Scene scene = load_scene("sphere:3000");
    const std::vector<std::string> motions{motion};
    anim::add_procedural_motions(scene, motions);
    const anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    poser.pose(0, posed);
    bvh::BuildConfig config;
    config.leaf_size_max = 4;
    bvh::TriangleBvh tree = bvh::build_triangle_bvh(triangles_of(scene, posed), config);
    double previous_sah = 0.0;
    for (int f = 1; f <= frames; ++f) {
        poser.pose(f, posed);
        const std::vector<bvh::Triangle> tris = triangles_of(scene, posed);
        const bvh::RefitResult result = bvh::refit(tree, tris, config.sah_costs());
        ASSERT_FALSE(result.needs_rebuild()) << "frame " << f;
        const std::string problem = bvh::validate(tree, tris, config.leaf_size_max);
        ASSERT_EQ(problem, "") << "frame " << f;
        previous_sah = result.sah_cost;
    }
    EXPECT_GT(previous_sah, 0.0);
}

TEST(RefitOverFrames, WaveKeepsEveryBoxAroundItsContents) { refit_for_frames("wave", 300); }

TEST(RefitOverFrames, ExplodeKeepsEveryBoxAroundItsContents) { refit_for_frames("explode", 150); }

}  // namespace
}  // namespace dynrt
