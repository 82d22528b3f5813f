// Textures through the library API (Engine::add_texture, MeshDesc::texcoords,
// Surface::diffuse_texture) against dynrt::Renderer over the equivalent Scene (Scene::textures,
// Material::diffuse_map, Mesh::texcoords): the same frame bit for bit. Both shade through the
// same FramePipeline and TextureSet (OpenImageIO's filtered lookups over the same footprint),
// so equality is exact, for a texture from a file and one from bytes, with each wrap mode, and
// after a texture is added, changed or dropped between renders (exact pixel reuse on).

#include "api_test_world.h"

#include "dynrt/engine/renderer.h"
#include "dynrt/scene/vertex_normals.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr int kWidth = 96, kHeight = 72;
constexpr auto kArgument = Error::Code::invalid_argument;

/// A 4x4 image of distinct colours (so that a wrong coordinate or wrap shows), written as a
/// PNG into the test's temporary folder; returns its path.
std::string write_texture(const std::string& name) {
    std::vector<float> rgb;
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            rgb.insert(rgb.end(), {0.15f + 0.25f * float(x), 0.9f - 0.2f * float(y), float((x + y) % 2)});
        }
    }
    const std::string path = (std::filesystem::path(testing::TempDir()) / name).string();
    save_image(path, 4, 4, rgb);
    return path;
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A textured quad: a sheet with texture coordinates running `tiles` times across it (so that
/// wrap modes matter), s to the right and t down.
struct Quad {
    std::string name;
    MeshData mesh;
    std::vector<float> texcoords;
    Transform transform;
    Surface surface;
};

Quad quad(const std::string& name, float tiles, Transform transform, Surface surface) {
    Quad q{name, sheet(0.0f, 0.0f, 0.0f, 2.0f, 4), {}, transform, surface};
    for (std::size_t v = 0; v < q.mesh.vertices(); ++v) {
        const float x = q.mesh.positions[3 * v], y = q.mesh.positions[3 * v + 1];
        q.texcoords.insert(q.texcoords.end(), {tiles * (x + 1.0f) / 2.0f - 0.3f, tiles * (1.0f - y) / 2.0f});
    }
    return q;
}

TextureWrap scene_wrap(Wrap wrap) {
    switch (wrap) {
        case Wrap::repeat: return TextureWrap::repeat;
        case Wrap::clamp: return TextureWrap::clamp;
        case Wrap::mirror: return TextureWrap::mirror;
    }
    return TextureWrap::repeat;
}

/// The quads as a scene the Renderer takes, with `textures` as Scene::textures (texture i of
/// the engine is scene texture i).
Scene scene_of(const std::vector<Quad>& quads, const std::vector<Texture>& textures) {
    Scene scene;
    scene.source = "api textures test";
    scene.textures = textures;
    for (std::size_t i = 0; i < quads.size(); ++i) {
        const Quad& q = quads[i];
        Object object;
        object.name = q.name;
        for (std::size_t v = 0; v < q.mesh.vertices(); ++v) {
            object.mesh.positions.emplace_back(q.mesh.positions[3 * v], q.mesh.positions[3 * v + 1],
                                               q.mesh.positions[3 * v + 2]);
            object.mesh.texcoords.emplace_back(q.texcoords[2 * v], q.texcoords[2 * v + 1]);
        }
        for (std::size_t k = 0; k < q.mesh.indices.size(); k += 3) {
            object.mesh.triangles.emplace_back(q.mesh.indices[k], q.mesh.indices[k + 1], q.mesh.indices[k + 2]);
        }
        object.mesh.normals = area_weighted_normals(object.mesh.positions, object.mesh.triangles);
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) object.transform[c][r] = q.transform.m[std::size_t(c * 4 + r)];
        }
        object.material = std::uint32_t(i);
        scene.objects.push_back(std::move(object));
        Material material;
        material.name = q.name;
        material.diffuse = {q.surface.diffuse.x, q.surface.diffuse.y, q.surface.diffuse.z};
        material.specular = {q.surface.specular.x, q.surface.specular.y, q.surface.specular.z};
        material.shininess = q.surface.shininess;
        if (q.surface.diffuse_texture.valid()) {
            material.diffuse_map = TextureMap{q.surface.diffuse_texture.value, scene_wrap(q.surface.wrap_s),
                                              scene_wrap(q.surface.wrap_t)};
        }
        scene.materials.push_back(material);
    }
    return scene;
}

