// Engine::render against dynrt::Renderer: the same geometry (static, rigid and deformable
// meshes with transforms), lights, camera and materials give the same frame pixel for pixel:
// colour, depth and mesh ids. World positions are computed in double and rounded once on both
// sides, and both trace through the same frame tracer, so equality is exact. Shading normals
// too: the ball's are given (MeshDesc::normals, the scene's Mesh::normals), the others'
// computed (area_weighted_normals on both sides, again after set_positions).

#include "api_test_world.h"

#include "dynrt/anim/motion_class.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/vertex_normals.h"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <chrono>
#include <thread>
#include <cstdint>
#include <random>
#include <cstring>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

struct Piece {
    std::string name;
    MeshData mesh;
    Motion motion;
    Transform transform;
    Surface surface;
    /// Given shading normals (x, y, z per vertex), or empty: computed.
    std::vector<float> normals = {};
};

/// A sphere's own normals: its vertices' directions from its centre (at the origin).
std::vector<float> radial_normals(const MeshData& mesh) {
    std::vector<float> normals(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.vertices(); ++v) {
        const glm::vec3 n = glm::normalize(
            glm::vec3(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]));
        for (int a = 0; a < 3; ++a) normals[3 * v + std::size_t(a)] = n[a];
    }
    return normals;
}

std::vector<Piece> pieces() {
    std::vector<Piece> p;
    p.push_back({"floor", sheet(0.0f, 0.0f, 0.0f, 6.0f, 8), Motion::static_,
                 Transform::rotation({1.0f, 0.0f, 0.0f}, -1.5707964f, {0.0f, -1.0f, 0.0f}),
                 Surface{{0.7f, 0.7f, 0.6f}, {0.1f, 0.1f, 0.1f}, 8.0f}});
    p.push_back({"ball", sphere({0.0f, 0.0f, 0.0f}, 0.8f), Motion::static_,
                 Transform::translation({-1.2f, 0.0f, 0.3f}), Surface{{0.9f, 0.2f, 0.2f}, {0.5f, 0.5f, 0.5f}, 64.0f}});
    p.back().normals = radial_normals(p.back().mesh);
    p.push_back({"arm", sphere({0.0f, 0.0f, 0.0f}, 0.6f, 8, 16), Motion::rigid,
                 Transform::rotation({0.0f, 1.0f, 0.0f}, 0.7f, {1.3f, 0.2f, -0.4f}),
                 Surface{{0.2f, 0.8f, 0.3f}, {0.3f, 0.3f, 0.3f}, 16.0f}});
    p.push_back({"cloth", sheet(0.0f, 0.0f, 0.0f, 2.0f, 12), Motion::deformable,
                 Transform::rotation({1.0f, 0.2f, 0.0f}, 0.4f, {0.0f, 1.2f, -1.0f}),
                 Surface{{0.2f, 0.3f, 0.9f}, {0.2f, 0.2f, 0.2f}, 32.0f}});
    p.back().mesh.positions = waved(p.back().mesh, 0.5f, 0.2f);
    return p;
}

glm::mat4 to_mat4(const Transform& t) {
    glm::mat4 m;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) m[c][r] = t.m[std::size_t(c * 4 + r)];
    }
    return m;
}

anim::MotionClass to_class(Motion motion) {
    switch (motion) {
        case Motion::rigid: return anim::MotionClass::rigid;
        case Motion::deformable: return anim::MotionClass::deformable;
        case Motion::exploding: return anim::MotionClass::exploding;
        default: return anim::MotionClass::static_;
    }
}

