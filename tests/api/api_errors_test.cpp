// Bad input to the library API: every failing call throws dynrt::Error with the right code and
// a message naming what was wrong (the mesh, the step, the vertex, the ray), leaves the engine
// as it was, and nothing crashes on huge or degenerate geometry.

#include "api_test_world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr auto kArgument = Error::Code::invalid_argument;
constexpr auto kGeometry = Error::Code::invalid_geometry;
constexpr auto kState = Error::Code::invalid_state;

MeshDesc desc_of(const std::string& name, const MeshData& mesh, Motion motion = Motion::automatic) {
    MeshDesc d;
    d.name = name;
    d.positions = mesh.positions;
    d.indices = mesh.indices;
    d.motion = motion;
    return d;
}

TEST(ApiErrors, BadEngineOptions) {
    const auto refused = [](auto change, const char* fragment) {
        EngineOptions options;
        change(options);
        expect_error([&] { Engine engine(options); }, kArgument, {fragment});
    };
    refused([](EngineOptions& o) { o.threads = -1; }, "threads");
    refused([](EngineOptions& o) { o.cost_ratio = 0.0f; }, "cost_ratio");
    refused([](EngineOptions& o) { o.cost_ratio = kNaN; }, "cost_ratio");
    refused([](EngineOptions& o) { o.cost_ratio = 2e6f; }, "cost_ratio");
    refused([](EngineOptions& o) { o.cost_ratio_exploding = -1.0f; }, "cost_ratio_exploding");
    refused([](EngineOptions& o) { o.leaf_size = 0; }, "leaf_size");
    refused([](EngineOptions& o) { o.leaf_size = 65; }, "leaf_size");
    refused([](EngineOptions& o) { o.rebuild_threshold = -0.1; }, "rebuild_threshold");
    refused([](EngineOptions& o) { o.rebuild_threshold = std::nan(""); }, "rebuild_threshold");
    EngineOptions edge;
    edge.leaf_size = 64;
    edge.cost_ratio = 1e6f;
    edge.rebuild_threshold = std::numeric_limits<double>::infinity();
    Engine engine(edge);  // the limits themselves are fine
}

