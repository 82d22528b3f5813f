// Exact pixel reuse (TraceSettings::reuse, PixelReuse::exact; engine/src/rendering/
// exact_reuse.h): sequences rendered frame by frame with reuse and without must give the same
// bits in every buffer of every frame, while reuse really keeps pixels. Procedural motions
// (rigid, wave and explode over a static floor that takes their shadows), skinned and morphing
// glTF models and a BART scene held still; frames played in order, repeated and jumped. Then
// the decisions (what forces a full trace) and the changed-space tests on their own. The
// library API's steps are in tests/api/api_reuse_test.cpp.

#include "moving_scene.h"
#include "same_bits.h"
#include "same_frame.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "rendering/changed_space.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace dynrt {
namespace {

using test::kExplode;
using test::kPlane;
using test::kRigid;
using test::kWave;
using test::moving_scene;

using dynrt::test::expect_same_frame;
using dynrt::test::same_bits;

struct Totals {
    std::size_t reused = 0, traced = 0, shadows = 0, pixels = 0;
};

/// Renders `frames` of `scene` from `camera` with exact reuse and without; every frame must be
/// the same. Returns what reuse kept and traced.
Totals render_both_ways(const Scene& scene, const Camera& camera, RenderOptions options,
                        std::initializer_list<int> frames) {
    options.reuse.mode = PixelReuse::exact;
    Renderer reusing(options);
    options.reuse.mode = PixelReuse::off;
    Renderer full(options);
    RenderedFrame a, b;
    Totals totals;
    for (const int f : frames) {
        SCOPED_TRACE("frame " + std::to_string(f));
        reusing.render(scene, camera, f, a);
        full.render(scene, camera, f, b);
        expect_same_frame(a, b);
        EXPECT_EQ(a.stats.reuse_mode, "exact");
        EXPECT_EQ(b.stats.pixels_traced, b.color.size());
        EXPECT_EQ(a.stats.pixels_traced + a.stats.pixels_shadows_retraced + a.stats.pixels_reused,
                  a.color.size());
        totals.reused += a.stats.pixels_reused;
        totals.traced += a.stats.pixels_traced;
        totals.shadows += a.stats.pixels_shadows_retraced;
        totals.pixels += a.color.size();
    }
    return totals;
}

TEST(ExactReuse, ProceduralMotionsMatchFullRendersWithBothTracers) {
    const Scene scene = moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        SCOPED_TRACE(tracer == Tracer::packet ? "packet" : "single");
        RenderOptions options;
        options.width = 88;  // edge tiles clipped on both axes
        options.height = 72;
        options.tracer = tracer;
        options.method = UpdateMethod::threshold;
        const Totals t = render_both_ways(scene, camera, options, {0, 1, 2, 3, 3, 8, 9, 20, 4});
        // Reuse did something: pixels kept, and shadows on the floor re-traced on their own.
        EXPECT_GT(t.reused, t.pixels / 4);
        EXPECT_GT(t.shadows, 0u);
    }
}

// A directional light's shadow rays run from their surface toward it without end, and a
// spot's are cut by its cone: kept shadows must still be re-traced exactly where a moving
// object may cross them.
TEST(ExactReuse, DirectionalAndSpotLightsMatchFullRenders) {
    const Scene scene = moving_scene();
    const Camera camera = default_camera(scene_bounds(scene));
    PointLight sun;
    sun.kind = PointLight::Kind::directional;
    sun.direction = glm::normalize(glm::vec3(0.6f, -1.0f, 0.2f));
    sun.intensity = 0.7f;
    PointLight spot{glm::vec3(0.0f, 3.0f, 1.0f), 1.5f};
    spot.kind = PointLight::Kind::spot;
    spot.direction = glm::normalize(glm::vec3(0.0f, -1.0f, -0.3f));
    spot.inner_cone = 0.3f;
    spot.outer_cone = 0.6f;
    spot.inverse_square = true;
    RenderOptions options;
    options.width = 88;
    options.height = 72;
    options.lights = {sun, spot};
    const Totals t = render_both_ways(scene, camera, options, {0, 1, 2, 3, 3, 8, 9});
    EXPECT_GT(t.reused, t.pixels / 4);
    EXPECT_GT(t.shadows, 0u);
}