MeshDesc desc_of(const Quad& q) {
    MeshDesc d;
    d.name = q.name;
    d.positions = q.mesh.positions;
    d.indices = q.mesh.indices;
    d.texcoords = q.texcoords;
    d.motion = Motion::static_;
    d.transform = q.transform;
    d.surface = q.surface;
    return d;
}

const Camera kCamera{{0.3f, 0.4f, 4.5f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};
const View kView{{0.3f, 0.4f, 4.5f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};

RenderedFrame renderer_frame(const std::vector<Quad>& quads, const std::vector<Texture>& textures) {
    RenderOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.lights = {PointLight{{2.0f, 3.0f, 5.0f}, 1.0f}};
    const Scene scene = scene_of(quads, textures);
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, kCamera, 0, frame);
    return frame;
}

std::vector<float> engine_frame(const Engine& engine, bool reuse_pixels = true) {
    RenderSettings settings;
    settings.reuse_pixels = reuse_pixels;
    settings.lights = {Light{{2.0f, 3.0f, 5.0f}, 1.0f}};
    std::vector<float> rgb(std::size_t(kWidth * kHeight * 3));
    engine.render(kView, ImageView{kWidth, kHeight, rgb}, settings);
    return rgb;
}

/// Pixels whose colour differs in any bit.
int wrong_pixels(const RenderedFrame& want, const std::vector<float>& got) {
    int wrong = 0;
    for (std::size_t p = 0; p < want.color.size(); ++p) {
        bool same = true;
        for (int c = 0; c < 3; ++c) {
            same = same && std::bit_cast<std::uint32_t>(want.color[p][c]) ==
                               std::bit_cast<std::uint32_t>(got[3 * p + std::size_t(c)]);
        }
        wrong += !same;
    }
    return wrong;
}

/// Two quads side by side: one textured from a file, repeating, one from bytes, clamped in s
/// and mirrored in t.
struct TwoQuads {
    std::string path = write_texture("api_textures_test.png");
    std::vector<unsigned char> bytes = file_bytes(path);
    std::vector<Texture> scene_textures = [&] {
        std::vector<Texture> textures(2);
        textures[0].name = textures[0].path = path;
        textures[1].name = "bytes";
        textures[1].encoded = bytes;
        textures[1].mime_type = "image/png";
        return textures;
    }();
    std::vector<Quad> quads{
        quad("file quad", 2.0f, Transform::rotation({0.0f, 1.0f, 0.0f}, 0.3f, {-1.1f, 0.0f, 0.0f}),
             Surface{{0.9f, 0.9f, 0.9f}, {0.1f, 0.1f, 0.1f}, 16.0f, {}, {}, 1.0f, TextureId{0}}),
        quad("bytes quad", 2.5f, Transform::rotation({1.0f, 0.0f, 0.0f}, -0.4f, {1.1f, 0.1f, -0.5f}),
             Surface{{1.0f, 0.8f, 0.8f}, {0.1f, 0.1f, 0.1f}, 16.0f, {}, {}, 1.0f, TextureId{1}, Wrap::clamp,
                     Wrap::mirror})};

    TwoQuads() { EXPECT_FALSE(bytes.empty()) << path; }

    void add_textures(Engine& engine) const {
        EXPECT_EQ(engine.add_texture(TextureDesc{.path = path}), TextureId{0});
        EXPECT_EQ(engine.add_texture(TextureDesc{.name = "bytes", .encoded = bytes}), TextureId{1});
    }
};

TEST(ApiTextures, TexturedQuadsAreTheRenderersFrameBitForBit) {
    const TwoQuads world;
    const RenderedFrame want = renderer_frame(world.quads, world.scene_textures);
    std::vector<Quad> plain = world.quads;
    for (Quad& q : plain) q.surface.diffuse_texture = {};
    // Else this test could not tell whether the textures were used.
    const RenderedFrame want_plain = renderer_frame(plain, {});
    ASSERT_NE(want.color, want_plain.color) << "the renderer ignores the textures";

    Engine engine;
    world.add_textures(engine);
    for (const Quad& q : world.quads) engine.add_mesh(desc_of(q));
    engine.update();
    const std::vector<float> got = engine_frame(engine);
    EXPECT_EQ(wrong_pixels(want, got), 0);
    EXPECT_GT(wrong_pixels(want_plain, got), kWidth * kHeight / 10) << "the quads should fill the view";
}

TEST(ApiTextures, TexturesAddedChangedAndDroppedLaterShowAtTheNextRender) {
    // The engine's scene is one object for its life, so the textures opened at its first
    // textured render must be opened again when a surface maps another one; and exact reuse
    // must trace again the pixels of a surface whose texture alone changed.
    TwoQuads world;
    std::vector<Quad> quads = world.quads;
    for (Quad& q : quads) q.surface.diffuse_texture = {};
    Engine engine;
    for (const Quad& q : quads) engine.add_mesh(desc_of(q));
    engine.update();
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, {}), engine_frame(engine)), 0);

    // A texture added after the first render, mapped by one quad, then by the other too.
    world.add_textures(engine);
    quads[0].surface = world.quads[0].surface;
    engine.set_surface(MeshId{0}, quads[0].surface);
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, world.scene_textures), engine_frame(engine)), 0);
    quads[1].surface = world.quads[1].surface;
    engine.set_surface(MeshId{1}, quads[1].surface);
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, world.scene_textures), engine_frame(engine)), 0);

    // Another texture, another wrap mode, then none: each render is the Renderer's.
    quads[0].surface.diffuse_texture = TextureId{1};
    engine.set_surface(MeshId{0}, quads[0].surface);
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, world.scene_textures), engine_frame(engine)), 0);
    quads[0].surface.wrap_s = Wrap::mirror;
    engine.set_surface(MeshId{0}, quads[0].surface);
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, world.scene_textures), engine_frame(engine)), 0);
    quads[1].surface.diffuse_texture = {};
    engine.set_surface(MeshId{1}, quads[1].surface);
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, world.scene_textures), engine_frame(engine)), 0);

    // A mesh added later with a texture, in the place of a removed one.
    engine.remove_mesh(MeshId{0});
    engine.update();
    const MeshId again = engine.add_mesh(desc_of(world.quads[0]));
    engine.update();
    EXPECT_EQ(again, MeshId{2});
    quads[0] = world.quads[0];
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, world.scene_textures), engine_frame(engine)), 0);
}

