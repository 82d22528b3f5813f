// Degenerate input: zero-area and collinear triangles, duplicated vertices and triangles,
// thousands of triangles sharing one centroid (the builder must not recurse forever), a single
// triangle, empty scenes and NaN/Inf coordinates. Nothing may crash or hang, trees must stay
// valid, every tracing path must give the brute-force watertight answer bit for bit, and the
// documented behaviour holds (README, "Scene input"): degenerate triangles are skipped and
// counted as degenerate_skipped; non-finite positions give a one-line SceneError naming the
// object, and the frame when animation made them.

#include "stress_geometry.h"
#include "stress_mode.h"
#include "stress_tracers.h"

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace dynrt::stress {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// Random rays through the box of `tris`: half from outside toward points inside, half from
/// points inside in random directions.
std::vector<bvh::Ray> rays_through(std::span<const bvh::Triangle> tris, std::int64_t count, std::uint32_t seed) {
    const bvh::Aabb box = bvh::testing::bounds_of(tris);
    const glm::vec3 c = box.center();
    const float r = std::max(0.5f * glm::length(box.extent()), 1e-3f);
    std::mt19937 rng(seed);
    std::vector<bvh::Ray> rays;
    for (std::int64_t i = 0; i < count; ++i) {
        const glm::vec3 target = bvh::testing::random_point(rng, box.lo, box.hi);
        bvh::Ray ray;
        if (i % 2 == 0) {
            ray.org = c + 3.0f * r * bvh::testing::random_direction(rng);
            ray.dir = target - ray.org;
        } else {
            ray.org = target;
            ray.dir = bvh::testing::random_direction(rng);
        }
        if (ray.dir != glm::vec3(0.0f)) rays.push_back(ray);
    }
    return rays;
}

/// Every path's answers equal the brute-force watertight loop's, bit for bit (hit, t, u, v and
/// triangle; any-hit verdict). Returns the number of rays checked per path.
std::size_t expect_brute_force_answers(const Tracers& tracers, std::span<const bvh::Ray> rays, const std::string& what) {
    std::vector<bvh::Hit> want(rays.size());
    std::vector<std::uint8_t> want_any(rays.size());
    tbb::parallel_for(std::size_t(0), rays.size(), [&](std::size_t i) {
        want[i] = brute_force_closest(tracers.world(), rays[i], false);
        want_any[i] = want[i].is_hit();
    });
    Answers got;
    for (const Path path : kPaths) {
        tracers.trace(path, rays, got);
        std::size_t bad = 0;
        std::string first;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (same_hit(got.closest[i], want[i]) && got.any[i] == want_any[i]) continue;
            if (bad++ == 0) first = describe(rays[i]);
        }
        EXPECT_EQ(bad, 0u) << what << ", " << path_name(path) << ": first " << first;
    }
    return rays.size();
}

TEST(DegenerateStress, ZeroAreaCollinearAndDuplicatedTrianglesAreSkippedAndCounted) {
    std::vector<bvh::Triangle> tris = bvh::testing::random_soup(7, 2000, 2.0f, 0.15f);
    std::mt19937 rng(8);
    std::size_t degenerate = 0;
    std::vector<bvh::Triangle> mixed;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        mixed.push_back(tris[i]);
        const glm::vec3 a = tris[i].v0, b = tris[i].v1;
        switch (i % 8) {
            case 0: mixed.push_back({a, a, a}); ++degenerate; break;            // one point
            case 1: mixed.push_back({a, b, a}); ++degenerate; break;            // two vertices equal
            case 2: {  // collinear: on a 1/1024 grid, so a + d and a + 2d are exact
                const glm::vec3 g = glm::round(a * 1024.0f) / 1024.0f, d(0.25f, 0.5f, -0.125f);
                mixed.push_back({g, g + d, g + 2.0f * d});
                ++degenerate;
                break;
            }
            case 3: mixed.push_back({a, glm::vec3(a.x + 0.25f, a.y, a.z), glm::vec3(a.x - 2.0f, a.y, a.z)});
                    ++degenerate; break;                                       // collinear along x
            case 4: mixed.push_back(tris[i]); break;                           // duplicated triangle
            case 5: mixed.push_back({tris[i].v2, tris[i].v0, tris[i].v1}); break;  // same, rotated order
            default: break;
        }
    }
    for (const bvh::Triangle& t : mixed) ASSERT_TRUE(bvh::is_finite(t));
    std::size_t counted = 0;
    for (const bvh::Triangle& t : mixed) counted += bvh::is_degenerate(t);
    ASSERT_EQ(counted, degenerate) << "the construction should make exactly these degenerate";

    for (const std::uint32_t leaf : {1u, 4u, 8u}) {
        const Tracers tracers(mixed, bvh::BuildConfig{1.0f, leaf, 16});
        EXPECT_EQ(tracers.tree().degenerate_skipped, degenerate);
        EXPECT_EQ(bvh::validate(tracers.tree(), mixed, leaf), "");
        expect_brute_force_answers(tracers, rays_through(mixed, scaled(4000, 20), 9 + leaf), "leaf " + std::to_string(leaf));
    }

    // The renderer counts the same triangles, for both tracers.
    Scene scene;
    scene.source = "stress";
    scene.materials.push_back(Material{});
    Object object;
    object.name = "mixed";
    for (const bvh::Triangle& t : mixed) {
        const auto base = std::uint32_t(object.mesh.positions.size());
        object.mesh.positions.insert(object.mesh.positions.end(), {t.v0, t.v1, t.v2});
        object.mesh.triangles.emplace_back(base, base + 1, base + 2);
    }
    scene.objects.push_back(object);
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        RenderOptions options;
        options.width = options.height = 32;
        options.tracer = tracer;
        Renderer renderer(options);
        RenderedFrame frame;
        renderer.render(scene, default_camera(scene_bounds(scene)), 0, frame);
        EXPECT_EQ(frame.stats.degenerate_skipped, degenerate);
        EXPECT_EQ(frame.stats.triangles, mixed.size());
    }
}