// Light through glass is not remembered per pixel: the kept pixels of a tile that may change
// have their shadow rays traced again, and the images stay those of full renders.
TEST(ExactReuse, ShadowsThroughGlassMatchFullRenders) {
    // A still glass ball beside the moving objects: kept pixels in its shadow, in tiles where
    // something else moves, must get their light through it again.
    Scene scene = load_scene(kPlane + "+" + kRigid + "+" + kWave + "+" + kExplode + "+sphere:400@0.2,-0.5,0.9,0.4");
    anim::add_procedural_motions(scene, std::vector<std::string>{"rigid:" + kRigid, "wave:" + kWave, "explode:" + kExplode});
    Material glass = scene.materials[scene.objects.back().material];
    glass.transmittance = glm::vec3(0.8f, 0.6f, 0.3f);
    glass.ior = 1.2f;
    scene.materials.push_back(glass);
    scene.objects.back().material = std::uint32_t(scene.materials.size() - 1);
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = 88;
    options.height = 72;
    const Totals t = render_both_ways(scene, camera, options, {0, 1, 2, 3, 3, 8});
    EXPECT_GT(t.reused, t.pixels / 8);
    EXPECT_GT(t.shadows, 0u);
}

// A moving cut-out (alphaMode MASK): rays through its holes meet what is behind it, and kept
// pixels are traced again wherever its old or new place may cross their rays.
TEST(ExactReuse, MovingCutoutMatchesFullRenders) {
    Scene scene = moving_scene();
    Texture checker;
    checker.name = "checker";
    checker.texels = TexelArray{.width = 4, .height = 4, .channels = 2, .floating = false, .bytes = {}};
    for (int k = 0; k < 16; ++k) {
        checker.texels.bytes.push_back(200);
        checker.texels.bytes.push_back(((k % 4) + (k / 4)) % 2 == 0 ? 255 : 0);
    }
    scene.textures.push_back(checker);
    Material cut{.name = "cut"};
    cut.diffuse_map = TextureMap{.texture = 0};
    cut.alpha_cutoff = 0.5f;
    scene.materials.push_back(cut);
    // Every object but the floor is cut out, through coordinates taken from its positions.
    for (std::size_t o = 1; o < scene.objects.size(); ++o) {
        Object& object = scene.objects[o];
        object.material = std::uint32_t(scene.materials.size() - 1);
        object.mesh.texcoords.clear();
        for (const glm::vec3& p : object.mesh.positions) object.mesh.texcoords.emplace_back(3.0f * p.x, 3.0f * (p.y + p.z));
    }
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = 88;
    options.height = 72;
    const Totals t = render_both_ways(scene, camera, options, {0, 1, 2, 3, 3, 8});
    EXPECT_GT(t.reused, t.pixels / 4);
    EXPECT_GT(t.shadows, 0u);
}

TEST(ExactReuse, OnlyTheRigidObjectMovesOverAStillScene) {
    Scene scene = load_scene(kPlane + "+" + kRigid + "+" + kWave);
    const std::vector<std::string> motions{"rigid:" + kRigid};
    anim::add_procedural_motions(scene, motions);
    RenderOptions options;
    options.width = options.height = 96;
    const Totals t = render_both_ways(scene, default_camera(scene_bounds(scene)), options,
                                      {0, 1, 2, 3, 4, 5});
    EXPECT_GT(t.reused, t.pixels / 2);
}

/// Renders the first `frames` frames of a scene in ../shared/scenes both ways. With
/// `expect_reuse` false the scene moves too much to reuse (more changed boxes than the tile
/// tests are worth), and every frame after the first must say so.
void shared_scene_matches(const std::string& relative, int frames, bool still_scene_camera,
                          bool expect_reuse = true) {
    const std::string path = std::string(DYNRT_SHARED_SCENES_DIR) + "/" + relative;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " does not exist";
    const Scene scene = load_scene(path);
    RenderOptions options;
    options.width = options.height = 64;
    Camera camera = default_camera(scene_bounds(scene));
    if (still_scene_camera) {
        // The scene's own camera at frame 0, held still.
        Renderer poser(options);
        RenderedFrame unused;
        camera = poser.render(scene, 0, CameraSource::scene(), unused);
    }
    std::vector<int> list;
    for (int f = 0; f < frames; ++f) list.push_back(f);
    options.reuse.mode = PixelReuse::exact;
    Renderer reusing(options);
    options.reuse.mode = PixelReuse::off;
    Renderer full(options);
    RenderedFrame a, b;
    std::size_t reused = 0;
    for (const int f : list) {
        SCOPED_TRACE(relative + ", frame " + std::to_string(f));
        reusing.render(scene, camera, f, a);
        full.render(scene, camera, f, b);
        expect_same_frame(a, b);
        reused += a.stats.pixels_reused;
        if (!expect_reuse && f > 0) {
            EXPECT_NE(a.stats.reuse_reason.find("too many boxes"), std::string::npos)
                << a.stats.reuse_reason;
        }
    }
    if (expect_reuse) {
        EXPECT_GT(reused, 0u);
    }
}