/// The pieces as a scene the Renderer takes: object-space positions and a float transform,
/// with the motion classes forced through class overrides (the poser computes world
/// positions in double from Object::transform, as the engine does from MeshDesc::transform).
Scene scene_of(const std::vector<Piece>& pieces, anim::PoseSettings& pose) {
    Scene scene;
    scene.source = "api render test";
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const Piece& p = pieces[i];
        Object object;
        object.name = p.name;
        for (std::size_t v = 0; v < p.mesh.vertices(); ++v) {
            object.mesh.positions.emplace_back(p.mesh.positions[3 * v], p.mesh.positions[3 * v + 1],
                                               p.mesh.positions[3 * v + 2]);
        }
        for (std::size_t k = 0; k < p.mesh.indices.size(); k += 3) {
            object.mesh.triangles.emplace_back(p.mesh.indices[k], p.mesh.indices[k + 1], p.mesh.indices[k + 2]);
        }
        object.transform = to_mat4(p.transform);
        if (p.normals.empty()) {
            object.mesh.normals = area_weighted_normals(object.mesh.positions, object.mesh.triangles);
        } else {
            // Normalised in float, as the engine normalises what it is given (and loaders what
            // files give).
            for (std::size_t v = 0; v < p.mesh.vertices(); ++v) {
                object.mesh.normals.push_back(
                    normalize_or_zero(glm::vec3(p.normals[3 * v], p.normals[3 * v + 1], p.normals[3 * v + 2])));
            }
        }
        object.material = std::uint32_t(i);
        scene.objects.push_back(std::move(object));
        Material material;
        material.name = p.name;
        material.diffuse = {p.surface.diffuse.x, p.surface.diffuse.y, p.surface.diffuse.z};
        material.specular = {p.surface.specular.x, p.surface.specular.y, p.surface.specular.z};
        material.shininess = p.surface.shininess;
        material.reflectance = {p.surface.reflectance.x, p.surface.reflectance.y, p.surface.reflectance.z};
        material.transmittance = {p.surface.transmittance.x, p.surface.transmittance.y, p.surface.transmittance.z};
        material.ior = p.surface.ior;
        scene.materials.push_back(material);
        if (p.motion != Motion::static_) {
            pose.class_overrides.push_back(anim::ClassOverride{std::uint32_t(i), to_class(p.motion), p.name});
        }
    }
    return scene;
}

void add_pieces(Engine& engine, const std::vector<Piece>& pieces) {
    for (const Piece& p : pieces) {
        MeshDesc d;
        d.name = p.name;
        d.positions = p.mesh.positions;
        d.indices = p.mesh.indices;
        d.normals = p.normals;
        d.motion = p.motion;
        d.transform = p.transform;
        d.surface = p.surface;
        engine.add_mesh(d);
    }
}

struct Image {
    std::vector<float> rgb, depth;
    std::vector<std::int32_t> mesh;
    Image(int w, int h) : rgb(std::size_t(w * h * 3)), depth(std::size_t(w * h)), mesh(std::size_t(w * h)) {}
};

constexpr int kWidth = 96, kHeight = 72;

void expect_same_frame(const RenderedFrame& want, const Image& got, bool hit_buffers) {
    int bad_rgb = 0, bad_depth = 0, bad_mesh = 0, hits = 0;
    for (std::size_t p = 0; p < want.color.size(); ++p) {
        for (int c = 0; c < 3; ++c) {
            bad_rgb += std::bit_cast<std::uint32_t>(want.color[p][c]) != std::bit_cast<std::uint32_t>(got.rgb[3 * p + std::size_t(c)]);
        }
        if (!hit_buffers) continue;
        bad_depth += std::bit_cast<std::uint32_t>(want.depth[p]) != std::bit_cast<std::uint32_t>(got.depth[p]);
        bad_mesh += want.object[p] != got.mesh[p];
        hits += want.object[p] >= 0;
    }
    EXPECT_EQ(bad_rgb, 0);
    EXPECT_EQ(bad_depth, 0);
    EXPECT_EQ(bad_mesh, 0);
    if (hit_buffers) {
        EXPECT_GT(hits, kWidth * kHeight / 3) << "the view should see the scene";
    }
}

