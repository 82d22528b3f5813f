// Textures (docs/rendering.md "Textures"): TextureSet's lookups (texel colours, orientation, wrap modes,
// footprints, sRGB decoding, files and embedded images, and a clear warning instead of an error
// for an unreadable file); textured quads rendered by dynrt::Renderer against the exact
// reference and against the texels worked out by hand, from a hand-made scene and from glTF
// files with baseColorTexture written here; and BART's textured kitchen, when
// ../shared/scenes/bart is there.

#include "gltf_test_file.h"

#include "dynrt/reference/image_comparison.h"
#include "dynrt/reference/reference_renderer.h"
#include "dynrt/reference/reference_tracer.h"

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/engine/texture_set.h"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

namespace dynrt {
namespace {

namespace fs = std::filesystem;

/// The 2x2 test image, sRGB bytes, top row first: red, green / blue, grey 128.
const std::vector<unsigned char> kTexels = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};

float srgb_to_linear(unsigned char byte) {
    const double c = byte / 255.0;
    return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

glm::vec3 texel(int x, int y) {
    const std::size_t i = std::size_t(3 * (2 * y + x));
    return {srgb_to_linear(kTexels[i]), srgb_to_linear(kTexels[i + 1]), srgb_to_linear(kTexels[i + 2])};
}

/// Writes `pixels` (8-bit RGB, top row first) to `path` through OpenImageIO.
void write_image(const fs::path& path, int width, int height, const std::vector<unsigned char>& pixels) {
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out) << OIIO::geterror();
    const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

fs::path temp_path(const std::string& name) {
    return fs::path(::testing::TempDir()) / ("dynrt_tex_" + std::to_string(::getpid()) + "_" + name);
}

std::vector<unsigned char> file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

::testing::AssertionResult near_per_channel(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    const glm::vec3 d = glm::abs(a - b);
    if (std::max({d.x, d.y, d.z}) <= tolerance) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", "
                                         << b.y << ", " << b.z << ")";
}

/// A scene of one material mapping texture 0 (a file or embedded bytes) with `wrap`.
Scene mapped(Texture texture, TextureWrap wrap = TextureWrap::repeat) {
    Scene scene;
    scene.source = "texture test";
    Material m;
    m.name = "checker";
    m.diffuse_map = TextureMap{0, wrap, wrap};
    scene.materials.push_back(m);
    scene.textures.push_back(std::move(texture));
    return scene;
}

Texture file_texture(const fs::path& path) {
    Texture t;
    t.name = t.path = path.string();
    return t;
}

// ---- TextureSet ------------------------------------------------------------------------------

TEST(TextureSet, TexelCentresGiveTheirLinearColoursTopRowFirst) {
    const fs::path png = temp_path("checker.png");
    write_image(png, 2, 2, kTexels);
    const TextureSet set(mapped(file_texture(png)));
    ASSERT_TRUE(set.maps(0)) << (set.warnings().empty() ? "" : set.warnings()[0]);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            const glm::vec2 st(0.25f + 0.5f * float(x), 0.25f + 0.5f * float(y));
            EXPECT_TRUE(near_per_channel(set.diffuse(0, st, 0.0f), texel(x, y), 1e-4f)) << x << "," << y;
        }
    }
    // Between texel centres, bilinear: halfway between red and green.
    EXPECT_TRUE(near_per_channel(set.diffuse(0, {0.5f, 0.25f}, 0.0f),
                     glm::vec3(srgb_to_linear(128), srgb_to_linear(128), 0.0f), 2e-3f))
        << "sRGB texels are filtered as stored, then decoded";
    // A footprint as wide as the image reads its coarsest level: the mean of the four texels
    // (of their encoded values, decoded).
    const glm::vec3 coarse = set.diffuse(0, {0.5f, 0.5f}, 1.0f);
    const float mean_red = srgb_to_linear(static_cast<unsigned char>((255 + 128 + 2) / 4));
    EXPECT_NEAR(coarse.x, mean_red, 0.03f);
    EXPECT_NEAR(coarse.y, mean_red, 0.03f);
    EXPECT_NEAR(coarse.z, mean_red, 0.03f);
}