TEST(ExactReuse, SkinnedModelMatchesFullRenders) {
    shared_scene_matches("cesiumman/CesiumMan.glb", 8, false);
}

TEST(ExactReuse, MorphingModelMatchesFullRenders) {
    shared_scene_matches("animatedmorphsphere/AnimatedMorphSphere.glb", 8, false);
}

TEST(ExactReuse, BartSceneHeldStillMatchesFullRenders) {
    shared_scene_matches("bart/kitchen/kitchen.aff", 6, true);
    // Every part of every robot moves: each frame is traced in full, and says why.
    shared_scene_matches("bart/robots/Robot.aff", 4, true, false);
}

TEST(ExactReuse, WhatForcesAFullTrace) {
    const Scene scene = moving_scene();
    Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = options.height = 48;
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    EXPECT_EQ(frame.stats.reuse_reason, "first frame");
    EXPECT_EQ(frame.stats.pixels_traced, frame.color.size());
    renderer.render(scene, camera, 0, frame);
    EXPECT_EQ(frame.stats.reuse_reason, "nothing changed");
    EXPECT_EQ(frame.stats.pixels_reused, frame.color.size());
    renderer.render(scene, camera, 1, frame);
    EXPECT_EQ(frame.stats.reuse_reason, "3 objects changed");
    // Another frame object, or one the caller edited, has nothing to reuse.
    RenderedFrame other;
    renderer.render(scene, camera, 2, other);
    EXPECT_EQ(other.stats.reuse_reason, "not the frame the last trace wrote");
    other.reuse_stamp = 0;
    renderer.render(scene, camera, 2, other);
    EXPECT_EQ(other.stats.reuse_reason, "not the frame the last trace wrote");
    camera.eye.x += 0.01f;
    renderer.render(scene, camera, 2, other);
    EXPECT_EQ(other.stats.reuse_reason, "camera moved");
    EXPECT_EQ(other.stats.pixels_traced, other.color.size());
    // Adaptive sampling traces afresh and keeps nothing.
    RenderOptions adaptive = options;
    adaptive.adaptive_tolerance = 0.05f;
    Renderer sampled(adaptive);
    sampled.render(scene, camera, 0, frame);
    EXPECT_EQ(frame.stats.reuse_mode, "off");
    EXPECT_EQ(frame.reuse_stamp, 0u);
}

// A camera that keeps moving is traced plainly after the first move (recording reuse memory
// would be wasted); when it holds still, one frame records again and the next reuses. Every
// frame is the full render's.
TEST(ExactReuse, MovingCameraTracesPlainlyThenReusesWhenItStops) {
    const Scene scene = moving_scene();
    const Camera start = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = options.height = 48;
    options.method = UpdateMethod::threshold;
    Renderer renderer(options);
    options.reuse.mode = PixelReuse::off;
    Renderer full(options);
    RenderedFrame frame, reference;
    const std::vector<std::pair<float, std::string>> steps = {
        {0.0f, "first frame"},   {0.1f, "camera moved"}, {0.2f, "camera moving"},
        {0.3f, "camera moving"}, {0.3f, "first frame"},  {0.3f, "3 objects changed"},
        {0.4f, "camera moved"},  {0.4f, "3 objects changed"}};
    for (std::size_t i = 0; i < steps.size(); ++i) {
        SCOPED_TRACE("step " + std::to_string(i));
        Camera camera = start;
        camera.eye.x += steps[i].first;
        renderer.render(scene, camera, int(i), frame);
        full.render(scene, camera, int(i), reference);
        expect_same_frame(frame, reference);
        EXPECT_EQ(frame.stats.reuse_reason, steps[i].second);
        EXPECT_EQ(frame.stats.reuse_mode, "exact");
    }
}