TEST(ApiErrors, BadMeshesAreRefusedNamingTheMesh) {
    Engine engine;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 1.0f);

    MeshData odd = ball;
    odd.positions.pop_back();
    expect_error([&] { engine.add_mesh(desc_of("odd", odd)); }, kArgument, {"'odd'", "multiple of 3"});
    MeshData odd_indices = ball;
    odd_indices.indices.pop_back();
    expect_error([&] { engine.add_mesh(desc_of("oddi", odd_indices)); }, kArgument, {"'oddi'", "multiple of 3"});
    MeshData out_of_range = ball;
    out_of_range.indices[7] = std::uint32_t(ball.vertices());
    expect_error([&] { engine.add_mesh(desc_of("far", out_of_range)); }, kArgument,
                 {"'far'", "index 7", "triangle 2"});
    for (const float bad : {kNaN, kInf, -kInf}) {
        MeshData nan = ball;
        nan.positions[3 * 5 + 1] = bad;
        expect_error([&] { engine.add_mesh(desc_of("nan", nan)); }, kArgument, {"'nan'", "vertex 5"});
        // Borrowed positions are checked at add_mesh too.
        MeshDesc borrowed = desc_of("nanb", nan);
        borrowed.ownership = Ownership::borrow;
        expect_error([&] { engine.add_mesh(borrowed); }, kArgument, {"'nanb'", "vertex 5"});
    }
    for (const float bad : {kNaN, kInf}) {
        MeshDesc d = desc_of("moved", ball);
        d.transform = Transform::translation({1.0f, bad, 0.0f});
        expect_error([&] { engine.add_mesh(d); }, kArgument, {"'moved'", "not finite"});
    }
    MeshDesc projective = desc_of("projective", ball);
    projective.transform.m[3] = 0.5f;  // last row (0.5, 0, 0, 1)
    expect_error([&] { engine.add_mesh(projective); }, kArgument, {"'projective'", "affine"});
    MeshDesc shiny = desc_of("shiny", ball);
    shiny.surface.shininess = -1.0f;
    expect_error([&] { engine.add_mesh(shiny); }, kArgument, {"'shiny'"});
    // The Whitted terms (types.h, Surface): finite, weights >= 0, ior > 0.
    const auto refused_surface = [&](auto change, const char* fragment) {
        MeshDesc d = desc_of("glass", ball);
        change(d.surface);
        expect_error([&] { engine.add_mesh(d); }, kArgument, {"add_mesh 'glass': surface ", fragment});
    };
    refused_surface([](Surface& s) { s.reflectance.y = -0.5f; }, "reflectance (0, -0.5, 0) must be finite and >= 0");
    refused_surface([](Surface& s) { s.reflectance.x = kNaN; }, "reflectance (nan, 0, 0) must be finite and >= 0");
    refused_surface([](Surface& s) { s.transmittance.z = kInf; }, "transmittance (0, 0, inf) must be finite and >= 0");
    refused_surface([](Surface& s) { s.transmittance = {-1.0f, -1.0f, -1.0f}; },
                    "transmittance (-1, -1, -1) must be finite and >= 0");
    refused_surface([](Surface& s) { s.emission = {0.0f, -1.0f, 0.0f}; }, "emission (0, -1, 0) must be finite and >= 0");
    refused_surface([](Surface& s) { s.emission.x = kNaN; }, "emission (nan, 0, 0) must be finite and >= 0");
    refused_surface([](Surface& s) { s.ior = 0.0f; }, "ior 0 must be finite and > 0");
    // Colours: a negative one would shade darker than black (issue 34).
    refused_surface([](Surface& s) { s.diffuse.x = -0.2f; }, "diffuse (-0.2, 0.8, 0.8) must be finite and >= 0");
    refused_surface([](Surface& s) { s.specular.z = -1.0f; }, "must be finite and >= 0");
    refused_surface([](Surface& s) { s.shininess = -1.0f; }, "shininess -1 must be finite and >= 0");
    refused_surface([](Surface& s) { s.ior = -1.5f; }, "ior -1.5 must be finite and > 0");
    refused_surface([](Surface& s) { s.ior = kNaN; }, "ior nan must be finite and > 0");
    refused_surface([](Surface& s) { s.ior = kInf; }, "ior inf must be finite and > 0");
    // Shading normals: 3 floats per vertex, finite.
    std::vector<float> normals(ball.positions.size(), 0.0f);
    MeshDesc short_normals = desc_of("bent", ball);
    const std::vector<float> fewer(normals.begin(), normals.end() - 3);
    short_normals.normals = fewer;
    expect_error([&] { engine.add_mesh(short_normals); }, kArgument, {"'bent'", "normals hold"});
    normals[3 * 4 + 2] = kNaN;
    MeshDesc nan_normals = desc_of("bent", ball);
    nan_normals.normals = normals;
    expect_error([&] { engine.add_mesh(nan_normals); }, kArgument, {"'bent'", "normal 4 is not finite"});
    MeshDesc unnamed = desc_of("", odd);
    expect_error([&] { engine.add_mesh(unnamed); }, kArgument, {"mesh 0"});
    // Nothing was added.
    EXPECT_EQ(engine.mesh_count(), 0u);
    EXPECT_EQ(engine.add_mesh(desc_of("fine", ball)).value, 0u);
}