TEST(TextureSet, WrapModesFoldCoordinatesOutsideTheImage) {
    const fs::path png = temp_path("wrap.png");
    write_image(png, 2, 2, kTexels);
    const glm::vec2 outside(1.25f, 0.25f);  // a quarter past the right edge, top row
    EXPECT_TRUE(near_per_channel(TextureSet(mapped(file_texture(png), TextureWrap::repeat)).diffuse(0, outside, 0.0f),
                     texel(0, 0), 1e-4f));
    EXPECT_TRUE(near_per_channel(TextureSet(mapped(file_texture(png), TextureWrap::clamp)).diffuse(0, outside, 0.0f),
                     texel(1, 0), 1e-4f));
    EXPECT_TRUE(near_per_channel(TextureSet(mapped(file_texture(png), TextureWrap::mirror)).diffuse(0, outside, 0.0f),
                     texel(1, 0), 1e-4f));
    EXPECT_TRUE(near_per_channel(TextureSet(mapped(file_texture(png), TextureWrap::mirror)).diffuse(0, {1.75f, 0.25f}, 0.0f),
                     texel(0, 0), 1e-4f));
}

TEST(TextureSet, EmbeddedImagesReadFromMemory) {
    const fs::path png = temp_path("embedded.png");
    write_image(png, 2, 2, kTexels);
    Texture embedded;
    embedded.name = "memory image";
    embedded.encoded = file_bytes(png);
    embedded.mime_type = "image/png";
    const TextureSet set(mapped(embedded));
    ASSERT_TRUE(set.maps(0)) << (set.warnings().empty() ? "" : set.warnings()[0]);
    EXPECT_TRUE(near_per_channel(set.diffuse(0, {0.25f, 0.75f}, 0.0f), texel(0, 1), 1e-4f));
}

TEST(TextureSet, UnreadableTexturesWarnNamingFileAndMaterialAndMapNothing) {
    const fs::path missing = temp_path("no_such_texture.png");
    const TextureSet set(mapped(file_texture(missing)), false);
    EXPECT_FALSE(set.maps(0));
    ASSERT_EQ(set.warnings().size(), 1u);
    const std::string& warning = set.warnings()[0];
    EXPECT_NE(warning.find(missing.string()), std::string::npos) << warning;
    EXPECT_NE(warning.find("material 'checker'"), std::string::npos) << warning;
    // Garbage bytes are no better, and no worse.
    Texture garbage;
    garbage.name = "garbage";
    garbage.encoded = {1, 2, 3, 4, 5};
    garbage.mime_type = "image/png";
    const TextureSet broken(mapped(garbage), false);
    EXPECT_FALSE(broken.maps(0));
    EXPECT_EQ(broken.warnings().size(), 1u);
    // A file cut short: its header reads, its texels do not. Textures are decoded whole when
    // the set is made, so it is reported then, not read as white at the first lookup. (A PPM,
    // BART's format: OpenImageIO's PNG reader leaves libpng's error by longjmp, past a string
    // it never frees, which the sanitizer job's leak check would report.)
    const fs::path whole = temp_path("whole.ppm"), cut = temp_path("cut.ppm");
    std::vector<unsigned char> texels(64 * 64 * 3);
    for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<unsigned char>(i * 7919 % 251);
    write_image(whole, 64, 64, texels);
    const std::vector<unsigned char> bytes = file_bytes(whole);
    std::ofstream(cut, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size() / 2));
    const TextureSet truncated(mapped(file_texture(cut)), false);
    EXPECT_FALSE(truncated.maps(0));
    ASSERT_EQ(truncated.warnings().size(), 1u);
    EXPECT_NE(truncated.warnings()[0].find(cut.string()), std::string::npos) << truncated.warnings()[0];
    EXPECT_TRUE(TextureSet(mapped(file_texture(whole)), false).maps(0));
    // Texels given as an array past the largest side dynrt holds: the same warning.
    Texture wide;
    wide.name = "wide";
    wide.texels = TexelArray{.width = kMaxTextureSide + 1, .height = 1, .channels = 1, .floating = false,
                             .bytes = std::vector<unsigned char>(std::size_t(kMaxTextureSide) + 1, 9)};
    const TextureSet too_wide(mapped(wide), false);
    EXPECT_FALSE(too_wide.maps(0));
    ASSERT_EQ(too_wide.warnings().size(), 1u);
    EXPECT_NE(too_wide.warnings()[0].find("16384 texels a side"), std::string::npos) << too_wide.warnings()[0];
    fs::remove(whole);
    fs::remove(cut);
}

// ---- Rendering -------------------------------------------------------------------------------

/// A unit quad z = 0 facing +z with texture coordinates (0, 0) at its top-left corner
/// (-1, 1) and (1, 1) at its bottom-right (1, -1), lit head-on, seen head-on filling the image.
struct QuadShot {
    Scene scene;
    Camera camera;
    RenderOptions options;

