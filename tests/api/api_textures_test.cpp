// Textures through the library API (Engine::add_texture, MeshDesc::texcoords,
// Surface::diffuse_texture) against dynrt::Renderer over the equivalent Scene (Scene::textures,
// Material::diffuse_map, Mesh::texcoords): the same frame bit for bit. Both shade through the
// same FramePipeline and TextureSet (the same filtered lookups over the same footprint),
// so equality is exact, for a texture from a file and one from bytes, with each wrap mode, and
// after a texture is added, changed or dropped between renders (exact pixel reuse on). Texels
// given as an array (TextureDesc::texels8, texels_float) are checked, copied into the scene's
// Texture, and render as a PNG file of the same texels does.

#include "api_test_world.h"

#include "api/scene_texture.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/scene/vertex_normals.h"

#include <gtest/gtest.h>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr int kWidth = 96, kHeight = 72;
constexpr auto kArgument = Error::Code::invalid_argument;

/// A 4x4 image of distinct colours (so that a wrong coordinate or wrap shows), written as a
/// PNG into the test's temporary folder, under a name of the running test's (ctest runs the
/// tests as parallel processes, which shared one file before); returns its path.
std::string write_texture(const std::string& name) {
    std::vector<float> rgb;
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            rgb.insert(rgb.end(), {0.15f + 0.25f * float(x), 0.9f - 0.2f * float(y), float((x + y) % 2)});
        }
    }
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string own = std::string(test->test_suite_name()) + "." + test->name() + "." + name;
    const std::string path = (std::filesystem::path(testing::TempDir()) / own).string();
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
            material.diffuse_map = TextureMap{q.surface.diffuse_texture.value, api_detail::scene_wrap(q.surface.wrap_s),
                                              api_detail::scene_wrap(q.surface.wrap_t)};
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
                 kArgument, {"'both'", "give one of a path, bytes or texels, not several (a path and bytes)"});
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

/// A 4x4 image of distinct 8-bit values (so that a texel out of place shows) with `channels`
/// channels, rows from the top-left. Alpha, when there is one, is opaque: OpenImageIO
/// multiplies a PNG's colours by its alpha, while texels are taken as they are (alpha unused).
std::vector<std::uint8_t> texel_image(int channels) {
    std::vector<std::uint8_t> texels;
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            const std::uint8_t grey = std::uint8_t(20 + 14 * (x + 4 * y));
            if (channels <= 2) texels.push_back(grey);
            if (channels >= 3) {
                texels.insert(texels.end(), {std::uint8_t(40 + 60 * x), std::uint8_t(230 - 50 * y),
                                             std::uint8_t((x + y) % 2 ? 250 : 10)});
            }
            if (channels % 2 == 0) texels.push_back(255);
        }
    }
    return texels;
}

/// `texels` (4x4, `channels` each) as a PNG file in the test's temporary folder; its path.
std::string write_png(const std::vector<std::uint8_t>& texels, int channels, const std::string& name) {
    const std::string path = (std::filesystem::path(testing::TempDir()) / name).string();
    EXPECT_NE(stbi_write_png(path.c_str(), 4, 4, channels, texels.data(), 4 * channels), 0) << path;
    return path;
}

TextureDesc texel_desc(std::span<const std::uint8_t> texels, int width, int height, int channels) {
    return TextureDesc{.name = "array", .texels8 = texels, .width = width, .height = height, .channels = channels};
}

/// TwoQuads' quads, both mapping the one texture `desc` adds (repeating; clamped and
/// mirrored), rendered by an Engine; `warnings`: what the render wrote on stderr.
std::vector<float> textured_frame(const TextureDesc& desc, std::string& warnings) {
    const TwoQuads world;
    Engine engine;
    EXPECT_EQ(engine.add_texture(desc), TextureId{0});
    for (Quad q : world.quads) {
        q.surface.diffuse_texture = TextureId{0};
        engine.add_mesh(desc_of(q));
    }
    engine.update();
    testing::internal::CaptureStderr();
    std::vector<float> rgb = engine_frame(engine);
    warnings = testing::internal::GetCapturedStderr();
    return rgb;
}

/// Pixels whose colours differ by more than `tolerance` in a channel (0: in any bit).
int differing_pixels(const std::vector<float>& a, const std::vector<float>& b, float tolerance = 0.0f) {
    int differing = 0;
    for (std::size_t p = 0; 3 * p < a.size(); ++p) {
        bool same = true;
        for (std::size_t c = 3 * p; c < 3 * p + 3; ++c) {
            same = same && (tolerance == 0.0f ? std::bit_cast<std::uint32_t>(a[c]) == std::bit_cast<std::uint32_t>(b[c])
                                              : std::fabs(a[c] - b[c]) <= tolerance);
        }
        differing += !same;
    }
    return differing;
}

