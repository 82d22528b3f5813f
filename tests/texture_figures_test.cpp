// The textures' figures (TextureFigures: count, bytes, load ms of one TextureSet) on their way
// to the user: the report's run.textures and its printed line, `dynrt bench`'s start-up line,
// Renderer::texture_figures and the benches' copies of it, and `dynrt render` / `dynrt bench`
// end to end. The writers are checked with figures given here; the end-to-end tests check a
// scene without textures (zeros in the JSON, no printed line) and a textured one, whose counts
// come from TextureSet itself.

#include "gltf_test_file.h"
#include "shell_command.h"
#include "test_files.h"

#include "dynrt/bench/bench.h"
#include "dynrt/bench/bench_sequence.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/report.h"
#include "dynrt/engine/texture_figures.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace dynrt {
namespace {

namespace fs = std::filesystem;

const TextureFigures kThreeImages{3, 12'400'000, 85.0};

nlohmann::json run_of(const RunInfo& run) { return nlohmann::json::parse(report_json(run, {}))["run"]; }

// ---- The writers, with figures given ---------------------------------------------------------

TEST(TextureFiguresReport, RunTexturesCarryCountBytesAndLoadMs) {
    RunInfo run;
    run.textures = kThreeImages;
    const nlohmann::json textures = run_of(run)["textures"];
    EXPECT_EQ(textures["count"].get<std::size_t>(), 3u);
    EXPECT_EQ(textures["bytes"].get<std::size_t>(), 12'400'000u);
    EXPECT_EQ(textures["load_ms"].get<double>(), 85.0);
}

// A scene without textures still has run.textures, all zeros: one shape for every report.
TEST(TextureFiguresReport, NoTexturesAreZerosInTheJson) {
    const nlohmann::json run = run_of(RunInfo{});
    ASSERT_TRUE(run.contains("textures"));
    EXPECT_EQ(run["textures"], (nlohmann::json{{"count", 0}, {"bytes", 0}, {"load_ms", 0.0}}));
}

TEST(TextureFiguresReport, DescribedInWordsWithTheirUnit) {
    EXPECT_EQ(describe_textures(kThreeImages), "3 images, 12.4 MB, read in 85.0 ms");
    EXPECT_EQ(describe_textures({1, 2'048, 0.3}), "1 image, 2.0 kB, read in 0.3 ms");
    EXPECT_EQ(describe_textures({2, 48, 12.0}), "2 images, 48 B, read in 12.0 ms");
}

TEST(TextureFiguresReport, PrintedLineOnlyWhenATextureWasRead) {
    std::ostringstream with, without;
    print_textures(with, kThreeImages);
    print_textures(without, TextureFigures{});
    EXPECT_EQ(with.str(), "textures: 3 images, 12.4 MB, read in 85.0 ms\n");
    EXPECT_EQ(without.str(), "");
}

TEST(TextureFiguresBench, StartUpLineEndsWithTheTextures) {
    std::ostringstream with, without;
    print_start_up(with, 1.5, 321.2, kThreeImages);
    print_start_up(without, 1.5, 321.2, TextureFigures{});
    const std::string line = "start-up (not in the runs): scene loaded in 1.5 ms; first frame 321.2 ms "
                             "(textures read, trees built from nothing)";
    EXPECT_EQ(with.str(), line + "; textures: 3 images, 12.4 MB, read in 85.0 ms\n");
    EXPECT_EQ(without.str(), line + "\n");
}

// ---- Scenes ------------------------------------------------------------------------------------

/// A `size` x `size` 8-bit RGB gradient written as a PNG at `path`.
void write_figures_png(const fs::path& path, int size) {
    std::vector<unsigned char> pixels;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            pixels.insert(pixels.end(), {static_cast<unsigned char>(4 * x), static_cast<unsigned char>(4 * y), 128});
        }
    }
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out) << OIIO::geterror();
    ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(size, size, 3, OIIO::TypeDesc::UINT8))) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

/// Four quads side by side, seen head-on: materials 0 and 1 map texture 0, material 2 maps
/// texture 1 (both 64x64 PNGs), material 3 maps texture 2, a file that is not there. So two
/// readable textures, one of them mapped twice.
struct FiguresScene {
    // Its own folder per process: ctest runs this file's cases at once, each a process of its
    // own, and one emptying a shared folder while another read its textures failed the other.
    fs::path dir = test::fresh_test_dir("texture_figures_" + std::to_string(::getpid()));
    Scene scene;
    Camera camera;
    RenderOptions options;