    explicit QuadShot(Scene s) : scene(std::move(s)) {
        camera.eye = glm::vec3(0.0f, 0.0f, 2.0f);
        camera.target = glm::vec3(0.0f);
        camera.fov_y_deg = 2.0f * float(glm::degrees(std::atan(0.5)));  // the quad fills the view
        // 34 pixels: pixel 8's centre is s = 8.5 / 34 = 0.25, the first texel's centre.
        options.width = options.height = 34;
        options.lights = {PointLight{{0.0f, 0.0f, 50.0f}, 1.0f}};
        options.ambient = 0.1f;
    }
    RenderedFrame render(Tracer tracer = Tracer::packet) const {
        RenderOptions o = options;
        o.tracer = tracer;
        Renderer renderer(o);
        RenderedFrame frame;
        renderer.render(scene, camera, 0, frame);
        return frame;
    }
    reference::ImageComparison compare(const RenderedFrame& frame) const {
        anim::PosedScene posed;
        anim::pose_scene(scene, 0, posed);
        const reference::ReferenceTracer tracer(scene, posed);
        const reference::ReferenceFrame ref = reference::render_reference(
            scene, tracer, camera, options.width, options.height, reference::shading_from(scene, options));
        return reference::compare_images(frame, ref);
    }
};

Scene quad_scene(const fs::path& png, glm::vec3 diffuse) {
    Scene scene = mapped(file_texture(png));
    scene.materials[0].diffuse = diffuse;
    scene.materials[0].specular = glm::vec3(0.0f);
    Object quad;
    quad.name = "quad";
    quad.mesh.positions = {{-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}};
    quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    quad.mesh.texcoords = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    scene.objects.push_back(std::move(quad));
    return scene;
}

/// Every quadrant of the frame shows its texel: the pixel over the texel's centre is
/// kd * texel * (ambient + n.l), n.l being 1 to 2e-4 for a light far along the view.
void expect_quadrants(const RenderedFrame& f, glm::vec3 kd, float ambient) {
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            const int px = 8 + 17 * x, py = 8 + 17 * y;
            const glm::vec3 want = kd * texel(x, y) * (ambient + 1.0f);
            EXPECT_TRUE(near_per_channel(f.color[std::size_t(py * f.width + px)], want, 2e-3f)) << "quadrant " << x << "," << y;
        }
    }
}

TEST(TexturedRender, AQuadShowsItsTexelsAsTheReferenceDoes) {
    const fs::path png = temp_path("quad.png");
    write_image(png, 2, 2, kTexels);
    const QuadShot shot(quad_scene(png, glm::vec3(1.0f, 0.5f, 1.0f)));
    const RenderedFrame frame = shot.render();
    expect_quadrants(frame, glm::vec3(1.0f, 0.5f, 1.0f), shot.options.ambient);
    const reference::ImageComparison cmp = shot.compare(frame);
    EXPECT_TRUE(cmp.passed()) << cmp.summary();
    EXPECT_GT(cmp.color_checked, 34 * 34 * 3 / 4);
    // The single-ray tracer shades through the same lookups: the same bits.
    const RenderedFrame single = shot.render(Tracer::single);
    EXPECT_EQ(0, std::memcmp(single.color.data(), frame.color.data(), frame.color.size() * sizeof(glm::vec3)));
}

// An emission map (glTF's emissiveTexture): the emission is the factor times the map's colour,
// the diffuse colour left alone; as the reference has it, for both tracers, the same bits.
TEST(TexturedRender, AnEmissionMapGlowsWithItsTexels) {
    const fs::path png = temp_path("glow.png");
    write_image(png, 2, 2, kTexels);
    Scene scene = quad_scene(png, glm::vec3(0.2f));
    Material& m = scene.materials[0];
    m.emission_map = m.diffuse_map;
    m.diffuse_map.reset();
    m.emission = glm::vec3(0.5f, 1.0f, 0.25f);
    const QuadShot shot(scene);
    const RenderedFrame frame = shot.render();
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            const int px = 8 + 17 * x, py = 8 + 17 * y;
            const glm::vec3 want = glm::vec3(0.2f) * (shot.options.ambient + 1.0f) + m.emission * texel(x, y);
            EXPECT_TRUE(near_per_channel(frame.color[std::size_t(py * frame.width + px)], want, 2e-3f))
                << "quadrant " << x << "," << y;
        }
    }
    const reference::ImageComparison cmp = shot.compare(frame);
    EXPECT_TRUE(cmp.passed()) << cmp.summary();
    EXPECT_GT(cmp.color_checked, 34 * 34 * 3 / 4);
    const RenderedFrame single = shot.render(Tracer::single);
    EXPECT_EQ(0, std::memcmp(single.color.data(), frame.color.data(), frame.color.size() * sizeof(glm::vec3)));
}

