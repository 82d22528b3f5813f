// Exploding to extremes: the explode motion flies a sphere's triangles out to 10^6 times its
// size, and a mesh collapses onto one point (every vertex equal, through tiny and subnormal
// sizes on the way). At every step the tree stays valid (bvh::validate) whether rebuilt or
// refitted from the frame-0 tree, traversal terminates, and every path (single ray, packet,
// two-level of each) gives the brute-force watertight answer bit for bit. The Renderer does
// the same frames with the object refitted (deformable) and rebuilt (exploding): identical.

#include "stress_geometry.h"
#include "stress_mode.h"
#include "stress_tracers.h"

#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bvh/refit.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

/// Rays toward the centroids of random triangles (so the far-flung fragments are found) and
/// random points of the box, from outside it.
std::vector<bvh::Ray> rays_at(std::span<const bvh::Triangle> tris, std::int64_t count, std::uint32_t seed) {
    const bvh::Aabb box = bvh::testing::bounds_of(tris);
    const glm::dvec3 c(box.center());
    const double r = std::max(0.5 * glm::length(glm::dvec3(box.extent())), 1e-30);
    std::mt19937 rng(seed);
    std::vector<bvh::Ray> rays;
    for (std::int64_t i = 0; i < count; ++i) {
        const glm::dvec3 target = i % 2 == 0 ? glm::dvec3(tris[rng() % tris.size()].centroid())
                                             : glm::dvec3(bvh::testing::random_point(rng, box.lo, box.hi));
        bvh::Ray ray;
        ray.org = glm::vec3(c + 2.0 * r * glm::dvec3(bvh::testing::random_direction(rng)));
        ray.dir = glm::vec3(target - glm::dvec3(ray.org));
        if (ray.dir != glm::vec3(0.0f) && std::isfinite(ray.dir.x + ray.dir.y + ray.dir.z)) rays.push_back(ray);
    }
    return rays;
}

struct StepCount {
    std::uint64_t rays = 0, hits = 0, mismatches = 0;
};

/// Validates `tree` against `tris` and checks every path's closest hits against brute force;
/// with `exact` false, only that every path terminates and its closest and any-hit answers
/// agree with each other (see CollapsingToAPoint for when the brute force stops being the
/// yardstick).
void expect_tree_correct(const bvh::TriangleBvh& tree, std::span<const bvh::Triangle> tris, bool refitted,
                         std::span<const bvh::Ray> rays, const std::string& what, StepCount& count,
                         bool exact = true) {
    ASSERT_EQ(bvh::validate(tree, tris, 8), "") << what;
    if (!exact) {
        const bvh::TwoLevelBvh tlas = Tracers::place(tree, glm::dmat4(1.0));
        Answers got;
        for (const Path path : kPaths) {
            Tracers::trace(tree, tlas, path, rays, got);
            std::uint64_t bad = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) bad += got.closest[i].is_hit() != bool(got.any[i]);
            EXPECT_EQ(bad, 0u) << what << ", " << path_name(path) << ": closest and any-hit disagree";
            count.rays += rays.size();
            count.mismatches += bad;
        }
        return;
    }
    std::vector<bvh::Hit> want(rays.size());
    tbb::parallel_for(std::size_t(0), rays.size(), [&](std::size_t i) { want[i] = brute_force_closest(tris, rays[i], refitted); });
    const bvh::TwoLevelBvh tlas = Tracers::place(tree, glm::dmat4(1.0));
    Answers got;
    for (const Path path : kPaths) {
        Tracers::trace(tree, tlas, path, rays, got);
        std::uint64_t bad = 0;
        std::string first;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (same_hit(got.closest[i], want[i]) && bool(got.any[i]) == want[i].is_hit()) continue;
            if (bad++ == 0) {
                first = describe(rays[i]) + " got prim " + std::to_string(got.closest[i].prim) + " t " +
                        std::to_string(got.closest[i].t) + " any " + std::to_string(got.any[i]) + ", want prim " +
                        std::to_string(want[i].prim) + " t " + std::to_string(want[i].t);
            }
        }
        EXPECT_EQ(bad, 0u) << what << ", " << path_name(path) << ": first " << first;
        count.mismatches += bad;
        count.rays += rays.size();
    }
    for (const bvh::Hit& h : want) count.hits += h.is_hit();
}