/// Triangles whose boxes all have the same centre: every binned split sees one bin, so the
/// builder must fall back to median splits (or leaves) and stop.
TEST(DegenerateStress, ThousandsOfTrianglesWithOneCentroidBuildAndTrace) {
    const std::int64_t n = scaled(4000, 10);
    std::mt19937 rng(10);
    std::uniform_real_distribution<float> u(0.1f, 1.0f);
    std::vector<bvh::Triangle> same_box_centre, identical;
    for (std::int64_t i = 0; i < n; ++i) {
        // x: {a, -a, e}, |e| <= a; y: {b, -b, f}, |f| <= b; z: {0, d, -d}: box centred at 0.
        const float a = u(rng), b = u(rng), d = u(rng);
        const float e = a * (2.0f * u(rng) - 1.0f), f = b * (2.0f * u(rng) - 1.0f);
        same_box_centre.push_back({{a, b, 0.0f}, {-a, -b, d}, {e, f, -d}});
        identical.push_back({{-1.0f, -0.5f, 0.25f}, {1.0f, -0.5f, -0.25f}, {0.0f, 1.0f, 0.0f}});
    }
    for (const auto& [tris, name] : {std::pair{&same_box_centre, "same box centre"}, std::pair{&identical, "identical"}}) {
        for (const auto& [cost, leaf] : {std::pair{1.0f, 1u}, std::pair{0.1f, 8u}, std::pair{4.0f, 4u}}) {
            const std::string what = std::string(name) + ", cost ratio " + std::to_string(cost) + ", leaf " +
                                     std::to_string(leaf);
            const Tracers tracers(*tris, bvh::BuildConfig{cost, leaf, 16});
            EXPECT_EQ(bvh::validate(tracers.tree(), *tris, leaf), "") << what;
            const bvh::BvhStats stats = bvh::compute_stats(tracers.tree().bvh);
            EXPECT_LE(stats.depth, bvh::kMaxDepth) << what;
            EXPECT_LE(stats.leaf_prims_max, leaf) << what;
            expect_brute_force_answers(tracers, rays_through(*tris, scaled(300, 10), 11), what);
        }
    }
}

TEST(DegenerateStress, SingleTriangle) {
    const std::vector<bvh::Triangle> tri = {{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}};
    const Tracers tracers(tri);
    EXPECT_EQ(bvh::validate(tracers.tree(), tri, 8), "");
    std::vector<bvh::Ray> rays = rays_through(tri, scaled(2000, 20), 12);
    // And straight at its corners and edges.
    for (const glm::vec3 p : {tri[0].v0, tri[0].v1, tri[0].v2, glm::vec3(0.5f, 0.0f, 0.0f), glm::vec3(0.5f, 0.5f, 0.0f)}) {
        rays.push_back(bvh::Ray{p + glm::vec3(0.125f, 0.25f, 1.0f), -glm::vec3(0.125f, 0.25f, 1.0f)});
    }
    expect_brute_force_answers(tracers, rays, "single triangle");
    Answers got;
    tracers.trace(Path::kPacket, rays, got);
    for (std::size_t i = rays.size() - 5; i < rays.size(); ++i) EXPECT_TRUE(got.closest[i].is_hit()) << i;
}