TEST(TexturedRender, AMissingTextureFallsBackToTheMaterialColour) {
    const QuadShot missing(quad_scene(temp_path("absent.png"), glm::vec3(0.3f, 0.6f, 0.9f)));
    Scene plain = missing.scene;
    plain.materials[0].diffuse_map.reset();
    const QuadShot without(plain);
    const RenderedFrame a = missing.render(), b = without.render();
    EXPECT_EQ(0, std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(glm::vec3)));
}

// Benchmarks time a full build per run without reading the textures again
// (Renderer::forget_trees): a texture file removed after the first frame still shows, and
// the trees are built afresh; reset() forgets the textures too, and the file's absence shows.
TEST(TexturedRender, ForgettingTheTreesKeepsTheTexturesRead) {
    const fs::path png = temp_path("kept.png");
    write_image(png, 2, 2, kTexels);
    const QuadShot shot(quad_scene(png, glm::vec3(1.0f)));
    Renderer renderer(shot.options);
    RenderedFrame first, again;
    renderer.render(shot.scene, shot.camera, 0, first);
    fs::remove(png);
    renderer.forget_trees();
    renderer.render(shot.scene, shot.camera, 0, again);
    EXPECT_GT(again.stats.objects_rebuilt, 0u);
    EXPECT_EQ(0, std::memcmp(first.color.data(), again.color.data(), first.color.size() * sizeof(glm::vec3)));
    renderer.reset();
    renderer.render(shot.scene, shot.camera, 0, again);
    EXPECT_NE(0, std::memcmp(first.color.data(), again.color.data(), first.color.size() * sizeof(glm::vec3)));
}

/// A glTF quad (two non-indexed triangles) with TEXCOORD_0 and a material whose base colour
/// factor multiplies `image` (a uri, or a data: URI when `embed`), clamped.
fs::path gltf_quad(const fs::path& png, bool embed, const std::string& name) {
    test::GltfTestFile file;
    const std::vector<float> positions = {-1, 1, 0, -1, -1, 0, 1, -1, 0, -1, 1, 0, 1, -1, 0, 1, 1, 0};
    const std::vector<float> st = {0, 0, 0, 1, 1, 1, 0, 0, 1, 1, 1, 0};
    const int mesh = file.add_mesh(positions, {{"TEXCOORD_0", file.add_floats(st, "VEC2")}});
    file.doc()["meshes"][mesh]["primitives"][0]["material"] = 0;
    file.add_node({{"name", "quad"}, {"mesh", mesh}});
    nlohmann::json image;
    if (embed) {
        image = {{"uri", "data:image/png;base64," + test::GltfTestFile::base64(file_bytes(png))}};
    } else {
        image = {{"uri", png.filename().string()}};
    }
    file.doc()["images"] = nlohmann::json::array({image});
    file.doc()["samplers"] = nlohmann::json::array({{{"wrapS", 33071}, {"wrapT", 33071}}});
    file.doc()["textures"] = nlohmann::json::array({{{"source", 0}, {"sampler", 0}}});
    file.doc()["materials"] = nlohmann::json::array(
        {{{"name", "tinted"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.5, 1.0, 1.0, 1.0}}, {"baseColorTexture", {{"index", 0}}},
            {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}}});
    // Next to the image, so that its relative uri resolves.
    const fs::path written = file.write(name);
    const fs::path beside = png.parent_path() / written.filename();
    if (beside != written) fs::copy_file(written, beside, fs::copy_options::overwrite_existing);
    return beside;
}

TEST(TexturedRender, GltfBaseColorTextureTimesItsFactor) {
    const fs::path png = temp_path("gltf_base.png");
    write_image(png, 2, 2, kTexels);
    for (const bool embed : {false, true}) {
        SCOPED_TRACE(embed ? "data: URI" : "file");
        const Scene scene = load_gltf(gltf_quad(png, embed, embed ? "embedded.gltf" : "file.gltf"));
        ASSERT_EQ(scene.objects.size(), 1u);
        ASSERT_EQ(scene.objects[0].mesh.texcoords.size(), 6u);
        const Material& m = scene.materials[scene.objects[0].material];
        ASSERT_TRUE(m.diffuse_map.has_value());
        EXPECT_EQ(m.diffuse_map->wrap_s, TextureWrap::clamp);
        EXPECT_EQ(m.diffuse_map->wrap_t, TextureWrap::clamp);
        for (const std::string& line : scene.ignored) EXPECT_EQ(line.find("texture"), std::string::npos) << line;
        const QuadShot shot(scene);
        const RenderedFrame frame = shot.render();
        // glTF's material has a grey highlight (specular 0.1): in the red, green and blue
        // quadrants, the channels the texel lacks show it alone, so the difference is kd times
        // the texel's channel, with red halved by the base colour factor.
        const float lit = shot.options.ambient + 1.0f;
        const auto at = [&](int x, int y) { return frame.color[std::size_t((8 + 17 * y) * 34 + 8 + 17 * x)]; };
        EXPECT_NEAR(at(0, 0).x - at(0, 0).y, 0.5f * lit, 2e-3f) << "red, halved";
        EXPECT_NEAR(at(1, 0).y - at(1, 0).x, lit, 2e-3f) << "green";
        EXPECT_NEAR(at(0, 1).z - at(0, 1).y, lit, 2e-3f) << "blue";
        EXPECT_GT(at(0, 0).y, 0.0f) << "the highlight";
        const reference::ImageComparison cmp = shot.compare(frame);
        EXPECT_TRUE(cmp.passed()) << cmp.summary();
    }
}