TEST(ApiErrors, BadChangesAreRefusedAndChangeNothing) {
    Engine engine;
    Mirror m;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 1.0f);
    const MeshId still = m.add(engine, "still", ball, Motion::static_);
    const MeshId arm = m.add(engine, "arm", sphere({3.0f, 0.0f, 0.0f}, 1.0f), Motion::rigid);
    const MeshId cloth = m.add(engine, "cloth", sphere({-3.0f, 0.0f, 0.0f}, 1.0f), Motion::deformable);
    engine.update();

    expect_error([&] { engine.set_positions(still, ball.positions); }, kArgument, {"'still'", "static"});
    expect_error([&] { engine.set_positions(arm, ball.positions); }, kArgument, {"'arm'", "rigid"});
    expect_error([&] { engine.set_transform(still, Transform::translation({1.0f, 0.0f, 0.0f})); }, kArgument,
                 {"'still'", "static"});
    std::vector<float> fewer(ball.positions.begin(), ball.positions.end() - 3);
    expect_error([&] { engine.set_positions(cloth, fewer); }, kArgument, {"'cloth'", "expected"});
    std::vector<float> nan = sphere({-3.0f, 0.0f, 0.0f}, 1.0f).positions;
    nan[3 * 11 + 2] = kNaN;
    expect_error([&] { engine.set_positions(cloth, nan); }, kArgument, {"'cloth'", "vertex 11"});
    const std::vector<float> good = sphere({-3.0f, 0.0f, 0.0f}, 1.0f).positions;
    expect_error([&] { engine.set_positions(cloth, good, fewer); }, kArgument, {"'cloth'", "normals hold"});
    expect_error([&] { engine.set_positions(cloth, good, nan); }, kArgument, {"'cloth'", "normal 11 is not finite"});
    Transform inf = Transform::translation({0.0f, 0.0f, 0.0f});
    inf.m[5] = kInf;
    expect_error([&] { engine.set_transform(arm, inf); }, kArgument, {"'arm'", "not finite"});
    Transform projective;
    projective.m[15] = 2.0f;
    expect_error([&] { engine.set_transform(arm, projective); }, kArgument, {"'arm'", "affine"});
    expect_error([&] { engine.set_transform(cloth, projective); }, kArgument, {"'cloth'", "affine"});
    Surface bad_surface;
    bad_surface.diffuse.y = kNaN;
    expect_error([&] { engine.set_surface(arm, bad_surface); }, kArgument, {"'arm'"});
    Surface bad_ior;
    bad_ior.ior = 0.0f;
    expect_error([&] { engine.set_surface(arm, bad_ior); }, kArgument,
                 {"set_surface: mesh 'arm' (id 1): ior 0 must be finite and > 0"});
    Surface bad_reflectance;
    bad_reflectance.reflectance.z = -1.0f;
    expect_error([&] { engine.set_surface(cloth, bad_reflectance); }, kArgument,
                 {"set_surface: mesh 'cloth' (id 2): reflectance (0, 0, -1) must be finite and >= 0"});
    Surface bad_transmittance;
    bad_transmittance.transmittance.x = kNaN;
    expect_error([&] { engine.set_surface(still, bad_transmittance); }, kArgument,
                 {"'still'", "transmittance (nan, 0, 0) must be finite and >= 0"});

    // None of it reached the engine: the next update has nothing to do.
    const FrameStats s = engine.update();
    EXPECT_EQ(s.objects_skipped, 3u);
    EXPECT_EQ(s.objects_rebuilt + s.objects_refitted, 0u);
    const Reference ref(m);
    std::mt19937 rng(3);
    const std::vector<Ray> rays = incoherent_rays(rng, {0.0f, 0.0f, 0.0f}, 6.0f, 3.0f, 300);
    std::vector<RayHit> hits(rays.size());
    engine.intersect(rays, hits);
    EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts_for(*ref.tracer, rays), hits, "unchanged").mismatches, 0u);
}

TEST(ApiErrors, NonFiniteBorrowedPositionsFailTheUpdateWhichKeepsTheLastGoodTrees) {
    Engine engine;
    Mirror m;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 1.0f);
    std::vector<float> buffer = ball.positions;
    m.add(engine, "still", sphere({3.0f, 0.0f, 0.0f}, 1.0f), Motion::static_);
    const MeshId cloth = m.add(engine, "cloth", ball, Motion::deformable, {}, Ownership::borrow, buffer);
    engine.update();
    engine.update();
    std::mt19937 rng(8);
    const std::vector<Ray> rays = incoherent_rays(rng, {1.5f, 0.0f, 0.0f}, 6.0f, 2.5f, 400);
    std::vector<RayHit> before(rays.size()), after(rays.size());
    engine.intersect(rays, before);

    // A NaN written into the borrowed buffer and announced: set_positions cannot see it yet
    // (borrowed positions are read at the update), the update names mesh, step and vertex.
    buffer = scaled(ball, {0.0f, 0.0f, 0.0f}, 1.3f);
    buffer[3 * 42] = kNaN;
    engine.set_positions(cloth, buffer);
    expect_error([&] { engine.update(); }, kGeometry, {"'cloth'", "step 2", "vertex 42"});
    // The engine still answers with the previous geometry, bit for bit.
    engine.intersect(rays, after);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_TRUE(identical(before[i], after[i])) << "ray " << i;
    }
    std::vector<float> rgb(16 * 16 * 3);
    engine.render(View{{0.0f, 0.0f, 8.0f}}, ImageView{16, 16, rgb});
    // Still refused while the buffer holds the NaN; fixed and announced, the update works.
    expect_error([&] { engine.update(); }, kGeometry, {"'cloth'", "vertex 42"});
    buffer[3 * 42] = 0.0f;
    buffer = scaled(ball, {0.0f, 0.0f, 0.0f}, 1.3f);
    m.set_positions(engine, cloth, buffer);
    const FrameStats s = engine.update();
    EXPECT_EQ(s.objects_refitted + s.objects_rebuilt, 1u);
    const Reference ref(m);
    engine.intersect(rays, after);
    EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts_for(*ref.tracer, rays), after, "fixed").mismatches, 0u);
}