    FiguresScene() {
        write_figures_png(dir / "a.png", 64);
        write_figures_png(dir / "b.png", 64);
        scene.source = "texture figures test";
        for (const char* file : {"a.png", "b.png", "absent.png"}) {
            Texture t;
            t.name = t.path = (dir / file).string();
            scene.textures.push_back(t);
        }
        const std::uint32_t maps[] = {0, 0, 1, 2};
        for (std::uint32_t m = 0; m < 4; ++m) {
            Material material;
            material.name = "quad " + std::to_string(m);
            material.diffuse_map = TextureMap{maps[m], TextureWrap::repeat, TextureWrap::repeat};
            scene.materials.push_back(material);
            Object quad;
            quad.name = material.name;
            const float x = 2.5f * float(m) - 3.75f;
            quad.mesh.positions = {{x - 1, 1, 0}, {x - 1, -1, 0}, {x + 1, -1, 0}, {x + 1, 1, 0}};
            quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
            quad.mesh.texcoords = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
            quad.material = m;
            scene.objects.push_back(std::move(quad));
        }
        camera.eye = {0.0f, 0.0f, 8.0f};
        camera.target = {0.0f, 0.0f, 0.0f};
        options.width = 48;
        options.height = 16;
    }
};

TEST(TextureFiguresEndToEnd, ASceneWithoutTexturesHasNone) {
    FiguresScene shot;
    for (Material& m : shot.scene.materials) m.diffuse_map.reset();
    Renderer renderer(shot.options);
    RenderedFrame frame;
    EXPECT_EQ(renderer.texture_figures(), TextureFigures{}) << "before any trace";
    renderer.render(shot.scene, shot.camera, 0, frame);
    EXPECT_EQ(renderer.texture_figures(), TextureFigures{});
}

// The figures belong to the TextureSet: taken at the first trace, the same for later frames
// and after forget_trees (the textures stay read), gone at reset() until the next trace.
TEST(TextureFiguresEndToEnd, KeptWithTheTexturesAndGoneAtReset) {
    FiguresScene shot;
    Renderer renderer(shot.options);
    RenderedFrame frame;
    renderer.render(shot.scene, shot.camera, 0, frame);
    const TextureFigures first = renderer.texture_figures();
    renderer.render(shot.scene, shot.camera, 1, frame);
    EXPECT_EQ(renderer.texture_figures(), first) << "not read again for the next frame";
    renderer.forget_trees();
    renderer.render(shot.scene, shot.camera, 0, frame);
    EXPECT_EQ(renderer.texture_figures(), first) << "forget_trees keeps the textures read";
    renderer.reset();
    EXPECT_EQ(renderer.texture_figures(), TextureFigures{});
}

// Two readable textures (one mapped by two materials, counted
// once), their bytes and their load time; a missing file counts for nothing.
TEST(TextureFiguresEndToEnd, RendererCountsTheReadTexturesOnce) {
    FiguresScene shot;
    Renderer renderer(shot.options);
    RenderedFrame frame;
    renderer.render(shot.scene, shot.camera, 0, frame);
    const TextureFigures figures = renderer.texture_figures();
    EXPECT_EQ(figures.count, 2u);
    // At least the finest level's texels, one byte per channel, of each image.
    EXPECT_GE(figures.bytes, 2u * 64u * 64u * 3u);
    EXPECT_GT(figures.load_ms, 0.0);
    // Two clocks read apart: a millisecond of slack for a loaded machine (this failed once
    // under ctest -j2 with the load a hair longer than the frame that contains it).
    EXPECT_LT(figures.load_ms, frame.stats.total_ms + 1.0) << "read within the first frame";
}

// The benches report what their start-up frame read: the renderer's figures, once.
TEST(TextureFiguresEndToEnd, BenchesCarryTheirStartUpFramesTextures) {
    FiguresScene shot;
    Renderer renderer(shot.options);
    RenderedFrame frame;
    renderer.render(shot.scene, shot.camera, 0, frame);
    const TextureFigures want = renderer.texture_figures();
    const BenchRow row = bench_configuration(shot.scene, shot.camera, shot.options, 1, 0);
    const SequenceBench sequence =
        bench_sequence(shot.scene, CameraSource::fixed(shot.camera), shot.options, FrameRange{0, 1}, 1, 0, {});
    // The load time is each renderer's own; the rest is the scene's.
    EXPECT_EQ(row.textures.count, want.count);
    EXPECT_EQ(row.textures.bytes, want.bytes);
    EXPECT_EQ(sequence.textures.count, want.count);
    EXPECT_EQ(sequence.textures.bytes, want.bytes);
    EXPECT_EQ(row.textures.count, 2u);
    EXPECT_GT(row.textures.load_ms, 0.0);
    EXPECT_GT(sequence.textures.load_ms, 0.0);
}