TEST(ApiRender, SameFrameAsTheRendererPixelForPixel) {
    const std::vector<Piece> ps = pieces();
    RenderOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.lights = {PointLight{{3.0f, 5.0f, 4.0f}, 0.8f}, PointLight{{-4.0f, 3.0f, 2.0f}, 0.5f}};
    options.background = {0.1f, 0.2f, 0.3f};
    options.ambient = 0.12f;
    const Scene scene = scene_of(ps, options.pose);
    Renderer renderer(options);
    const Camera camera{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    RenderedFrame want;
    renderer.render(scene, camera, 0, want);
    // The renderer did treat the pieces as meant.
    EXPECT_EQ(want.stats.static_objects, 2u);
    EXPECT_EQ(want.stats.rigid_objects, 1u);
    EXPECT_EQ(want.stats.deformable_objects, 1u);

    Engine engine;
    add_pieces(engine, ps);
    engine.update();
    RenderSettings settings;
    settings.lights = {Light{{3.0f, 5.0f, 4.0f}, 0.8f}, Light{{-4.0f, 3.0f, 2.0f}, 0.5f}};
    settings.background = {0.1f, 0.2f, 0.3f};
    settings.ambient = 0.12f;
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    Image full(kWidth, kHeight);
    const FrameStats stats = engine.render(view, ImageView{kWidth, kHeight, full.rgb, full.depth, full.mesh}, settings);
    expect_same_frame(want, full, true);
    EXPECT_EQ(stats.primary_rays, want.stats.primary_rays);
    EXPECT_EQ(stats.shadow_rays, want.stats.shadow_rays);
    EXPECT_EQ(stats.triangles, want.stats.triangles);

    // Depth and mesh buffers are optional, and leave the colour as it was.
    Image bare(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, bare.rgb}, settings);
    expect_same_frame(want, bare, false);
    Image depth_only(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, depth_only.rgb, depth_only.depth}, settings);
    expect_same_frame(want, depth_only, false);
    EXPECT_EQ(depth_only.depth, full.depth);
    Image mesh_only(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, mesh_only.rgb, {}, mesh_only.mesh}, settings);
    EXPECT_EQ(mesh_only.mesh, full.mesh);
}

// EngineOptions::compact_leaves (the static meshes' leaves read their vertices instead of a
// copy) and EngineOptions::quantized_nodes (their tree's boxes in 8-bit planes), apart and
// together. Frames and ray hits are the default engine's bit for bit, before and after a
// static mesh is removed (also in the render between remove_mesh and update, which still shows
// it), in fewer bytes.
TEST(ApiRender, CompactLeavesAndQuantizedNodesGiveTheSameFramesAndHitsInFewerBytes) {
    const std::vector<Piece> ps = pieces();
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    std::mt19937 rng(3);
    const std::vector<Ray> rays = coherent_rays(rng, {1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 0.5f, 2000);
    struct Layout {
        bool compact, quantized;
    };
    for (const Layout layout : {Layout{true, false}, Layout{false, true}, Layout{true, true}}) {
        SCOPED_TRACE(std::string(layout.compact ? "compact leaves" : "full blocks") +
                     (layout.quantized ? ", quantised nodes" : ""));
        EngineOptions options;
        Engine full(options);
        options.compact_leaves = layout.compact;
        options.quantized_nodes = layout.quantized;
        Engine compact(options);
        for (Engine* engine : {&full, &compact}) add_pieces(*engine, ps);
        const auto expect_same = [&](const char* when) {
            SCOPED_TRACE(when);
            Image a(kWidth, kHeight), b(kWidth, kHeight);
            full.render(view, ImageView{kWidth, kHeight, a.rgb, a.depth, a.mesh});
            compact.render(view, ImageView{kWidth, kHeight, b.rgb, b.depth, b.mesh});
            EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
            EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)), 0);
            EXPECT_EQ(a.mesh, b.mesh);
            std::vector<RayHit> ha(rays.size()), hb(rays.size());
            full.intersect(rays, ha);
            compact.intersect(rays, hb);
            int hits = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_TRUE(identical(ha[i], hb[i])) << describe(rays[i]) << ": " << describe(ha[i]) << " / " << describe(hb[i]);
                hits += ha[i].hit() ? 1 : 0;
            }
            EXPECT_GT(hits, 500);
        };
        full.update();
        compact.update();
        expect_same("after the first update");
        EXPECT_LT(compact.memory_bytes(), full.memory_bytes());
        // The static ball (mesh 1) goes: still drawn until the update, then gone from both.
        full.remove_mesh(MeshId{1});  // ids count from 0 in the order added
        compact.remove_mesh(MeshId{1});
        expect_same("between remove_mesh and update");
        full.update();
        compact.update();
        expect_same("after the update");
    }
}