std::vector<bvh::Triangle> triangles_of(const Scene& scene, const anim::PosedScene& posed) {
    std::vector<bvh::Triangle> tris;
    const std::vector<glm::vec3>& p = posed.objects[0].positions;
    for (const glm::uvec3& t : scene.objects[0].mesh.triangles) tris.push_back({p[t.x], p[t.y], p[t.z]});
    return tris;
}

TEST(ExplodeStress, FragmentsFlyingTo1e6TimesTheSceneSize) {
    Scene scene = load_scene("sphere:600");
    const std::string specs[] = {"explode"};
    anim::add_procedural_motions(scene, specs);
    const anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    poser.pose(0, posed);
    const std::vector<bvh::Triangle> rest = triangles_of(scene, posed);
    const bvh::BuildConfig config{1.0f, 8, 16};
    bvh::TriangleBvh refitted = bvh::build_triangle_bvh(rest, config);
    // Frame f moves triangles by f * 0.02 R (0.5 ... 1.5): frame 10^8 puts them 10^6 R out.
    std::vector<int> frames = {1, 2, 5, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};
    if (stress_mode()) {
        for (int f = 3; f < 100000000; f = f * 3 + 1) frames.push_back(f);
    }
    StepCount count;
    for (const int frame : frames) {
        const std::string what = "frame " + std::to_string(frame);
        poser.pose(frame, posed);
        const std::vector<bvh::Triangle> tris = triangles_of(scene, posed);
        const std::vector<bvh::Ray> rays = rays_at(tris, scaled(2000, 10), std::uint32_t(frame));
        const bvh::RefitResult result = bvh::refit(refitted, tris, config.sah_costs());
        ASSERT_FALSE(result.needs_rebuild()) << what;
        expect_tree_correct(refitted, tris, true, rays, what + " refitted", count);
        const bvh::TriangleBvh rebuilt = bvh::build_triangle_bvh(tris, config);
        expect_tree_correct(rebuilt, tris, false, rays, what + " rebuilt", count);
    }
    std::printf("explode to 1e6 x: %zu frames, %llu ray traces (%llu hits), %llu mismatches\n", frames.size(),
                static_cast<unsigned long long>(count.rays), static_cast<unsigned long long>(count.hits),
                static_cast<unsigned long long>(count.mismatches));
    RecordProperty("ray_traces", std::to_string(count.rays));
    RecordProperty("mismatches", std::to_string(count.mismatches));
}