TEST(ApiTextures, ARenderBetweenRemoveMeshAndUpdateShowsTheRemovedMeshTextured) {
    // Queries see the last update's meshes until the next update (remove_mesh), so a render in
    // between shades the removed quad's hits: with its texture, as before the removal.
    const TwoQuads world;
    Engine engine;
    world.add_textures(engine);
    for (const Quad& q : world.quads) engine.add_mesh(desc_of(q));
    engine.update();
    const std::vector<float> before = engine_frame(engine);
    engine.remove_mesh(MeshId{0});
    EXPECT_EQ(engine_frame(engine), before);
    EXPECT_EQ(engine_frame(engine, false), before);  // traced in full
    engine.update();
    EXPECT_EQ(wrong_pixels(renderer_frame({world.quads[1]}, world.scene_textures), engine_frame(engine)), 0);
}

TEST(ApiTextures, ARelativePathIsTheWorkingFoldersAtAddTexture) {
    // The file is read at the first render that shows it; the path means what it meant when
    // it was given, whatever the working folder is by then.
    const TwoQuads world;
    const std::filesystem::path before = std::filesystem::current_path();
    std::filesystem::current_path(std::filesystem::path(world.path).parent_path());
    Engine engine;
    const TextureId id = engine.add_texture(TextureDesc{.path = std::filesystem::path(world.path).filename().string()});
    std::filesystem::current_path(before);
    engine.add_texture(TextureDesc{.encoded = world.bytes});
    for (const Quad& q : world.quads) engine.add_mesh(desc_of(q));
    engine.update();
    EXPECT_EQ(id, TextureId{0});
    EXPECT_EQ(wrong_pixels(renderer_frame(world.quads, world.scene_textures), engine_frame(engine)), 0);
}