TEST(ApiErrors, ABorrowedStaticBufferSpoiledAfterHandOverFailsTheBuildAndBlocksQueries) {
    // A static mesh's borrowed buffer is read again only when the static group is rebuilt (here:
    // another static mesh joins it), half way through the update: the trees are then a mix of
    // two steps, so queries are refused until an update succeeds, which starts afresh.
    Engine engine;
    Mirror m;
    const MeshData ball = sphere({0.0f, 0.0f, 0.0f}, 1.0f);
    std::vector<float> buffer = ball.positions;
    m.add(engine, "ground", ball, Motion::static_, {}, Ownership::borrow, buffer);
    engine.update();
    std::mt19937 rng(9);
    const std::vector<Ray> rays = incoherent_rays(rng, {1.5f, 0.0f, 0.0f}, 6.0f, 2.5f, 400);
    std::vector<RayHit> hits(rays.size());
    engine.intersect(rays, hits);

    buffer[3 * 7 + 1] = kNaN;  // the caller breaks its promise
    m.add(engine, "rock", sphere({3.0f, 0.0f, 0.0f}, 1.0f), Motion::static_);
    expect_error([&] { engine.update(); }, kGeometry, {"'ground'", "step 1", "vertex 7"});
    expect_error([&] { engine.intersect(rays, hits); }, kState, {"failed"});
    std::vector<float> rgb(16 * 16 * 3);
    expect_error([&] { engine.render(View{{0.0f, 0.0f, 8.0f}}, ImageView{16, 16, rgb}); }, kState,
                 {"failed"});

    buffer = ball.positions;
    engine.update();
    const Reference ref(m);
    engine.intersect(rays, hits);
    EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts_for(*ref.tracer, rays), hits, "rebuilt")
                  .mismatches, 0u);
}

TEST(ApiErrors, TransformsThatOverflowTheGeometryFailTheUpdate) {
    // Finite vertices and a finite transform whose product is not finite in float: the update
    // names the mesh and step, and keeps the last good trees. Every class, rigid included
    // (traced in object space, but its world extent must exist).
    // Radius 1e9: large, but the float ray-triangle test's products (coordinates cubed) stay
    // finite, so the sphere is still hit correctly.
    const MeshData big = sphere({0.0f, 0.0f, 0.0f}, 1e9f);
    Transform blow_up;
    blow_up.m[0] = blow_up.m[5] = blow_up.m[10] = 1e30f;
    for (const Motion motion : {Motion::static_, Motion::rigid, Motion::deformable, Motion::automatic}) {
        SCOPED_TRACE(motion_name(motion));
        Engine engine;
        MeshDesc d = desc_of("big", big, motion);
        d.transform = blow_up;
        engine.add_mesh(d);
        expect_error([&] { engine.update(); }, kGeometry, {"'big'", "step 0"});
    }
    for (const Motion motion : {Motion::rigid, Motion::deformable, Motion::automatic}) {
        SCOPED_TRACE(motion_name(motion));
        Engine engine;
        const MeshId id = engine.add_mesh(desc_of("big", big, motion));
        engine.update();
        engine.set_transform(id, blow_up);
        expect_error([&] { engine.update(); }, kGeometry, {"'big'", "step 1"});
        const Ray ray{{1e8f, 2e8f, 1e10f}, {0.0f, 0.0f, -1.0f}};
        RayHit hit;
        engine.intersect(std::span<const Ray>(&ray, 1), std::span<RayHit>(&hit, 1));
        EXPECT_TRUE(hit.hit());
        EXPECT_NEAR(hit.t, 9.03e9f, 3e7f) << describe(hit);
        // A transform that fits works again.
        engine.set_transform(id, Transform::translation({1e9f, 0.0f, 0.0f}));
        engine.update();
    }
}