TEST(ExactReuse, ParsesItsSettings) {
    EXPECT_EQ(parse_reuse("exact").mode, PixelReuse::exact);
    EXPECT_EQ(parse_reuse("off").mode, PixelReuse::off);
    const ReuseSettings cache = parse_reuse("cache:0.125");
    EXPECT_EQ(cache.mode, PixelReuse::render_cache);
    EXPECT_EQ(cache.budget_share, 0.125f);
    const ReuseSettings frameless = parse_reuse("frameless:8ms");
    EXPECT_EQ(frameless.budget_ms, 8.0);
    EXPECT_EQ(to_string(frameless), "frameless:8ms");
    EXPECT_EQ(to_string(cache), "cache:0.125");
    for (const char* bad : {"", "exactly", "exact:0.5", "cache:0", "cache:1.5", "cache:x",
                            "frameless:-2ms", "cache:nan"}) {
        EXPECT_THROW(parse_reuse(bad), std::invalid_argument) << bad;
    }
}

// The changed-space tests against brute force: a segment or hull that meets a box must be
// reported (conservative), and one well clear of every box must not be.
TEST(ChangedSpace, RayTestIsConservativeAndTight) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-4.0f, 4.0f);
    const bvh::Aabb box{glm::vec3(-1.0f, -0.5f, 0.0f), glm::vec3(1.0f, 0.5f, 2.0f)};
    const detail::ChangedSpace space(std::span(&box, 1), 4.0f);
    packet::RayPacket rays;
    alignas(64) float until[packet::kPacketRays];
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        bvh::Ray ray;
        ray.org = {u(rng), u(rng), u(rng)};
        // Half the rays aimed near the box, so that both answers are common.
        const glm::vec3 aim = lane % 2 == 0 ? glm::vec3(u(rng), u(rng), u(rng)) * 0.4f - ray.org
                                            : glm::vec3(u(rng), u(rng), u(rng));
        ray.dir = glm::normalize(glm::vec3(aim.x, aim.y, lane % 7 == 0 ? 0.0f : aim.z));
        rays.set_ray(lane, ray);
        until[lane] = lane % 3 == 0 ? std::numeric_limits<float>::infinity() : 0.5f + 0.02f * float(lane);
    }
    const packet::LaneMask meets = space.meets_rays(rays, until, rays.active);
    int reported = 0;
    for (int lane = 0; lane < packet::kPacketRays; ++lane) {
        // Brute force: march the segment finely against the box grown or shrunk by a margin.
        const bvh::Ray r = rays.ray(lane);
        const float end = std::min(until[lane], 30.0f);
        bool inside_grown = false, inside_shrunk = false;
        for (int i = 0; i <= 6000; ++i) {
            const glm::vec3 p = r.org + (end * float(i) / 6000.0f) * r.dir;
            const auto in = [&](float m) {
                return glm::all(glm::greaterThanEqual(p, box.lo - m)) &&
                       glm::all(glm::lessThanEqual(p, box.hi + m));
            };
            inside_shrunk |= in(-0.01f);
            inside_grown |= in(0.05f);
        }
        if (inside_shrunk) {
            EXPECT_TRUE(meets.test(lane)) << "lane " << lane << " meets the box";
        }
        if (!inside_grown) {
            EXPECT_FALSE(meets.test(lane)) << "lane " << lane << " is clear of it";
        }
        reported += meets.test(lane);
    }
    EXPECT_GT(reported, 10);
    EXPECT_LT(reported, packet::kPacketRays - 10);
}

/// Brute force for ChangedSpace's tests: whether points along the paths from a grid of
/// (grid + 1)^3 points over `points` (`path(q, f)`, f in [0, 1] in `steps` steps) come into
/// `box` (touches) or within 0.1 of it (near).
struct Contact {
    bool touches = false, near = false;
};
template <class Path>
Contact brute_force_contact(const bvh::Aabb& box, const bvh::Aabb& points, int grid, int steps, Path&& path) {
    Contact c;
    const glm::vec3 size = points.hi - points.lo;
    for (int i = 0; i <= grid; ++i) {
        for (int j = 0; j <= grid; ++j) {
            for (int k = 0; k <= grid; ++k) {
                const glm::vec3 q = points.lo + size * glm::vec3(i, j, k) / float(grid);
                for (int s = 0; s <= steps; ++s) {
                    const glm::vec3 p = path(q, float(s) / float(steps));
                    const auto in = [&](float m) {
                        return glm::all(glm::greaterThanEqual(p, box.lo - m)) && glm::all(glm::lessThanEqual(p, box.hi + m));
                    };
                    c.touches |= in(0.0f);
                    c.near |= in(0.1f);
                }
            }
        }
    }
    return c;
}

