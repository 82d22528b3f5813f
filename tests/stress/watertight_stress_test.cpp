// Watertightness under stress: from points inside closed meshes (a UV sphere with pole fans, a
// box with tessellated faces, a subdivided icosahedron and a closed model from ../shared/scenes),
// rays aimed exactly at every vertex, every edge midpoint and points along every edge must all
// hit, on every tracing path (single ray, packet, and both through a transformed instance of
// the two-level structure), for closest-hit and any-hit queries alike. A mesh with a hole and a
// mesh with a crack show that the leak counter does catch escaping rays.

#include "stress_geometry.h"
#include "stress_mode.h"
#include "stress_tracers.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

/// Where the two-level paths place the mesh: rotated, scaled and moved, so rays reach its
/// object-space tree through a real transform.
glm::dmat4 placement() {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, -0.2, 0.1));
    m = glm::rotate(m, glm::radians(37.0), glm::normalize(glm::dvec3(1.0, 2.0, 3.0)));
    return glm::scale(m, glm::dvec3(1.7));
}

glm::vec3 apply(const glm::dmat4& m, glm::vec3 p) { return glm::vec3(glm::dvec3(m * glm::dvec4(glm::dvec3(p), 1.0))); }

/// Rays from every inside point (object space) toward every target (object space), both taken
/// to world space by `m` first, so they aim exactly at the world mesh's vertices and edges.
std::vector<bvh::Ray> rays_from_inside(std::span<const glm::vec3> inside, std::span<const glm::vec3> targets,
                                       const glm::dmat4& m) {
    std::vector<glm::vec3> world_targets;
    for (const glm::vec3& t : targets) world_targets.push_back(apply(m, t));
    std::vector<bvh::Ray> rays;
    rays.reserve(inside.size() * targets.size());
    for (const glm::vec3& o : inside) {
        const glm::vec3 org = apply(m, o);
        for (const glm::vec3& t : world_targets) {
            bvh::Ray r;
            r.org = org;
            r.dir = t - org;
            if (r.dir == glm::vec3(0.0f)) continue;
            rays.push_back(r);
        }
    }
    return rays;
}

/// Traces `rays` every way and returns the leak count per path.
std::array<LeakCount, kPaths.size()> leaks_of(const Tracers& tracers, std::span<const bvh::Ray> rays) {
    std::array<LeakCount, kPaths.size()> out;
    Answers answers;
    for (std::size_t p = 0; p < kPaths.size(); ++p) {
        tracers.trace(kPaths[p], rays, answers);
        count_leaks(rays, answers, out[p]);
    }
    return out;
}

/// Checks that no ray escapes `mesh` (object space) from `inside` points, on every path, and
/// reports the counts.
void expect_watertight(const std::string& name, const ClosedMesh& mesh, std::span<const glm::vec3> inside,
                       int along_edge) {
    ASSERT_TRUE(is_closed(mesh.triangles())) << name << " is not closed: the check would mean nothing";
    const glm::dmat4 m = placement();
    const ClosedMesh world = transformed(mesh, m);
    const Tracers tracers(world.triangles(), mesh.triangles(), m);
    const std::vector<glm::vec3> targets = edge_and_vertex_targets(mesh, along_edge);
    // The world-space rays aim at the world mesh exactly; the two-level paths see them through
    // the placement's inverse, so they aim at the object mesh to within a few ulps.
    const std::vector<bvh::Ray> rays = rays_from_inside(inside, targets, m);
    const auto leaks = leaks_of(tracers, rays);
    std::uint64_t total = 0;
    std::string line = "watertight " + name + ": " + std::to_string(rays.size()) + " rays x " +
                       std::to_string(kPaths.size()) + " paths, leaks:";
    for (std::size_t p = 0; p < kPaths.size(); ++p) {
        EXPECT_EQ(leaks[p].leaks(), 0u) << name << ", " << path_name(kPaths[p]) << ": " << leaks[p].closest_misses
                                        << " closest misses, " << leaks[p].any_misses
                                        << " any-hit misses; first: " << leaks[p].first;
        total += leaks[p].leaks();
        line += std::string(" ") + path_name(kPaths[p]) + " " + std::to_string(leaks[p].leaks());
    }
    std::printf("%s\n", line.c_str());
    ::testing::Test::RecordProperty("rays", std::to_string(rays.size() * kPaths.size()));
    ::testing::Test::RecordProperty("leaks", std::to_string(total));
}