TEST(DegenerateStress, EmptyAndAllDegenerateInput) {
    // No triangles at all, and only degenerate ones: empty trees that every path traces as a miss.
    const std::vector<bvh::Triangle> none;
    const std::vector<bvh::Triangle> all_degenerate = {{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    for (const auto* tris : {&none, &all_degenerate}) {
        const Tracers tracers(*tris);
        EXPECT_TRUE(tracers.tree().bvh.empty());
        EXPECT_EQ(tracers.tree().degenerate_skipped, tris->size());
        EXPECT_EQ(bvh::validate(tracers.tree(), *tris, 8), "");
        std::vector<bvh::Ray> rays;
        std::mt19937 rng(13);
        for (int i = 0; i < 600; ++i) rays.push_back(bvh::Ray{bvh::testing::random_point(rng, glm::vec3(-3), glm::vec3(3)),
                                                               bvh::testing::random_direction(rng)});
        Answers got;
        for (const Path path : kPaths) {
            tracers.trace(path, rays, got);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_FALSE(got.closest[i].is_hit()) << path_name(path);
                ASSERT_FALSE(got.any[i]) << path_name(path);
            }
        }
    }

    // An empty scene is refused with one line, as load_scene promises.
    Scene empty;
    empty.source = "empty.gltf";
    empty.materials.push_back(Material{});
    try {
        check_scene(empty);
        FAIL() << "expected SceneError";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
    }

    // A scene whose triangles are all degenerate renders the background, with all counted.
    Scene flat;
    flat.source = "stress";
    flat.materials.push_back(Material{});
    Object object;
    object.name = "flat";
    object.mesh.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {1, 0, 0}};
    object.mesh.triangles = {{0, 1, 2}, {3, 3, 1}};
    flat.objects.push_back(object);
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        RenderOptions options;
        options.width = options.height = 24;
        options.tracer = tracer;
        Renderer renderer(options);
        RenderedFrame frame;
        renderer.render(flat, default_camera(scene_bounds(flat)), 0, frame);
        EXPECT_EQ(frame.stats.degenerate_skipped, 2u);
        for (const std::int32_t o : frame.object) ASSERT_EQ(o, -1);
        for (const glm::vec3& c : frame.color) ASSERT_EQ(c, options.background);
    }
}

/// `f` must throw a SceneError whose message is one line holding every one of `needles`.
template <typename F>
void expect_scene_error(F&& f, std::initializer_list<std::string> needles, const std::string& what) {
    try {
        f();
        ADD_FAILURE() << what << ": expected SceneError";
    } catch (const SceneError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << what << ": " << message;
        for (const std::string& needle : needles) {
            EXPECT_NE(message.find(needle), std::string::npos) << what << ": '" << needle << "' not in: " << message;
        }
    }
}

Scene one_quad(const std::string& name) {
    Scene scene;
    scene.source = "stress.gltf";
    scene.materials.push_back(Material{});
    Object quad;
    quad.name = name;
    quad.mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.objects.push_back(quad);
    return scene;
}

TEST(DegenerateStress, NonFiniteCoordinatesGiveOneLineErrorsNamingObjectAndFrame) {
    Camera camera;
    camera.eye = {0.0f, 0.0f, 4.0f};
    for (const float bad : {kNaN, kInf, -kInf}) {
        for (int component = 0; component < 3; ++component) {
            Scene scene = one_quad("bad quad");
            scene.objects[0].mesh.positions.edit()[2][component] = bad;
            expect_scene_error([&] { check_scene(scene); }, {"stress.gltf", "bad quad", "vertex 2"}, "check_scene");
            for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
                RenderOptions options;
                options.width = options.height = 16;
                options.tracer = tracer;
                Renderer renderer(options);
                RenderedFrame frame;
                expect_scene_error([&] { renderer.render(scene, camera, 3, frame); }, {"bad quad", "frame 3"}, "render");
            }
        }
        Scene transformed_scene = one_quad("bad transform");
        transformed_scene.objects[0].transform[3][1] = bad;
        expect_scene_error([&] { check_scene(transformed_scene); }, {"bad transform", "transform"}, "check_scene");
        Renderer renderer(RenderOptions{});
        RenderedFrame frame;
        expect_scene_error([&] { renderer.render(transformed_scene, camera, 0, frame); }, {"bad transform", "frame 0"},
                           "render");
    }
    // Procedural specs refuse non-finite numbers.
    for (const std::string spec : {"sphere:10@nan,0,0", "plane:2@0,inf,0", "sphere:10@0,0,0,1e39"}) {
        expect_scene_error([&] { (void)load_scene(spec); }, {spec}, spec);
    }
}

TEST(DegenerateStress, AnimationThatOverflowsNamesTheFrame) {
    // A sphere 1e36 across explodes: each triangle moves f * 0.02 R (0.5 + h) along its normal,
    // past the float range (3.4e38) after ~10^4 frames. Frame 100 is still finite; the first
    // frames with an infinite coordinate are an error naming the object and the frame, from
    // the poser and from the renderer alike (which poses before anything else, so the camera,
    // whose own arithmetic overflows at this size, is never reached).
    Scene scene = load_scene("sphere:80@0,0,0,1e36");
    const std::string specs[] = {"explode"};
    anim::add_procedural_motions(scene, specs);
    const std::string name = scene.objects[0].name;
    anim::ScenePoser poser(scene, {});
    anim::PosedScene posed;
    EXPECT_NO_THROW(poser.pose(100, posed));
    expect_scene_error([&] { poser.pose(1000000, posed); }, {name, "frame 1000000"}, "pose");
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        RenderOptions options;
        options.width = options.height = 16;
        options.tracer = tracer;
        Renderer renderer(options);
        RenderedFrame frame;
        Camera camera;
        camera.eye = glm::vec3(0.0f, 0.0f, 1e37f);
        expect_scene_error([&] { renderer.render(scene, camera, 1000000, frame); }, {name, "frame 1000000"}, "render");
        expect_scene_error([&] { renderer.render(scene, camera, 20000, frame); }, {name, "frame 20000"}, "render");
    }
}

}  // namespace
}  // namespace dynrt::stress