TEST(ChangedSpace, SweepTestIsConservativeAndTight) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    int met = 0, clear = 0;
    for (int trial = 0; trial < 300; ++trial) {
        bvh::Aabb box;
        box.extend(glm::vec3(u(rng), u(rng), u(rng)));
        box.extend(box.lo + glm::vec3(0.3f + 0.2f * std::abs(u(rng))));
        const detail::ChangedSpace space(std::span(&box, 1), 6.0f);
        bvh::Aabb points;
        points.extend(glm::vec3(u(rng), u(rng), u(rng)));
        points.extend(points.lo + glm::vec3(0.4f));
        // Half the trials aim the sweep at the box.
        glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        if (trial % 2 == 0) dir = glm::normalize(box.center() - points.center() + 0.2f * dir);
        if (trial % 7 == 0) dir.y = 0.0f;  // parallel to a slab
        // 20 units along each: past every box.
        const auto [touches, near] =
            brute_force_contact(box, points, 6, 400, [&](const glm::vec3& q, float f) { return q + 20.0f * f * dir; });
        const bool sweep = space.meets_sweep(points, dir);
        if (touches) {
            EXPECT_TRUE(sweep) << "trial " << trial;
        }
        if (!near) {
            EXPECT_FALSE(sweep) << "trial " << trial;
        }
        detail::ChangedSpace kept;
        EXPECT_EQ(space.select_sweep(points, dir, kept), sweep);
        met += sweep;
        clear += !sweep;
    }
    EXPECT_GT(met, 60);
    EXPECT_GT(clear, 60);
}

TEST(ChangedSpace, HullAndPyramidTestsAreConservativeAndTight) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    int met = 0, clear = 0;
    for (int trial = 0; trial < 300; ++trial) {
        bvh::Aabb box;
        box.extend(glm::vec3(u(rng), u(rng), u(rng)));
        box.extend(box.lo + glm::vec3(0.3f + 0.2f * std::abs(u(rng))));
        const detail::ChangedSpace space(std::span(&box, 1), 6.0f);
        const glm::vec3 apex(u(rng), u(rng), u(rng));
        bvh::Aabb points;
        // Points often beyond the box as seen from the apex, so that both answers are common.
        const glm::vec3 beyond = box.center() + (box.center() - apex) * (0.2f + 0.3f * std::abs(u(rng)));
        points.extend(trial % 2 == 0 ? beyond + glm::vec3(u(rng), u(rng), u(rng)) * 0.2f
                                     : glm::vec3(u(rng), u(rng), u(rng)));
        points.extend(points.lo + glm::vec3(0.5f));
        // Brute force over segments from the apex to a grid of points of the box.
        const auto [touches, near] =
            brute_force_contact(box, points, 8, 200, [&](const glm::vec3& q, float f) { return apex + f * (q - apex); });
        const bool hull = space.meets_hull(apex, points);
        if (touches) {
            EXPECT_TRUE(hull) << "trial " << trial;
        }
        if (!near) {
            EXPECT_FALSE(hull) << "trial " << trial;
        }
        met += hull;
        clear += !hull;
        // The pyramid from the apex through the corners of a square facing the box's centre.
        const glm::vec3 centre = box.center();
        const glm::vec3 forward = glm::normalize(centre - apex);
        const glm::vec3 side = glm::normalize(glm::cross(forward, glm::vec3(0.3f, 1.0f, 0.1f)));
        const glm::vec3 up = glm::cross(side, forward);
        const float half = 0.01f + 0.3f * std::abs(u(rng)) / 3.0f;
        const float off = u(rng) / 3.0f;
        const glm::vec3 aim = forward + off * side;
        const glm::vec3 corners[4] = {aim - half * side - half * up, aim + half * side - half * up,
                                      aim - half * side + half * up, aim + half * side + half * up};
        const bool centre_ray_hits = std::abs(off) <= half;  // the ray through the centre is inside
        if (centre_ray_hits) {
            EXPECT_TRUE(space.meets_pyramid(apex, corners)) << "trial " << trial;
        }
        // Pointed away from a box at a distance, it never meets it.
        const glm::vec3 away[4] = {-corners[0], -corners[1], -corners[2], -corners[3]};
        if (glm::length(apex - centre) > 2.0f) {
            EXPECT_FALSE(space.meets_pyramid(apex, away)) << "trial " << trial;
        }
    }
    EXPECT_GT(met, 20);
    EXPECT_GT(clear, 20);
}

}  // namespace
}  // namespace dynrt