// ---- The CLI -----------------------------------------------------------------------------------

test::ShellRun run_figures_cli(const std::string& args) {
    return test::run_shell("timeout 300 " + std::string(DYNRT_CLI_PATH) + " " + args);
}

nlohmann::json report_textures(const fs::path& report) {
    std::ifstream in(report);
    return nlohmann::json::parse(in)["run"]["textures"];
}

/// A glTF quad whose base colour maps a 64x64 PNG embedded as a data: URI.
fs::path textured_gltf_quad(const fs::path& dir) {
    const fs::path png = dir / "quad.png";
    write_figures_png(png, 64);
    const std::string png_bytes = test::bytes_of(png);
    test::GltfTestFile file;
    const std::vector<float> positions = {-1, 1, 0, -1, -1, 0, 1, -1, 0, -1, 1, 0, 1, -1, 0, 1, 1, 0};
    const std::vector<float> st = {0, 0, 0, 1, 1, 1, 0, 0, 1, 1, 1, 0};
    const int mesh = file.add_mesh(positions, {{"TEXCOORD_0", file.add_floats(st, "VEC2")}});
    file.doc()["meshes"][mesh]["primitives"][0]["material"] = 0;
    file.add_node({{"name", "quad"}, {"mesh", mesh}});
    file.doc()["images"] = nlohmann::json::array(
        {{{"uri", "data:image/png;base64," +
                      test::GltfTestFile::base64(std::vector<unsigned char>(png_bytes.begin(), png_bytes.end()))}}});
    file.doc()["textures"] = nlohmann::json::array({{{"source", 0}}});
    file.doc()["materials"] = nlohmann::json::array(
        {{{"name", "textured"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    return file.write("texture_figures_quad.gltf");
}

TEST(TextureFiguresCli, RenderAndBenchOfASceneWithoutTexturesSayNothingOfThem) {
    const fs::path dir = test::fresh_test_dir("texture_figures_plain");
    const test::ShellRun render = run_figures_cli("render sphere:50 --res 16x16 --threads 2 --out " +
                                                  (dir / "f.png").string() + " --report " + (dir / "r.json").string());
    ASSERT_EQ(render.exit_code, 0) << render.output;
    EXPECT_EQ(report_textures(dir / "r.json"), (nlohmann::json{{"count", 0}, {"bytes", 0}, {"load_ms", 0.0}}));
    EXPECT_EQ(render.output.find("textures:"), std::string::npos) << render.output;
    const test::ShellRun bench = run_figures_cli("bench sphere:50 --res 16x16 --repeat 1 --threads 2");
    ASSERT_EQ(bench.exit_code, 0) << bench.output;
    EXPECT_NE(bench.output.find("(textures read, trees built from nothing)\n"), std::string::npos) << bench.output;
    EXPECT_EQ(bench.output.find("; textures:"), std::string::npos) << bench.output;
}

// The render's report and printed line, and bench's start-up line,
// give the one texture read.
TEST(TextureFiguresCli, RenderAndBenchOfATexturedSceneGiveItsReadTextures) {
    const fs::path dir = test::fresh_test_dir("texture_figures_gltf");
    const fs::path gltf = textured_gltf_quad(dir);
    const test::ShellRun render = run_figures_cli("render " + gltf.string() + " --res 16x16 --threads 2 --out " +
                                                  (dir / "f.png").string() + " --report " + (dir / "r.json").string());
    ASSERT_EQ(render.exit_code, 0) << render.output;
    const nlohmann::json textures = report_textures(dir / "r.json");
    const test::ShellRun bench = run_figures_cli("bench " + gltf.string() + " --res 16x16 --repeat 1 --threads 2");
    ASSERT_EQ(bench.exit_code, 0) << bench.output;
    EXPECT_EQ(textures["count"].get<std::size_t>(), 1u);
    EXPECT_GE(textures["bytes"].get<std::size_t>(), 64u * 64u * 3u);
    EXPECT_GT(textures["load_ms"].get<double>(), 0.0);
    EXPECT_NE(render.output.find("\ntextures: 1 image, "), std::string::npos) << render.output;
    EXPECT_NE(bench.output.find("(textures read, trees built from nothing); textures: 1 image, "), std::string::npos)
        << bench.output;
}

}  // namespace
}  // namespace dynrt