TEST(ApiErrors, BadRaysAreRefusedNamingTheRay) {
    Engine engine;
    engine.add_mesh(desc_of("ball", sphere({0.0f, 0.0f, 0.0f}, 1.0f)));
    engine.update();
    std::mt19937 rng(1);
    const std::vector<Ray> good = incoherent_rays(rng, {0.0f, 0.0f, 0.0f}, 4.0f, 1.0f, 600);
    std::vector<RayHit> hits(good.size());
    std::vector<std::uint8_t> occluded(good.size());
    const auto refused = [&](auto spoil, const char* problem) {
        for (const std::size_t index : {std::size_t(0), std::size_t(300), std::size_t(599)}) {
            std::vector<Ray> rays = good;
            spoil(rays[index]);
            const std::string ray = "ray " + std::to_string(index);
            expect_error([&] { engine.intersect(rays, hits); }, kArgument, {ray, problem});
            expect_error([&] { engine.occluded(rays, occluded); }, kArgument, {ray, problem});
        }
    };
    refused([](Ray& r) { r.origin.y = kNaN; }, "origin");
    refused([](Ray& r) { r.origin.z = kInf; }, "origin");
    refused([](Ray& r) { r.direction = {0.0f, 0.0f, 0.0f}; }, "zero");
    refused([](Ray& r) { r.direction.x = kNaN; }, "direction");
    refused([](Ray& r) { r.tmin = 2.0f, r.tmax = 1.0f; }, "tmax");
    refused([](Ray& r) { r.tmin = -1.0f; }, "tmin");
    refused([](Ray& r) { r.tmin = kNaN; }, "tmin");
    refused([](Ray& r) { r.tmax = kNaN; }, "tmax");
    refused([](Ray& r) { r.tmin = kInf; }, "tmin");

    std::vector<RayHit> short_hits(good.size() - 1);
    std::vector<std::uint8_t> long_flags(good.size() + 1);
    expect_error([&] { engine.intersect(good, short_hits); }, kArgument, {"600 rays", "599"});
    expect_error([&] { engine.occluded(good, long_flags); }, kArgument, {"600 rays", "601"});
    // Tiny, huge and denormal directions are fine.
    std::vector<Ray> odd = good;
    odd[0].direction = {1e-30f, 0.0f, 0.0f};
    odd[1].direction = {1e30f, -1e30f, 1e30f};
    odd[2].direction = {std::numeric_limits<float>::denorm_min(), 0.0f, 0.0f};
    odd[3].tmax = odd[3].tmin;
    engine.intersect(odd, hits);
    engine.occluded(odd, occluded);
}

TEST(ApiErrors, QueriesAndRendersNeedAFirstUpdate) {
    Engine engine;
    engine.add_mesh(desc_of("ball", sphere({0.0f, 0.0f, 0.0f}, 1.0f)));
    const std::vector<Ray> rays(3);
    std::vector<RayHit> hits(3);
    std::vector<std::uint8_t> occluded(3);
    std::vector<float> rgb(4 * 4 * 3);
    expect_error([&] { engine.intersect(rays, hits); }, kState, {"intersect", "update"});
    expect_error([&] { engine.occluded(rays, occluded); }, kState, {"occluded", "update"});
    expect_error([&] { engine.render(View{}, ImageView{4, 4, rgb}); }, kState, {"render", "update"});
    engine.update();
    engine.intersect(rays, hits);
}

TEST(ApiErrors, BadRenderCalls) {
    Engine engine;
    engine.add_mesh(desc_of("ball", sphere({0.0f, 0.0f, 0.0f}, 1.0f)));
    engine.update();
    std::vector<float> rgb(8 * 6 * 3), depth(8 * 6), wrong(8 * 6 - 1);
    std::vector<std::int32_t> mesh(8 * 6), wrong_mesh(8 * 6 + 1);
    const View view;
    engine.render(view, ImageView{8, 6, rgb, depth, mesh});
    expect_error([&] { engine.render(view, ImageView{8, 7, rgb}); }, kArgument, {"rgb"});
    expect_error([&] { engine.render(view, ImageView{0, 6, {}}); }, kArgument, {"0x6"});
    expect_error([&] { engine.render(view, ImageView{-8, -6, rgb}); }, kArgument, {"size"});
    expect_error([&] { engine.render(view, ImageView{8, 6, rgb, wrong}); }, kArgument, {"depth"});
    expect_error([&] { engine.render(view, ImageView{8, 6, rgb, {}, wrong_mesh}); }, kArgument, {"mesh"});
    View same = view;
    same.target = same.eye;
    expect_error([&] { engine.render(same, ImageView{8, 6, rgb}); }, kArgument, {"eye"});
    View parallel = view;
    parallel.up = {0.0f, 0.0f, 1.0f};
    expect_error([&] { engine.render(parallel, ImageView{8, 6, rgb}); }, kArgument, {"up"});
    for (const float fov : {0.0f, 180.0f, kNaN, -10.0f}) {
        View narrow = view;
        narrow.fov_y_deg = fov;
        expect_error([&] { engine.render(narrow, ImageView{8, 6, rgb}); }, kArgument, {"fov"});
    }
    View nan_eye = view;
    nan_eye.eye.x = kNaN;
    expect_error([&] { engine.render(nan_eye, ImageView{8, 6, rgb}); }, kArgument, {"render"});
    RenderSettings bad_light;
    bad_light.lights.push_back(Light{{0.0f, kInf, 0.0f}, 1.0f});
    expect_error([&] { engine.render(view, ImageView{8, 6, rgb}, bad_light); }, kArgument, {"light"});
    RenderSettings bad_ambient;
    bad_ambient.ambient = kNaN;
    expect_error([&] { engine.render(view, ImageView{8, 6, rgb}, bad_ambient); }, kArgument, {"ambient"});
    for (const int depth : {-1, 65}) {
        RenderSettings bad_depth;
        bad_depth.max_depth = depth;
        expect_error([&] { engine.render(view, ImageView{8, 6, rgb}, bad_depth); }, kArgument, {"max_depth"});
    }
    for (const float cutoff : {-0.1f, 1.5f, kNaN}) {
        RenderSettings bad_cutoff;
        bad_cutoff.cutoff = cutoff;
        expect_error([&] { engine.render(view, ImageView{8, 6, rgb}, bad_cutoff); }, kArgument, {"cutoff"});
    }
}

