// Refit drift: a deformable mesh waving for thousands of frames (4000 in the fast mode, 50 times
// more with --stress), its tree only ever refitted, never rebuilt. At sampled frames the
// refitted tree must still be valid and give exactly the hits of a fresh build (bit for bit,
// every path), and agree with the exact reference where it says the answer is determined. The
// Renderer, refitting the same object with rebuilds switched off, must render exactly the frame
// of a renderer that builds afresh.

#include "stress_geometry.h"
#include "stress_mode.h"
#include "stress_tracers.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

bool same_answer(const Answers& a, const Answers& b, std::size_t i) {
    return same_hit(a.closest[i], b.closest[i]) && a.any[i] == b.any[i];
}

TEST(RefitDriftStress, WaveForThousandsOfFramesMatchesFreshBuildsAndTheReference) {
    Scene scene = load_scene("sphere:500");
    const std::string specs[] = {"wave"};
    anim::add_procedural_motions(scene, specs);
    const anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    const auto triangles = [&] {
        std::vector<bvh::Triangle> tris;
        const std::vector<glm::vec3>& p = posed.objects[0].positions;
        for (const glm::uvec3& t : scene.objects[0].mesh.triangles) tris.push_back({p[t.x], p[t.y], p[t.z]});
        return tris;
    };
    poser.pose(0, posed);
    const bvh::BuildConfig config{1.0f, 4, 16};
    bvh::TriangleBvh refitted = bvh::build_triangle_bvh(triangles(), config);
    const double sah_at_build = bvh::sah_cost(refitted.bvh, config.sah_costs());

    const int frames = int(scaled(4000, 50));
    const int every = 200;  // sampled frames: bit-for-bit against a fresh build
    const int reference_every = 1000;  // and against the exact reference
    std::uint64_t compared = 0, mismatches = 0, reference_rays = 0, disagreements = 0;
    double sah_max = sah_at_build;
    std::mt19937 rng(31);
    for (int frame = 1; frame <= frames; ++frame) {
        poser.pose(frame, posed);
        const std::vector<bvh::Triangle> tris = triangles();
        const bvh::RefitResult result = bvh::refit(refitted, tris, config.sah_costs());
        ASSERT_FALSE(result.needs_rebuild()) << "frame " << frame;
        sah_max = std::max(sah_max, result.sah_cost);
        if (frame % every != 0) continue;
        const std::string what = "frame " + std::to_string(frame);
        ASSERT_EQ(bvh::validate(refitted, tris, config.leaf_size_max), "") << what;

        std::vector<bvh::Ray> rays;
        const bvh::Aabb box = bvh::testing::bounds_of(tris);
        const float r = 0.5f * glm::length(box.extent());
        for (int i = 0; i < scaled(1000, 2); ++i) {
            bvh::Ray ray;
            ray.org = box.center() + 2.0f * r * bvh::testing::random_direction(rng);
            ray.dir = bvh::testing::random_point(rng, box.lo, box.hi) - ray.org;
            rays.push_back(ray);
        }
        const Tracers fresh(tris, config);
        const bvh::TwoLevelBvh placed = Tracers::place(refitted, glm::dmat4(1.0));
        // The reference at every reference_every-th frame, shared by the paths.
        std::unique_ptr<ReferenceWorld> exact;
        std::vector<reference::ReferenceHit> ref;
        if (frame % reference_every == 0) {
            exact = std::make_unique<ReferenceWorld>(tris);
            ref = reference_hits(*exact->tracer, rays);
        }
        Answers want, got;
        for (const Path path : kPaths) {
            fresh.trace(path, rays, want);
            Tracers::trace(refitted, placed, path, rays, got);
            std::uint64_t bad = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) bad += !same_answer(want, got, i);
            EXPECT_EQ(bad, 0u) << what << ", " << path_name(path);
            compared += rays.size();
            mismatches += bad;
            if (exact) {
                Agreement agreement;
                check_against_reference(rays, ref, got, agreement);
                EXPECT_EQ(agreement.disagreements, 0u) << what << ", " << path_name(path) << ": " << agreement.first;
                reference_rays += agreement.rays;
                disagreements += agreement.disagreements;
            }
        }
    }
    std::printf("refit drift: %d frames refitted, %llu rays compared with fresh builds (%llu mismatches), %llu "
                "with the reference (%llu disagreements); SAH cost %.3f at build, at most %.3f refitted\n",
                frames, static_cast<unsigned long long>(compared), static_cast<unsigned long long>(mismatches),
                static_cast<unsigned long long>(reference_rays), static_cast<unsigned long long>(disagreements),
                sah_at_build, sah_max);
    RecordProperty("frames", frames);
    RecordProperty("mismatches", std::to_string(mismatches));
    RecordProperty("disagreements", std::to_string(disagreements));
}

TEST(RefitDriftStress, RendererRefittingForThousandsOfFramesMatchesAFreshRender) {
    Scene scene = load_scene("sphere:300");
    const std::string specs[] = {"wave"};
    anim::add_procedural_motions(scene, specs);
    RenderOptions options;
    options.width = options.height = 32;
    options.method = UpdateMethod::refit;  // refit only
    const Camera camera = default_camera(scene_bounds(scene));
    const int frames = int(scaled(3000, 20));
    int compared = 0;
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        options.tracer = tracer;
        Renderer long_lived(options);
        RenderedFrame got, want;
        std::size_t rebuilt = 0;
        for (int frame = 0; frame <= frames; ++frame) {
            long_lived.update(scene, frame);
            if (frame % 500 != 0) continue;
            long_lived.trace(camera, got);
            rebuilt += got.stats.objects_rebuilt;
            Renderer fresh(options);
            fresh.render(scene, camera, frame, want);
            EXPECT_EQ(got.prim, want.prim) << "frame " << frame;
            EXPECT_EQ(got.depth, want.depth) << "frame " << frame;
            EXPECT_EQ(got.color, want.color) << "frame " << frame;
            ++compared;
        }
        EXPECT_EQ(rebuilt, 1u) << "only the first frame builds";
    }
    std::printf("refit drift, renderer: %d frames refitted per tracer, %d compared with fresh renders\n", frames,
                compared);
}

}  // namespace
}  // namespace dynrt::stress