TEST(ExplodeStress, CollapsingToAPoint) {
    const ClosedMesh mesh = bvh::testing::icosphere_mesh(3, 1.0f, glm::vec3(0.5f, -0.25f, 2.0f));
    const glm::dvec3 point(0.5, -0.25, 2.0);
    const std::vector<bvh::Triangle> rest = mesh.triangles();
    const bvh::BuildConfig config{1.0f, 8, 16};
    bvh::TriangleBvh refitted = bvh::build_triangle_bvh(rest, config);
    StepCount count;
    // Toward the point 0.5,-0.25,2 by factors down to 0 (every vertex equal), then around the
    // origin through subnormal sizes down to 0 (every vertex at the origin).
    //
    // Below a size of about 1e-18 the watertight test's edge functions (products of two
    // coordinates relative to the ray origin) fall under the smallest normal float, 1.2e-38, and
    // lose their relative precision, so its t is no longer accurate and no brute force is the
    // yardstick: at 1e-20 the single-ray tracer culls, by a correct box test, a leaf whose
    // triangle the rounded test reports hit a little nearer, which the packet tracer and the
    // brute force then report. There, only validity, termination and the consistency of each
    // path's closest and any-hit answers are checked.
    std::vector<std::pair<glm::dvec3, double>> steps;
    for (const double k : {1e-1, 1e-3, 1e-6, 1e-7, 1e-8, 1e-12, 0.0}) steps.push_back({point, k});
    for (const double k : {1e-20, 1e-36, 1e-38, 1e-40, 1e-44, 1e-46, 0.0}) steps.push_back({glm::dvec3(0.0), k});
    for (const auto& [centre, k] : steps) {
        char factor[32];
        std::snprintf(factor, sizeof factor, "%g", k);
        const std::string what = std::string("factor ") + factor + " toward (" + std::to_string(centre.x) + ", " +
                                 std::to_string(centre.y) + ", " + std::to_string(centre.z) + ")";
        std::vector<bvh::Triangle> tris;
        for (const bvh::Triangle& t : rest) {
            const auto squeeze = [&](glm::vec3 v) { return glm::vec3(centre + k * (glm::dvec3(v) - point)); };
            tris.push_back({squeeze(t.v0), squeeze(t.v1), squeeze(t.v2)});
        }
        std::vector<bvh::Ray> rays = rays_at(tris, scaled(1000, 10), 7);
        // And straight at the point from a few directions, however small the mesh.
        std::mt19937 rng(8);
        for (int i = 0; i < 64; ++i) {
            const glm::vec3 d = bvh::testing::random_direction(rng);
            rays.push_back(bvh::Ray{glm::vec3(centre) - d, d});
        }
        const bvh::RefitResult result = bvh::refit(refitted, tris, config.sah_costs());
        ASSERT_FALSE(result.needs_rebuild()) << what;
        const bool exact = k >= 1e-12 || k == 0.0;
        expect_tree_correct(refitted, tris, true, rays, what + " refitted", count, exact);
        const bvh::TriangleBvh rebuilt = bvh::build_triangle_bvh(tris, config);
        expect_tree_correct(rebuilt, tris, false, rays, what + " rebuilt", count, exact);
        if (k == 0.0) {
            EXPECT_TRUE(rebuilt.bvh.empty()) << what << ": every triangle is a point";
        }
    }
    std::printf("collapse to a point: %zu steps, %llu ray traces (%llu hits), %llu mismatches\n", steps.size(),
                static_cast<unsigned long long>(count.rays), static_cast<unsigned long long>(count.hits),
                static_cast<unsigned long long>(count.mismatches));
    RecordProperty("ray_traces", std::to_string(count.rays));
}

/// The renderer's own update paths on the same motion: refitting a deformable object and
/// rebuilding it as exploding give the same frame, bit for bit, at every extreme.
TEST(ExplodeStress, RendererRefitAndRebuildAgreeAtExtremes) {
    Scene scene = load_scene("sphere:400");
    const std::string specs[] = {"explode"};
    anim::add_procedural_motions(scene, specs);
    const std::string treat[] = {scene.objects[0].name + "=exploding"};
    const bvh::Aabb bounds = scene_bounds(scene);
    int frames = 0;
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        RenderOptions refit_options;
        refit_options.width = refit_options.height = 48;
        refit_options.tracer = tracer;
        refit_options.method = UpdateMethod::refit;  // refit only
        RenderOptions rebuild_options = refit_options;
        rebuild_options.method = UpdateMethod::threshold;  // exploding: rebuilt every frame
        rebuild_options.pose.class_overrides = anim::parse_class_overrides(scene, treat);
        Renderer refit_renderer(refit_options), rebuild_renderer(rebuild_options);
        RenderedFrame a, b;
        for (const int frame : {0, 1, 10, 1000, 100000, 10000000, 100000000, 3}) {
            // Look at the whole cloud from outside it, so far-flung fragments are on screen.
            Camera camera = default_camera(bounds);
            const double spread = 0.02 * 1.5 * frame + 2.0;
            camera.eye = glm::vec3(glm::dvec3(bounds.center()) +
                                   spread * 0.5 * glm::length(glm::dvec3(bounds.extent())) * glm::dvec3(0.3, 0.5, 2.0));
            refit_renderer.render(scene, camera, frame, a);
            rebuild_renderer.render(scene, camera, frame, b);
            EXPECT_EQ(a.stats.objects_rebuilt, frame == 0 ? 1u : 0u) << "frame " << frame;
            EXPECT_EQ(a.prim, b.prim) << "frame " << frame;
            EXPECT_EQ(a.depth, b.depth) << "frame " << frame;
            EXPECT_EQ(a.color, b.color) << "frame " << frame;
            ++frames;
        }
    }
    std::printf("explode, renderer refit vs rebuild: %d frames identical\n", frames);
}

}  // namespace
}  // namespace dynrt::stress