TEST(ApiErrors, HugeAndDegenerateTrianglesDoNotCrash) {
    Engine engine;
    // Zero-area triangles (a repeated vertex, three collinear vertices), a needle, a triangle
    // spanning +-1e30, one at 1e-30 scale, and a sphere to hit beside them.
    MeshData odd;
    odd.positions = {0, 0, 0,  1, 0, 0,  2, 0, 0,            // collinear
                     -1e30f, -1e30f, 0,  1e30f, -1e30f, 0,  0, 1e30f, 0,  // huge, in z = 0
                     0, 0, 1e-30f,  1e-30f, 0, 1e-30f,  0, 1e-30f, 1e-30f,  // tiny
                     0, 0, 1,  1e-7f, 0, 1,  5, 0, 1};  // needle
    odd.indices = {0, 1, 2,  0, 0, 1,  3, 4, 5,  6, 7, 8,  9, 10, 11,  1, 1, 1};
    Mirror m;
    m.add(engine, "odd", odd, Motion::static_);
    const MeshId dyn = m.add(engine, "odd moving", odd, Motion::deformable);
    const MeshId soup_id = m.add(engine, "ball", sphere({0.0f, 0.0f, 5.0f}, 1.0f), Motion::exploding);
    FrameStats s = engine.update();
    EXPECT_GE(s.degenerate_skipped, 2u);
    std::mt19937 rng(2);
    std::vector<Ray> rays = incoherent_rays(rng, {0.0f, 0.0f, 2.0f}, 10.0f, 4.0f, 600);
    const std::vector<Ray> packet = coherent_rays(rng, {0.5f, 0.5f, 20.0f}, {0.0f, 0.0f, 0.0f}, 0.2f, 256);
    rays.insert(rays.begin(), packet.begin(), packet.end());
    std::vector<RayHit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size());
    engine.intersect(rays, hits);
    engine.occluded(rays, occluded);
    // The huge triangle covers the plane z = 0 around the scene: rays down -z hit it.
    const Ray down{{0.3f, 0.2f, -0.5f}, {0.0f, 0.0f, 1.0f}};
    RayHit hit;
    engine.intersect(std::span<const Ray>(&down, 1), std::span<RayHit>(&hit, 1));
    EXPECT_TRUE(hit.hit());
    // Moving the odd geometry about, collapsing it to a point, and back.
    std::vector<float> collapsed(odd.positions.size(), 0.5f);
    m.set_positions(engine, dyn, collapsed);
    m.set_positions(engine, soup_id, std::vector<float>(sphere({0, 0, 5}, 1.0f).positions.size(), 1e30f));
    s = engine.update();
    engine.intersect(rays, hits);
    m.set_positions(engine, dyn, odd.positions);
    engine.update();
    engine.intersect(rays, hits);
    engine.occluded(rays, occluded);
    std::vector<float> rgb(32 * 32 * 3);
    engine.render(View{{0.0f, 0.0f, 30.0f}}, ImageView{32, 32, rgb});
    const Reference ref(m);
    EXPECT_EQ(check_closest(*ref.tracer, rays, verdicts_for(*ref.tracer, rays), hits, "odd").mismatches, 0u);
}

}  // namespace
}  // namespace dynrt::api_test