TEST(ApiTextures, BadTexelArraysAreRefusedNamingTheTexture) {
    const TwoQuads world;
    const std::vector<std::uint8_t> rgb = texel_image(3);
    std::vector<float> floats(rgb.begin(), rgb.end());
    Engine engine;
    const auto refused = [&](TextureDesc desc, std::initializer_list<std::string> fragments) {
        expect_error([&] { engine.add_texture(desc); }, kArgument, fragments);
    };
    TextureDesc desc = texel_desc(rgb, 4, 4, 3);
    desc.path = world.path;
    refused(desc, {"add_texture 'array'", "give one of a path, bytes or texels, not several (a path and texels)"});
    desc.path = {};
    desc.encoded = world.bytes;
    refused(desc, {"'array'", "not several (bytes and texels)"});
    // Sizes alone count as texels given: a caller who forgot the values hears so.
    refused(TextureDesc{.path = world.path, .width = 4}, {"not several (a path and texels)"});
    refused(TextureDesc{.width = 4, .height = 4, .channels = 3},
            {"add_texture 'texture 0'", "no texels in texels8 or texels_float, 4 x 4 x 3 = 48 expected"});

    desc = texel_desc(rgb, 4, 4, 3);
    desc.texels_float = floats;
    refused(desc, {"'array'", "give texels8 or texels_float, not both"});
    refused(texel_desc(rgb, 0, 4, 3), {"'array'", "texels' size 0 x 4: each side must be in [1, 16384]"});
    refused(texel_desc(rgb, 4, -4, 3), {"texels' size 4 x -4"});
    refused(texel_desc(rgb, 16385, 1, 3), {"texels' size 16385 x 1"});
    refused(texel_desc(rgb, 48, 0, 1), {"texels' size 48 x 0"});
    refused(texel_desc(rgb, 4, 4, 0), {"'array'", "texels have 0 channels, not 1 to 4 (grey, grey and alpha, RGB, RGBA)"});
    refused(texel_desc(rgb, 4, 4, 5), {"texels have 5 channels"});
    refused(texel_desc(std::span(rgb).first(47), 4, 4, 3), {"'array'", "texels8 holds 47 values, 4 x 4 x 3 = 48 expected"});
    refused(texel_desc(rgb, 4, 4, 4), {"texels8 holds 48 values, 4 x 4 x 4 = 64 expected"});
    refused(texel_desc(rgb, 16384, 16384, 4), {"texels8 holds 48 values, 16384 x 16384 x 4 = 1073741824 expected"});
    refused(TextureDesc{.texels_float = std::span(floats).first(40), .width = 4, .height = 4, .channels = 3},
            {"'texture 0'", "texels_float holds 40 values, 4 x 4 x 3 = 48 expected"});

    // Float values must be finite and >= 0; the message finds the texel and channel.
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), -0.5f}) {
        std::vector<float> values(floats.size(), 0.5f);
        values[17] = bad;  // texel 5 (x 1, y 1), channel 2
        std::ostringstream value;
        value << bad;
        refused(TextureDesc{.name = "linear", .texels_float = values, .width = 4, .height = 4, .channels = 3, .srgb = false},
                {"add_texture 'linear'", "texels_float value 17 (texel x 1, y 1, channel 2) is " + value.str(),
                 "texels must be finite and >= 0"});
    }
    // Refused descriptions take no id; every channel count from 1 to 4 is taken.
    for (int channels = 1; channels <= 4; ++channels) {
        const std::vector<std::uint8_t> texels = texel_image(channels);
        EXPECT_EQ(engine.add_texture(texel_desc(texels, 4, 4, channels)), TextureId{std::uint32_t(channels - 1)});
    }
    EXPECT_EQ(engine.add_texture(TextureDesc{.texels_float = floats, .width = 16, .height = 1, .channels = 3}), TextureId{4});
}