// A binary glTF whose base colour is a JPEG in a bufferView (CesiumMan): read from memory, and
// its frame agrees with the reference, textures included.
TEST(TexturedRender, CesiumManEmbeddedJpegMatchesTheReference) {
    const fs::path file = fs::path(DYNRT_SHARED_SCENES_DIR) / "cesiumman" / "CesiumMan.glb";
    if (!fs::exists(file)) GTEST_SKIP() << file << " not found";
    const Scene scene = load_gltf(file);
    ASSERT_FALSE(scene.textures.empty());
    EXPECT_FALSE(scene.textures[0].encoded.empty()) << "the image is in the binary buffer";
    const TextureSet set(scene, false);
    EXPECT_TRUE(set.warnings().empty()) << set.warnings()[0];
    std::uint32_t textured = 0;
    while (textured < scene.materials.size() && !set.maps(textured)) ++textured;
    ASSERT_LT(textured, scene.materials.size());
    glm::vec3 lo(1.0f), hi(0.0f);
    for (int i = 0; i < 64; ++i) {
        const glm::vec3 c = set.diffuse(textured, {float(i % 8) / 8.0f + 0.06f, float(i / 8) / 8.0f + 0.06f}, 0.0f);
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    EXPECT_GT(hi.x - lo.x, 0.1f) << "an image, not a flat colour";

    RenderOptions options;
    options.width = options.height = 24;
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    anim::PosedScene posed;
    anim::pose_scene(scene, 0, posed);
    const reference::ReferenceTracer tracer(scene, posed);
    const reference::ReferenceFrame ref = reference::render_reference(
        scene, tracer, camera, options.width, options.height, reference::shading_from(scene, options));
    const reference::ImageComparison cmp = reference::compare_images(frame, ref);
    EXPECT_TRUE(cmp.passed()) << cmp.summary();
    EXPECT_GT(cmp.color_checked, 24 * 24 / 8);
}

// ---- BART ------------------------------------------------------------------------------------

TEST(TexturedBart, KitchenMapsItsTexturesAndWarnsOfMissingFiles) {
    const fs::path kitchen = fs::path(DYNRT_SHARED_SCENES_DIR) / "bart" / "kitchen" / "kitchen.aff";
    if (!fs::exists(kitchen)) GTEST_SKIP() << kitchen << " not found";
    const Scene scene = load_aff(kitchen);
    std::size_t textured_objects = 0;
    for (const Object& object : scene.objects) {
        const Material& m = scene.materials[object.material];
        if (!m.diffuse_map) continue;
        ++textured_objects;
        EXPECT_EQ(object.mesh.texcoords.size(), object.mesh.positions.size()) << object.name;
    }
    EXPECT_GT(textured_objects, 10u);
    EXPECT_FALSE(scene.textures.empty());
    for (const std::string& line : scene.ignored) EXPECT_EQ(line.find("textures of"), std::string::npos) << line;
    // Each texture file is read next to the .aff naming it; those not in the folder (BART's
    // images are not in ../shared) are reported, naming file and material, and shade plain.
    const TextureSet set(scene, false);
    std::size_t readable = 0, missing_files = 0;
    for (const Texture& t : scene.textures) (fs::exists(t.path) ? readable : missing_files)++;
    EXPECT_GE(set.warnings().size(), missing_files > 0 ? 1u : 0u);
    for (const std::string& warning : set.warnings()) {
        EXPECT_NE(warning.find(".ppm"), std::string::npos) << warning;
        EXPECT_NE(warning.find("material '"), std::string::npos) << warning;
    }
    RecordProperty("readable_textures", int(readable));
}

}  // namespace
}  // namespace dynrt