/// `count` points inside the ball of `radius` around `center` (the centre first).
std::vector<glm::vec3> points_in_ball(std::uint32_t seed, std::int64_t count, glm::vec3 center, float radius) {
    std::mt19937 rng(seed);
    std::vector<glm::vec3> out{center};
    while (std::int64_t(out.size()) < count) {
        out.push_back(center + radius * std::uniform_real_distribution<float>(0.0f, 1.0f)(rng) *
                                   bvh::testing::random_direction(rng));
    }
    return out;
}

TEST(WatertightStress, UvSphereWithPoleFans) {
    const ClosedMesh sphere = uv_sphere_mesh(64, 32, 1.0f, glm::vec3(0.25f, -0.5f, 0.125f));
    expect_watertight("uv sphere 64x32", sphere,
                      points_in_ball(1, scaled(10, 20), glm::vec3(0.25f, -0.5f, 0.125f), 0.9f), 3);
}

TEST(WatertightStress, BoxWithTessellatedFaces) {
    const ClosedMesh box = box_mesh(8, glm::vec3(-1.0f, -0.5f, -2.0f), glm::vec3(1.5f, 0.75f, 1.0f));
    expect_watertight("box 8x8 per face", box,
                      points_in_ball(2, scaled(40, 20), glm::vec3(0.25f, 0.125f, -0.5f), 0.6f), 3);
}

TEST(WatertightStress, SubdividedIcosahedron) {
    const ClosedMesh ico = bvh::testing::icosphere_mesh(3, 2.0f, glm::vec3(-1.0f, 0.5f, 3.0f));
    expect_watertight("icosphere level 3", ico,
                      points_in_ball(3, scaled(30, 20), glm::vec3(-1.0f, 0.5f, 3.0f), 1.8f), 3);
}

/// Points inside a closed mesh: random points of its box that a ray in each of five random
/// directions leaves through an odd number of triangles (brute force), so concave models work.
std::vector<glm::vec3> points_inside(const ClosedMesh& mesh, std::int64_t count, std::uint32_t seed) {
    const std::vector<bvh::Triangle> tris = mesh.triangles();
    const bvh::Aabb box = bvh::testing::bounds_of(tris);
    std::mt19937 rng(seed);
    std::vector<glm::vec3> out;
    for (int tries = 0; tries < 20000 && std::int64_t(out.size()) < count; ++tries) {
        const glm::vec3 p = bvh::testing::random_point(rng, box.lo, box.hi);
        bool inside = true;
        for (int k = 0; k < 5 && inside; ++k) {
            inside = bvh::testing::count_hits(tris, bvh::testing::make_ray(p, bvh::testing::random_direction(rng))) % 2 == 1;
        }
        if (inside) out.push_back(p);
    }
    return out;
}

/// The models of ../shared/scenes whose posed frame 0 is closed (checked here with is_closed:
/// their vertices are split per face corner or seam, but bit-identical positions close them all
/// the same). Of the small ones, AnimatedMorphSphere and AnimatedMorphCube are closed; the rest
/// are tested for closedness and skipped when open, so the count of closed models is printed.
TEST(WatertightStress, SharedClosedModels) {
    const std::filesystem::path root(DYNRT_SHARED_SCENES_DIR);
    if (!std::filesystem::exists(root)) GTEST_SKIP() << root << " not found";
    const char* candidates[] = {"animatedmorphsphere/AnimatedMorphSphere.glb", "animatedmorphcube/AnimatedMorphCube.glb",
                                "animatedcube/AnimatedCube.gltf",          "boxanimated/BoxAnimated.glb",
                                "riggedsimple/RiggedSimple.glb",           "riggedfigure/RiggedFigure.glb",
                                "fox/Fox.glb",                             "cesiumman/CesiumMan.glb",
                                "morphstresstest/MorphStressTest.glb"};
    int closed = 0;
    for (const char* candidate : candidates) {
        const std::filesystem::path path = root / candidate;
        if (!std::filesystem::exists(path)) continue;
        const Scene scene = load_scene(path.string());
        anim::PosedScene posed;
        anim::pose_scene(scene, 0, posed);
        ClosedMesh mesh;
        for (std::size_t o = 0; o < scene.objects.size(); ++o) {
            const auto base = std::uint32_t(mesh.vertices.size());
            mesh.vertices.insert(mesh.vertices.end(), posed.objects[o].positions.begin(),
                                 posed.objects[o].positions.end());
            for (const glm::uvec3& t : scene.objects[o].mesh.triangles) {
                mesh.faces.push_back({base + t.x, base + t.y, base + t.z});
            }
        }
        const bool is = is_closed(mesh.triangles());
        std::printf("shared model %s: %zu triangles, %s\n", candidate, mesh.faces.size(), is ? "closed" : "open");
        if (!is) continue;
        // Fewer origins for the larger models: the rays per origin grow with the edges.
        const std::vector<glm::vec3> inside = points_inside(mesh, scaled(mesh.faces.size() > 1000 ? 5 : 20, 20), 4);
        ASSERT_FALSE(inside.empty()) << candidate << ": no inside point found";
        ++closed;
        expect_watertight(path.filename().string(), mesh, inside, 3);
    }
    if (closed == 0) GTEST_SKIP() << "no closed model found under " << root;
}