// EngineOptions::memory_budget picks the static meshes' layout: a budget below what any
// layout is predicted to need gives the smallest (compact leaves, quantised nodes: the bytes of
// an engine asked for them), an ample one the full layout (the default engine's bytes); the
// frames are the default engine's bit for bit. The choice is reported on the update that built
// the static meshes' tree, and only then.
TEST(ApiRender, AMemoryBudgetChoosesTheStaticLayoutAndReportsIt) {
    const std::vector<Piece> ps = pieces();
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    EngineOptions options;
    Engine full(options);
    options.compact_leaves = options.quantized_nodes = true;
    Engine smallest(options);
    options = EngineOptions{};
    options.memory_budget = 1'000'000;  // less than the process already holds
    Engine tight(options);
    options.memory_budget = std::size_t(1) << 50;
    Engine ample(options);
    for (Engine* engine : {&full, &smallest, &tight, &ample}) {
        add_pieces(*engine, ps);
        const FrameStats stats = engine->update();
        if (engine == &tight) {
            EXPECT_EQ(stats.static_layout, "compact leaves, quantized nodes");
            EXPECT_NE(stats.static_layout_why.find("over the budget even with the smallest layout"), std::string::npos)
                << stats.static_layout_why;
            EXPECT_GT(stats.static_layout_predicted_peak, std::size_t(1'000'000));
        } else if (engine == &ample) {
            EXPECT_EQ(stats.static_layout, "full leaves, float nodes");
            EXPECT_EQ(stats.static_layout_why.find("over the budget"), std::string::npos) << stats.static_layout_why;
        } else {
            EXPECT_EQ(stats.static_layout, "");  // no budget, no choice
        }
    }
    EXPECT_EQ(tight.memory_bytes(), smallest.memory_bytes());
    EXPECT_EQ(ample.memory_bytes(), full.memory_bytes());
    EXPECT_LT(tight.memory_bytes(), full.memory_bytes());
    Image want(kWidth, kHeight);
    full.render(view, ImageView{kWidth, kHeight, want.rgb, want.depth, want.mesh});
    for (Engine* engine : {&tight, &ample}) {
        Image got(kWidth, kHeight);
        engine->render(view, ImageView{kWidth, kHeight, got.rgb, got.depth, got.mesh});
        EXPECT_EQ(std::memcmp(want.rgb.data(), got.rgb.data(), want.rgb.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(want.depth.data(), got.depth.data(), want.depth.size() * sizeof(float)), 0);
        EXPECT_EQ(want.mesh, got.mesh);
    }
    // The next update keeps the static tree: nothing is chosen.
    EXPECT_EQ(tight.update().static_layout, "");
}

// Engine::cancel_render from another thread stops a render in progress; the next render is
// whole (the same as one never stopped).
TEST(ApiRender, ARenderStoppedFromAnotherThreadReturnsAndTheNextIsWhole) {
    Engine engine;
    add_pieces(engine, pieces());
    engine.update();
    RenderSettings settings;
    settings.samples_per_pixel = 16;
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    Image whole(kWidth, kHeight);
    Engine other;
    add_pieces(other, pieces());
    other.update();
    other.render(view, ImageView{kWidth, kHeight, whole.rgb}, settings);
    std::atomic<bool> finished{false};
    FrameStats stopped;
    Image image(kWidth, kHeight);
    std::thread render([&] {
        stopped = engine.render(view, ImageView{kWidth, kHeight, image.rgb}, settings);
        finished = true;
    });
    while (!finished) {
        engine.cancel_render();
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    render.join();
    EXPECT_TRUE(stopped.cancelled);
    const FrameStats next = engine.render(view, ImageView{kWidth, kHeight, image.rgb}, settings);
    EXPECT_FALSE(next.cancelled);
    EXPECT_EQ(image.rgb, whole.rgb);
}

// Progress polled from another thread: nothing before the first render; while it runs the
// tile passes done only grow toward every tile once per sample; after it, all of them done.
TEST(ApiRender, ProgressCountsTilePassesWhileARenderRuns) {
    Engine engine;
    add_pieces(engine, pieces());
    engine.update();
    EXPECT_FALSE(engine.render_progress().tracing);
    EXPECT_EQ(engine.render_progress().tiles_total, 0u);
    EXPECT_EQ(engine.render_progress().fraction(), 0.0);
    RenderSettings settings;
    settings.samples_per_pixel = 9;
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    const std::size_t passes = std::size_t((kWidth + 15) / 16) * std::size_t((kHeight + 15) / 16) * 9;
    Image image(kWidth, kHeight);
    std::atomic<bool> finished{false};
    std::thread render([&] {
        engine.render(view, ImageView{kWidth, kHeight, image.rgb}, settings);
        finished = true;
    });
    std::size_t last = 0;
    int seen_tracing = 0;
    while (!finished) {
        const RenderProgress p = engine.render_progress();
        if (p.tracing) {
            ++seen_tracing;
            EXPECT_EQ(p.tiles_total, passes);
            EXPECT_GE(p.tiles_done, last);
            EXPECT_LE(p.tiles_done, p.tiles_total);
            last = p.tiles_done;
        }
        std::this_thread::yield();
    }
    render.join();
    const RenderProgress after = engine.render_progress();
    EXPECT_FALSE(after.tracing);
    EXPECT_EQ(after.tiles_total, passes);
    EXPECT_EQ(after.tiles_done, passes);
    EXPECT_EQ(after.fraction(), 1.0);
    RecordProperty("polls_while_tracing", seen_tracing);
}

TEST(ApiRender, DefaultLightIsTheRenderersDefault) {
    const std::vector<Piece> ps = pieces();
    RenderOptions options;
    options.width = kWidth;
    options.height = kHeight;
    const Scene scene = scene_of(ps, options.pose);
    Renderer renderer(options);
    const Camera camera{{-2.0f, 3.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 40.0f};
    RenderedFrame want;
    renderer.render(scene, camera, 0, want);

    Engine engine;
    add_pieces(engine, ps);
    engine.update();
    Image got(kWidth, kHeight);
    engine.render(View{{-2.0f, 3.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 40.0f},
                  ImageView{kWidth, kHeight, got.rgb, got.depth, got.mesh});
    expect_same_frame(want, got, true);
}

TEST(ApiRender, AfterMovesTheFrameShowsTheNewGeometry) {
    // Moved through the API for a few steps, then compared with a renderer given the geometry
    // of the last step from the start.
    std::vector<Piece> ps = pieces();
    Engine engine;
    add_pieces(engine, ps);
    engine.update();
    for (int step = 1; step <= 3; ++step) {
        ps[2].transform = Transform::rotation({0.0f, 1.0f, 0.0f}, 0.7f + 0.3f * float(step), {1.3f, 0.2f * float(step), -0.4f});
        engine.set_transform(MeshId{2}, ps[2].transform);
        ps[3].mesh.positions = waved(pieces()[3].mesh, 0.5f + float(step), 0.2f);
        engine.set_positions(MeshId{3}, ps[3].mesh.positions);
        engine.update();
    }
    Surface red{{1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0f};
    engine.set_surface(MeshId{1}, red);
    ps[1].surface = red;
    engine.update();

    RenderOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.lights = {PointLight{{3.0f, 5.0f, 4.0f}, 1.0f}};
    const Scene scene = scene_of(ps, options.pose);
    Renderer renderer(options);
    const Camera camera{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    RenderedFrame want;
    renderer.render(scene, camera, 0, want);
    RenderSettings settings;
    settings.lights = {Light{{3.0f, 5.0f, 4.0f}, 1.0f}};
    Image got(kWidth, kHeight);
    engine.render(View{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f},
                  ImageView{kWidth, kHeight, got.rgb, got.depth, got.mesh}, settings);
    expect_same_frame(want, got, true);
}

TEST(ApiRender, SetSurfaceTakesEffectAtTheNextRender) {
    // "A new material, used from the next render on" (api/engine.h): no update in between.
    std::vector<Piece> ps = pieces();
    Engine engine;
    add_pieces(engine, ps);
    engine.update();
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    RenderSettings settings;
    settings.lights = {Light{{3.0f, 5.0f, 4.0f}, 1.0f}};
    Image before(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, before.rgb}, settings);
    const Surface red{{1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0f};
    engine.set_surface(MeshId{1}, red);
    ps[1].surface = red;

    RenderOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.lights = {PointLight{{3.0f, 5.0f, 4.0f}, 1.0f}};
    const Scene scene = scene_of(ps, options.pose);
    Renderer renderer(options);
    RenderedFrame want;
    renderer.render(scene, Camera{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f}, 0, want);
    Image got(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, got.rgb, got.depth, got.mesh}, settings);
    EXPECT_NE(got.rgb, before.rgb);
    expect_same_frame(want, got, true);
}

TEST(ApiRender, MirrorAndGlassSurfacesGiveTheRenderersFrame) {
    // Surface's reflectance, transmittance and ior reach the material the renderer shades
    // with, from add_mesh and from set_surface: the frame is the Renderer's for a scene with
    // those materials, not the one without them.
    std::vector<Piece> ps = pieces();
    ps[0].surface.reflectance = {0.5f, 0.5f, 0.4f};  // a mirror floor
    ps[1].surface.transmittance = {0.9f, 0.9f, 0.8f};  // a glass ball
    ps[1].surface.ior = 1.5f;
    Engine engine;
    add_pieces(engine, ps);
    engine.update();
    RenderOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.lights = {PointLight{{3.0f, 5.0f, 4.0f}, 1.0f}};
    RenderSettings settings;
    settings.lights = {Light{{3.0f, 5.0f, 4.0f}, 1.0f}};
    const Camera camera{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    const View view{{1.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
    const auto renderer_frame = [&](const std::vector<Piece>& pieces_now) {
        RenderOptions o = options;
        const Scene scene = scene_of(pieces_now, o.pose);
        Renderer renderer(o);
        RenderedFrame frame;
        renderer.render(scene, camera, 0, frame);
        return frame;
    };
    const RenderedFrame want = renderer_frame(ps);
    std::vector<Piece> opaque = ps;
    for (Piece& p : opaque) p.surface = Surface{p.surface.diffuse, p.surface.specular, p.surface.shininess};
    // Else this test could not tell whether the terms were passed on.
    ASSERT_NE(want.color, renderer_frame(opaque).color) << "the renderer ignores reflectance and transmittance";
    Image got(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, got.rgb, got.depth, got.mesh}, settings);
    expect_same_frame(want, got, true);

    // set_surface replaces all of it, also when only a Whitted term changes: first the floor
    // stops mirroring (its Phong terms stay), then the ball becomes a red mirror.
    ps[0].surface = opaque[0].surface;
    engine.set_surface(MeshId{0}, ps[0].surface);
    const RenderedFrame want_dull_floor = renderer_frame(ps);
    ASSERT_NE(want_dull_floor.color, want.color);
    Image dull_floor(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, dull_floor.rgb, dull_floor.depth, dull_floor.mesh}, settings);
    expect_same_frame(want_dull_floor, dull_floor, true);

    ps[1].surface = Surface{{1.0f, 0.0f, 0.0f}, {0.2f, 0.2f, 0.2f}, 16.0f, {0.6f, 0.6f, 0.6f}, {}, 1.0f};
    engine.set_surface(MeshId{1}, ps[1].surface);
    const RenderedFrame want_mirror_ball = renderer_frame(ps);
    ASSERT_NE(want_mirror_ball.color, want_dull_floor.color);
    Image mirror_ball(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, mirror_ball.rgb, mirror_ball.depth, mirror_ball.mesh}, settings);
    expect_same_frame(want_mirror_ball, mirror_ball, true);

    // RenderSettings' depth and cut-off reach the renderer: depth 0 is the opaque frame.
    RenderSettings flat = settings;
    flat.max_depth = 0;
    const RenderedFrame want_flat = [&] {
        RenderOptions o = options;
        o.secondary.max_depth = 0;
        const Scene scene = scene_of(ps, o.pose);
        Renderer renderer(o);
        RenderedFrame frame;
        renderer.render(scene, camera, 0, frame);
        return frame;
    }();
    ASSERT_NE(want_flat.color, want_mirror_ball.color);
    Image flat_image(kWidth, kHeight);
    engine.render(view, ImageView{kWidth, kHeight, flat_image.rgb, flat_image.depth, flat_image.mesh}, flat);
    expect_same_frame(want_flat, flat_image, true);
}

}  // namespace
}  // namespace dynrt::api_test