TEST(ApiTextures, TexelArraysAreCopiedIntoTheScenesTexture) {
    // The scene's Texture (what the TextureSet reads) for an array of texels and for the same
    // texels as a PNG file and as that file's bytes.
    std::vector<std::uint8_t> rgb = texel_image(3);
    const std::string path = write_png(rgb, 3, "api_texels_copied.png");
    const std::vector<unsigned char> png = file_bytes(path);

    const Texture array = api_detail::texture_of(texel_desc(rgb, 4, 4, 3), 3);
    const Texture file = api_detail::texture_of(TextureDesc{.path = path}, 4);
    const Texture bytes = api_detail::texture_of(TextureDesc{.encoded = png}, 5);
    rgb.assign(rgb.size(), 0);  // the caller's buffer may change or go away: it was copied
    const std::vector<std::uint8_t> want = texel_image(3);
    EXPECT_EQ(array.name, "array");
    EXPECT_EQ(array.texels.width, 4);
    EXPECT_EQ(array.texels.height, 4);
    EXPECT_EQ(array.texels.channels, 3);
    EXPECT_FALSE(array.texels.floating);
    EXPECT_EQ(array.texels.bytes, std::vector<unsigned char>(want.begin(), want.end()));
    EXPECT_TRUE(array.path.empty() && array.encoded.empty() && array.mime_type.empty());
    EXPECT_TRUE(array.srgb);

    EXPECT_EQ(file.name, path);
    EXPECT_EQ(file.path, path);
    EXPECT_TRUE(file.texels.empty() && file.texels.bytes.empty() && file.encoded.empty());
    EXPECT_EQ(bytes.name, "texture 5");
    EXPECT_EQ(bytes.encoded, png);
    EXPECT_EQ(bytes.mime_type, "image/png");
    EXPECT_TRUE(bytes.texels.empty() && bytes.path.empty());

    // Float texels: their bytes, flagged floating, with the caller's srgb as given.
    const std::vector<float> linear = {0.0f, 0.25f, 1.5f, 0.125f, 3.0f, 0.0f};
    const Texture floating = api_detail::texture_of(
        TextureDesc{.texels_float = linear, .width = 1, .height = 3, .channels = 2, .srgb = false}, 0);
    EXPECT_EQ(floating.name, "texture 0");
    EXPECT_EQ(floating.texels.width, 1);
    EXPECT_EQ(floating.texels.height, 3);
    EXPECT_EQ(floating.texels.channels, 2);
    EXPECT_TRUE(floating.texels.floating);
    ASSERT_EQ(floating.texels.bytes.size(), linear.size() * sizeof(float));
    std::vector<float> back(linear.size());
    std::memcpy(back.data(), floating.texels.bytes.data(), floating.texels.bytes.size());
    EXPECT_EQ(back, linear);
    EXPECT_FALSE(floating.srgb);

    // The engine holds its copy (memory_bytes counts it).
    Engine engine;
    const std::size_t before = engine.memory_bytes();
    const std::vector<float> large(std::size_t(256 * 128 * 4), 0.5f);
    engine.add_texture(TextureDesc{.texels_float = large, .width = 256, .height = 128, .channels = 4, .srgb = false});
    EXPECT_GE(engine.memory_bytes(), before + large.size() * sizeof(float));
}

TEST(ApiTextures, ATexelArrayRendersAsThePngFileOfTheSameTexels) {
    // The end-to-end check of texels given directly: the TextureSet reads Texture::texels as it
    // reads the decoded file, for grey, grey and alpha, RGB and RGBA.
    std::string warnings;
    std::vector<float> untextured;
    {
        const TwoQuads world;
        Engine engine;
        for (Quad q : world.quads) {
            q.surface.diffuse_texture = {};
            engine.add_mesh(desc_of(q));
        }
        engine.update();
        untextured = engine_frame(engine);
    }
    for (int channels = 1; channels <= 4; ++channels) {
        SCOPED_TRACE(std::to_string(channels) + " channels");
        const std::vector<std::uint8_t> texels = texel_image(channels);
        const std::string path = write_png(texels, channels, "api_texels_" + std::to_string(channels) + ".png");
        const std::vector<float> want = textured_frame(TextureDesc{.path = path}, warnings);
        ASSERT_EQ(warnings, "");
        ASSERT_GT(differing_pixels(want, untextured), kWidth * kHeight / 10) << "the texture should show";

        const std::vector<float> got = textured_frame(texel_desc(texels, 4, 4, channels), warnings);
        EXPECT_EQ(warnings, "");
        EXPECT_EQ(differing_pixels(want, got), 0);

        // The same values as floats (k / 255, sRGB-encoded like the 8-bit ones): the same image
        // but for rounding (lookups may filter 8-bit texels in 8 bits).
        std::vector<float> floats;
        for (const std::uint8_t v : texels) floats.push_back(float(v) / 255.0f);
        const std::vector<float> got_float = textured_frame(
            TextureDesc{.name = "array", .texels_float = floats, .width = 4, .height = 4, .channels = channels}, warnings);
        EXPECT_EQ(warnings, "");
        EXPECT_EQ(differing_pixels(want, got_float, 2.0f / 255.0f), 0);
    }
}

}  // namespace
}  // namespace dynrt::api_test