/// The counter must see leaks where there are some: an icosphere with one triangle removed
/// (rays aimed inside the hole) and one whose triangle has its own copies of its vertices,
/// pulled 1% of the way in toward its centroid (rays aimed into the cracks this opens along its
/// three edges). Every such ray escapes, on every path, and must be counted.
TEST(WatertightStress, LeakCounterCatchesHoleAndCrack) {
    const ClosedMesh ico = bvh::testing::icosphere_mesh(2, 1.0f);
    const std::uint32_t victim = 17;
    const auto f = ico.faces[victim];
    const glm::vec3 a = ico.vertices[f[0]], b = ico.vertices[f[1]], c = ico.vertices[f[2]];
    const glm::vec3 centroid = (a + b + c) / 3.0f;
    const std::vector<glm::vec3> in_hole = {centroid, 0.6f * a + 0.2f * b + 0.2f * c, 0.2f * a + 0.6f * b + 0.2f * c,
                                            0.2f * a + 0.2f * b + 0.6f * c};
    const std::vector<glm::vec3> in_crack = [&] {
        std::vector<glm::vec3> out;
        for (const glm::vec3 m : {0.5f * (a + b), 0.5f * (b + c), 0.5f * (c + a), 0.3f * a + 0.7f * b}) {
            out.push_back(m + 0.004f * (centroid - m));
        }
        return out;
    }();
    const std::vector<glm::vec3> inside = points_in_ball(5, 16, glm::vec3(0.0f), 0.5f);

    ClosedMesh holed = ico;
    holed.faces.erase(holed.faces.begin() + victim);
    ClosedMesh cracked = ico;
    for (int k = 0; k < 3; ++k) {
        const glm::vec3 v = ico.vertices[f[k]];
        cracked.vertices.push_back(v + 0.01f * (centroid - v));
        cracked.faces[victim][k] = std::uint32_t(cracked.vertices.size() - 1);
    }
    EXPECT_FALSE(is_closed(holed.triangles()));
    EXPECT_FALSE(is_closed(cracked.triangles()));
    using Case = std::tuple<const ClosedMesh*, const char*, const std::vector<glm::vec3>*>;
    for (const auto& [mesh, name, targets] : {Case{&holed, "hole", &in_hole}, Case{&cracked, "crack", &in_crack}}) {
        const Tracers tracers(mesh->triangles());
        const std::vector<bvh::Ray> rays = rays_from_inside(inside, *targets, glm::dmat4(1.0));
        const auto leaks = leaks_of(tracers, rays);
        for (std::size_t p = 0; p < kPaths.size(); ++p) {
            EXPECT_EQ(leaks[p].closest_misses, rays.size()) << name << ", " << path_name(kPaths[p]);
            EXPECT_EQ(leaks[p].any_misses, rays.size()) << name << ", " << path_name(kPaths[p]);
        }
        std::printf("leak counter, %s: %zu rays, %llu escaped (single ray)\n", name, rays.size(),
                    static_cast<unsigned long long>(leaks[0].closest_misses));
    }
}

}  // namespace
}  // namespace dynrt::stress