TEST(ApiTextures, AnUnreadableFileWarnsAtRenderAndShowsTheDiffuseColour) {
    // As `dynrt render` does (TextureSet): no error, one warning naming the file, and the
    // surface's diffuse colour alone.
    const TwoQuads world;
    std::vector<Quad> quads = world.quads;
    const std::string missing = (std::filesystem::path(testing::TempDir()) / "no_such_texture.png").string();
    Engine engine;
    EXPECT_EQ(engine.add_texture(TextureDesc{.path = missing}), TextureId{0});
    quads.resize(1);
    engine.add_mesh(desc_of(quads[0]));
    engine.update();
    testing::internal::CaptureStderr();
    const std::vector<float> got = engine_frame(engine);
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("no_such_texture.png"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("'file quad'"), std::string::npos) << warnings;
    quads[0].surface.diffuse_texture = {};
    EXPECT_EQ(wrong_pixels(renderer_frame(quads, {}), got), 0);
}

TEST(ApiTextures, BadTexturesAndTexcoordsAreRefusedNamingThem) {
    const TwoQuads world;
    Engine engine;
    expect_error([&] { engine.add_texture(TextureDesc{.name = "blank"}); }, kArgument,
                 {"add_texture 'blank'", "no path and no bytes"});
    expect_error([&] { engine.add_texture(TextureDesc{}); }, kArgument, {"add_texture 'texture 0'"});
    expect_error([&] { engine.add_texture(TextureDesc{.name = "both", .path = world.path, .encoded = world.bytes}); },
                 kArgument, {"'both'", "a path or bytes, not both"});
    // Refused descriptions take no id.
    EXPECT_EQ(engine.add_texture(TextureDesc{.encoded = world.bytes}), TextureId{0});

    Quad q = world.quads[1];  // maps texture 1, not added
    expect_error([&] { engine.add_mesh(desc_of(q)); }, kArgument, {"'bytes quad'", "no texture with id 1"});
    q.surface.diffuse_texture = TextureId{0};
    MeshDesc bare = desc_of(q);
    bare.texcoords = {};
    expect_error([&] { engine.add_mesh(bare); }, kArgument, {"'bytes quad'", "maps texture 0", "no texcoords"});
    std::vector<float> short_uv = q.texcoords;
    short_uv.pop_back();
    MeshDesc short_desc = desc_of(q);
    short_desc.texcoords = short_uv;
    expect_error([&] { engine.add_mesh(short_desc); }, kArgument,
                 {"'bytes quad'", "texcoords hold " + std::to_string(short_uv.size()) + " floats",
                  std::to_string(2 * q.mesh.vertices()) + " expected"});
    std::vector<float> nan_uv = q.texcoords;
    nan_uv[7] = std::numeric_limits<float>::quiet_NaN();
    MeshDesc nan_desc = desc_of(q);
    nan_desc.texcoords = nan_uv;
    expect_error([&] { engine.add_mesh(nan_desc); }, kArgument, {"'bytes quad'", "texcoord 3 is not finite"});
    EXPECT_EQ(engine.mesh_count(), 0u);

    const MeshId textured = engine.add_mesh(desc_of(q));
    bare.surface.diffuse_texture = {};
    const MeshId untextured = engine.add_mesh(bare);
    Surface s = q.surface;
    s.diffuse_texture = TextureId{5};
    expect_error([&] { engine.set_surface(textured, s); }, kArgument, {"set_surface", "'bytes quad'", "no texture with id 5"});
    s.diffuse_texture = TextureId{0};
    expect_error([&] { engine.set_surface(untextured, s); }, kArgument, {"set_surface", "maps texture 0", "no texcoords"});
}

}  // namespace
}  // namespace dynrt::api_test
