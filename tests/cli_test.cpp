// Runs the `dynrt` executable as a user would: good runs write what they promise, bad flags and
// bad input end with a clear one-line error and a non-zero exit, never a crash.

#include "test_files.h"
#include "shell_command.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

using CliRun = dynrt::test::ShellRun;
using dynrt::test::run_shell;

/// run_dynrt under `timeout`: a run still going after `seconds` is killed and exits with 124.
CliRun run_dynrt_within(int seconds, const std::string& args) {
    std::string command = "timeout " + std::to_string(seconds);
    command += ' ';
    command += DYNRT_CLI_PATH;
    command += ' ';
    command += args;
    return run_shell(command);
}

/// Every run is bounded: a hang fails its test (exit 124) instead of stalling the suite. The
/// bound is far above any of these runs' time, sanitizers included.
CliRun run_dynrt(const std::string& args) { return run_dynrt_within(300, args); }

fs::path fresh_dir(const std::string& name) { return dynrt::test::fresh_test_dir("cli_" + name); }

TEST(Cli, RenderWritesImageAovsAndReport) {
    const fs::path dir = fresh_dir("render");
    const CliRun run = run_dynrt("render 'plane:2@0,-1,0,3+sphere:500' --res 40x30 --out " +
                              (dir / "img.png").string() + " --aov depth,object,prim,normal" +
                              " --report " + (dir / "r.json").string() + " --threads 2");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    for (const char* f : {"img.png", "img.depth.exr", "img.object.exr", "img.prim.exr",
                          "img.normal.exr", "r.json"}) {
        EXPECT_TRUE(fs::exists(dir / f)) << f;
    }
    std::ifstream report(dir / "r.json");
    const nlohmann::json doc = nlohmann::json::parse(report);
    ASSERT_EQ(doc["frames"].size(), 1u);
    EXPECT_EQ(doc["frames"][0]["primary_rays"], 40 * 30);
    EXPECT_GT(doc["frames"][0]["shadow_rays"].get<int>(), 0);
    // plane:2 is 2x2 quads; sphere:500 has S = round((1 + sqrt(501)) / 2) = 12 stacks, 24 slices.
    EXPECT_EQ(doc["frames"][0]["triangles"].get<int>(), 2 * 2 * 2 + 2 * 24 * (12 - 1));
    EXPECT_NE(run.output.find("build"), std::string::npos);  // the printed table
}

// --memory-budget picks the static objects' layout: a budget below what the process holds
// already gets the smallest, reported with its prediction; a large one the full layout. The
// image is the same either way.
TEST(Cli, AMemoryBudgetChoosesTheStaticLayoutAndSaysWhy) {
    const fs::path dir = fresh_dir("memory_budget");
    std::string images[2];
    const char* budgets[2] = {"1M", "1T"};
    const char* chosen[2] = {"compact leaves, quantized nodes", "full leaves, float nodes"};
    for (int i = 0; i < 2; ++i) {
        SCOPED_TRACE(budgets[i]);
        const fs::path image = dir / (std::string(budgets[i]) + ".png");
        const fs::path report_path = dir / (std::string(budgets[i]) + ".json");
        const CliRun run = run_dynrt("render sphere:2000 --res 32x24 --memory-budget " + std::string(budgets[i]) +
                                     " --out " + image.string() + " --report " + report_path.string());
        ASSERT_EQ(run.exit_code, 0) << run.output;
        EXPECT_NE(run.output.find(std::string("static objects' tree with ") + chosen[i]), std::string::npos)
            << run.output;
        std::ifstream report(report_path);
        const nlohmann::json doc = nlohmann::json::parse(report);
        const nlohmann::json& layout = doc["frames"][0]["static_layout"];
        EXPECT_EQ(layout["chosen"], chosen[i]);
        EXPECT_GT(layout["predicted_peak_bytes"].get<std::size_t>(), 0u);
        std::ifstream png(image, std::ios::binary);
        images[i].assign(std::istreambuf_iterator<char>(png), {});
    }
    EXPECT_FALSE(images[0].empty());
    EXPECT_EQ(images[0], images[1]);
}

TEST(Cli, BackgroundColoursThePixelsThatSeeNothing) {
    // A camera looking away from the scene: every pixel the background given, in 8 bits.
    const fs::path dir = fresh_dir("background");
    const CliRun run = run_dynrt("render sphere:100 --res 8x4 --camera eye=0,0,5,target=0,0,10 "
                                 "--background 1,0.25,0 --out " + (dir / "bg.ppm").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::ifstream file(dir / "bg.ppm", std::ios::binary);
    std::string magic;
    int width = 0, height = 0, max = 0;
    file >> magic >> width >> height >> max;
    file.get();
    ASSERT_EQ(magic, "P6");
    ASSERT_EQ(width * height, 32);
    std::vector<unsigned char> rgb(std::size_t(width * height * 3));
    file.read(reinterpret_cast<char*>(rgb.data()), std::streamsize(rgb.size()));
    for (int p = 0; p < width * height; ++p) {
        // Linear 0.25 is sRGB 0.537, 137 of 255.
        EXPECT_EQ(int(rgb[std::size_t(3 * p)]), 255);
        EXPECT_EQ(int(rgb[std::size_t(3 * p + 1)]), 137);
        EXPECT_EQ(int(rgb[std::size_t(3 * p + 2)]), 0);
    }
}

TEST(Cli, RenderWritesOneImagePerFrameAndAReportOfEachUpdate) {
    const fs::path dir = fresh_dir("sequence");
    const CliRun run = run_dynrt("render 'plane:2@0,-1,0,3+sphere:200' --anim wave:sphere:200 "
                                 "--res 24x16 --frames 2-4 --update threshold --out " + (dir / "f%03d.png").string() +
                                 " --report " + (dir / "r.json").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    for (const char* f : {"f002.png", "f003.png", "f004.png"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
    EXPECT_FALSE(fs::exists(dir / "f001.png"));
    std::ifstream report(dir / "r.json");
    const nlohmann::json doc = nlohmann::json::parse(report);
    ASSERT_EQ(doc["frames"].size(), 3u);
    EXPECT_EQ(doc["frames"][0]["frame"], 2);
    EXPECT_EQ(doc["frames"][0]["rebuilds"].size(), 2u);  // both objects' first builds
    EXPECT_EQ(doc["frames"][1]["static_objects"], 1);
    EXPECT_EQ(doc["frames"][1]["deformable_objects"], 1);
    EXPECT_EQ(doc["frames"][1]["objects_skipped"], 1);   // the plane
    EXPECT_EQ(doc["frames"][1]["objects_refitted"], 1);  // the wave
    EXPECT_TRUE(doc["summary"]["median"].contains("refit_ms"));
    EXPECT_NE(run.output.find("refitted"), std::string::npos) << run.output;
}

TEST(Cli, BenchFramesTimesASequenceAndDrawsItsTimeline) {
    const fs::path dir = fresh_dir("bench_frames");
    std::string args = "bench sphere:300 --anim explode --treat sphere:300=exploding --res 32x32 "
                       "--frames 0-3 --warmup 0 "
                       "--plot " + (dir / "t.png").string() + " --json " + (dir / "b.json").string();
#if DYNRT_HAVE_EMBREE
    args += " --vs embree";
#endif
    const CliRun run = run_dynrt(args);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("frames 0-3"), std::string::npos) << run.output;
    EXPECT_TRUE(fs::exists(dir / "t.png"));
    std::ifstream json(dir / "b.json");
    const nlohmann::json doc = nlohmann::json::parse(json);
    EXPECT_EQ(doc["frames"].size(), 4u);
    EXPECT_EQ(doc["frames"][2]["rebuilds"][0]["reason"], "exploding");
#if DYNRT_HAVE_EMBREE
    ASSERT_EQ(doc["sequence"].size(), 3u);
    EXPECT_EQ(doc["sequence"][1]["tracer"], "embree refit");
    EXPECT_EQ(doc["sequence"][2]["tracer"], "embree low");
    // Both see the same exploding frames as dynrt: no pixel may differ in hit or object.
    EXPECT_EQ(doc["sequence"][1]["hit_object_differs"], 0);
    EXPECT_EQ(doc["sequence"][2]["hit_object_differs"], 0);
#endif
}

TEST(Cli, BenchPrintsOneRowPerConfigurationAndWritesCsv) {
    const fs::path dir = fresh_dir("bench");
    const CliRun run = run_dynrt("bench sphere:300 --res 16x16 --repeat 2 --warmup 0 "
                                 "--sweep cost-ratio=0.5,2 --sweep leaf=2,4 --csv " +
                                 (dir / "b.csv").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("4 configuration(s)"), std::string::npos) << run.output;
    std::ifstream csv(dir / "b.csv");
    std::string line;
    int lines = 0;
    while (std::getline(csv, line)) ++lines;
    EXPECT_EQ(lines, 1 + 4);
}

#if DYNRT_HAVE_EMBREE
TEST(Cli, BenchVsEmbreePrintsTheEmbreeBlock) {
    const CliRun run = run_dynrt("bench sphere:500 --res 32x32 --repeat 1 --vs embree");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("hit agreement"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("medium"), std::string::npos) << run.output;
}

TEST(Cli, BenchDiffImageMarksDisagreementsWithEmbree) {
    const fs::path dir = fresh_dir("diff");
    const CliRun run = run_dynrt("bench sphere:500 --res 32x24 --repeat 1 --warmup 0 --vs embree "
                                 "--diff-image " + (dir / "diff.png").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(fs::exists(dir / "diff.png"));
    EXPECT_NE(run.output.find("0 red pixels"), std::string::npos) << run.output;
}
#else
TEST(Cli, BenchVsEmbreeWithoutEmbreeIsAClearError) {
    const CliRun run = run_dynrt("bench sphere:10 --res 16x16 --repeat 1 --vs embree");
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find("this dynrt was built without Embree"), std::string::npos)
        << run.output;
}
#endif

TEST(Cli, BenchPlotDrawsAChartAndKeepsItsScript) {
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
        GTEST_SKIP() << "gnuplot is not installed (scripts/install-deps.sh installs it)";
    }
    const fs::path dir = fresh_dir("plot");
    const CliRun run = run_dynrt("bench sphere:300 --res 16x16 --repeat 1 --warmup 0 "
                                 "--sweep leaf=1,4,16 --plot " + (dir / "sweep.png").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_GT(fs::file_size(dir / "sweep.png"), 1000u);
    EXPECT_TRUE(fs::exists(dir / "sweep.png.gp"));
}

TEST(Cli, BenchErrorPrintsTimeAgainstErrorPerConfiguration) {
    const fs::path dir = fresh_dir("error");
    const CliRun run = run_dynrt("bench sphere:2000 --res 64x64 --error --repeat 1 --sweep "
                                 "culling=none,all --json " + (dir / "e.json").string() +
                                 " --csv " + (dir / "e.csv").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("reference: frame 0, 64 sampled pixels (one per 8x8 block)"),
              std::string::npos)
        << run.output;
    for (const char* column : {"total ms", "hit differs %", "ambig", "RMSE", "PSNR dB"}) {
        EXPECT_NE(run.output.find(column), std::string::npos) << column << "\n" << run.output;
    }
    std::ifstream json(dir / "e.json");
    const nlohmann::json doc = nlohmann::json::parse(json);
    ASSERT_EQ(doc["rows"].size(), 2u);
    for (const nlohmann::json& row : doc["rows"]) {
        EXPECT_EQ(row["samples"], 64);
        EXPECT_EQ(row["determined_differs"], 0);  // culling is exact
    }
    EXPECT_EQ(doc["reference"]["samples"], 64);
    std::ifstream csv(dir / "e.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find(",rmse,psnr_db"), std::string::npos) << header;
}

TEST(Cli, BenchErrorOnAWavingMeshComparesRefitWithRebuild) {
    const fs::path dir = fresh_dir("error_anim");
    std::string args = "bench sphere:500 --anim wave --res 32x32 --error --error-block 2 "
                       "--error-frame 6 --repeat 1 --sweep update=rebuild,refit";
    if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
        args += " --plot " + (dir / "error.png").string();
    }
    const CliRun run = run_dynrt(args);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("frame 6"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("refit"), std::string::npos) << run.output;
    if (args.find("--plot") != std::string::npos) {
        EXPECT_GT(fs::file_size(dir / "error.png"), 1000u);
        EXPECT_TRUE(fs::exists(dir / "error.png.gp"));
    }
}

TEST(Cli, BenchFramesErrorComparesReuseAndAdaptiveWithFullRenders) {
    const fs::path dir = fresh_dir("sequence_error");
    std::string args = "bench sphere:500 --anim wave --res 32x32 --frames 0-2 --error --sweep "
                       "reuse=off,exact --sweep adaptive=0,0.5 --json " +
                       (dir / "s.json").string();
    if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
        args += " --plot " + (dir / "s.png").string();
    }
    const CliRun run = run_dynrt(args);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    for (const char* text : {"frames 0-2", "4 configuration(s)", "off (full render)",
                             "exact + adaptive 0.5", "mean SSIM"}) {
        EXPECT_NE(run.output.find(text), std::string::npos) << text << "\n" << run.output;
    }
    std::ifstream json(dir / "s.json");
    const nlohmann::json doc = nlohmann::json::parse(json);
    ASSERT_EQ(doc["rows"].size(), 4u);
    EXPECT_EQ(doc["rows"][0]["mean_ssim"], 1.0);  // reuse off, no adaptive sampling
    EXPECT_EQ(doc["rows"][0]["per_frame"].size(), 3u);
    if (args.find("--plot") != std::string::npos) {
        EXPECT_GT(fs::file_size(dir / "s.png"), 1000u);
        std::ifstream script(dir / "s.png.gp");
        const std::string text((std::istreambuf_iterator<char>(script)), {});
        EXPECT_NE(text.find("1 - mean SSIM"), std::string::npos);
        EXPECT_NE(text.find("Pareto front"), std::string::npos);
    }
}

TEST(Cli, BenchFramesErrorRefusesWhatItCannotMeasure) {
    const std::pair<const char*, const char*> cases[] = {
        {"--frames 0-1 --error --vs embree", "--vs"},
        {"--frames 0-1 --error --error-frame 1", "--error-frame"},
        {"--frames 0-1 --error --sweep cost-ratio=0.1,1", "only reuse=..., adaptive=..., spp=..., aa=... and lod=..."},
        {"--frames 0-1 --error --sweep reuse=cache:2", "reuse=cache:2"},
        {"--sweep reuse=off,exact", "give --frames A-B and --error"},
        {"--frames 0-1 --sweep reuse=off,exact", "give --frames A-B and --error"},
    };
    for (const auto& [flags, message] : cases) {
        const CliRun run = run_dynrt(std::string("bench sphere:10 --res 16x16 ") + flags);
        EXPECT_EQ(run.exit_code, 2) << flags << "\n" << run.output;  // usage errors
        EXPECT_NE(run.output.find(message), std::string::npos) << flags << "\n" << run.output;
    }
}

TEST(Cli, BenchVsAnUnknownTracerIsAnError) {
    const CliRun run = run_dynrt("bench sphere:10 --res 16x16 --repeat 1 --vs optix");
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("--vs"), std::string::npos) << run.output;
}

/// Frame numbers near INT_MAX once wrapped the frame counter and wrote files until the disk
/// filled (render) or looped for ever (bench). They must be refused at once, naming the bound,
/// with nothing written. `timeout` bounds the run, so a regression fails instead of hanging.
TEST(Cli, FarFramesAreRefusedAtOnceWithNothingWritten) {
    const fs::path dir = fresh_dir("far_frames");
    for (const std::string& frames : {std::string("2147483646-2147483647"), std::string("10000001"),
                                      std::string("9999999-10000000"),
                                      std::string("0-99999999999999999999999")}) {
        for (const std::string& command : {std::string("render"), std::string("bench")}) {
            const std::string out = (dir / "big" / "%d.png").string();
            const CliRun run = run_dynrt_within(
                20, command + " sphere:10 --res 8x8 --anim rigid --frames " + frames +
                        (command == "render" ? " --out '" + out + "'" : std::string()));
            SCOPED_TRACE(command + " --frames " + frames);
            EXPECT_NE(run.exit_code, 0) << run.output;
            EXPECT_NE(run.exit_code, 124) << "did not finish within 20 s: " << run.output;
            EXPECT_LT(run.exit_code, 128) << "crashed: " << run.output;
            EXPECT_NE(run.output.find("frame numbers above 9999999 are not supported"),
                      std::string::npos)
                << run.output;
            EXPECT_FALSE(fs::exists(dir / "big")) << "a refused run created its output folder";
        }
    }
    // The largest frame is still rendered.
    const CliRun last = run_dynrt_within(
        60, "render sphere:10 --res 8x8 --anim rigid --frames 9999998-9999999 --out '" +
                (dir / "ok" / "%d.png").string() + "'");
    EXPECT_EQ(last.exit_code, 0) << last.output;
    EXPECT_TRUE(fs::exists(dir / "ok" / "9999999.png"));
    // The two frames, and the render's journal (hidden), which makes it resumable.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "ok"), fs::directory_iterator{}), 3);
    EXPECT_TRUE(fs::exists(dir / "ok" / ".dynrt-frames.jsonl"));
}

/// A sequence seen as one file: an animated GIF with one image per frame, a contact sheet of
/// the frames in a grid, and a video.
TEST(Cli, SequencesGoToAnAnimatedGifAndAContactSheet) {
    const fs::path dir = fresh_dir("sequence_files");
    const fs::path gif = dir / "anim.gif", sheet = dir / "sheet.png";
    const CliRun run = run_dynrt("render sphere:200 --res 20x12 --anim rigid --frames 0-4 --out '" +
                                 gif.string() + "' --contact-sheet '" + sheet.string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    auto in = OIIO::ImageInput::open(gif.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    int frames = 0;
    while (in->seek_subimage(frames, 0)) {
        EXPECT_EQ(in->spec().width, 20);
        EXPECT_EQ(in->spec().height, 12);
        ++frames;
    }
    EXPECT_EQ(frames, 5);
    in->close();
    auto grid = OIIO::ImageInput::open(sheet.string());
    ASSERT_TRUE(grid) << OIIO::geterror();
    EXPECT_EQ(grid->spec().width, 3 * 21 - 1);   // 5 thumbnails: 3 columns of 20 + 1 pixels
    EXPECT_EQ(grid->spec().height, 2 * 13 - 1);  // 2 rows
    grid->close();
    EXPECT_NE(run.output.find("contact sheet: "), std::string::npos) << run.output;

    // A video goes through ffmpeg when it is installed (every frame in the file, an odd size
    // padded), else it is refused before rendering with what to do instead.
    const fs::path mp4 = dir / "anim.mp4";
    const CliRun video = run_dynrt("render sphere:200 --res 21x13 --anim rigid --frames 0-6 --out '" +
                                   mp4.string() + "'");
    if (run_shell("command -v ffmpeg >/dev/null && command -v ffprobe >/dev/null").exit_code == 0) {
        ASSERT_EQ(video.exit_code, 0) << video.output;
        const CliRun probe = run_shell(
            "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
            "stream=nb_read_frames,width,height -of csv=p=0 '" + mp4.string() + "'");
        EXPECT_EQ(probe.exit_code, 0) << probe.output;
        EXPECT_EQ(probe.output, "22,14,7\n") << probe.output;
    } else {
        EXPECT_NE(video.exit_code, 0);
        EXPECT_LT(video.exit_code, 128) << video.output;
        EXPECT_NE(video.output.find("needs the ffmpeg program"), std::string::npos) << video.output;
        EXPECT_NE(video.output.find("ffmpeg -framerate"), std::string::npos) << video.output;
        EXPECT_FALSE(fs::exists(mp4));
    }
}

/// glTF parts dynrt leaves out are named, as BART's are (skipped without ../shared/scenes).
TEST(Cli, GltfTexturesAndExtensionsAreReportedAsIgnored) {
    const fs::path file = fs::path(DYNRT_SHARED_SCENES_DIR) / "transmissiontest" / "TransmissionTest.glb";
    if (!fs::exists(file)) GTEST_SKIP() << file << " not found";
    const fs::path dir = fresh_dir("ignored");
    const CliRun run = run_dynrt("render '" + file.string() + "' --res 8x8 --out '" +
                                 (dir / "t.png").string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("ignored: textures other than base colour and emission of "), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("ignored: extension KHR_xmp"), std::string::npos) << run.output;
    // Its transmission is mapped to the materials (docs/scene-input.md "Materials"), not left out.
    EXPECT_EQ(run.output.find("KHR_materials_transmission"), std::string::npos) << run.output;
}

TEST(Cli, PrintsItsVersion) {
    const CliRun run = run_dynrt("--version");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output.rfind("dynrt ", 0), 0u) << run.output;
}

/// A numbered output makes its folder for one frame as for many, and only once the scene has
/// loaded: a run that fails first leaves no folder behind.
TEST(Cli, NumberedOutputMakesItsFolderOnlyForARunThatRenders) {
    const fs::path dir = fresh_dir("numbered");
    const CliRun one = run_dynrt("render sphere:10 --res 8x8 --frames 0-0 --out '" +
                                 (dir / "one" / "%d.png").string() + "'");
    EXPECT_EQ(one.exit_code, 0) << one.output;
    EXPECT_TRUE(fs::exists(dir / "one" / "0.png")) << one.output;
    const CliRun bad = run_dynrt("render /no/such/file.gltf --frames 0-1 --out '" +
                                 (dir / "bad" / "%d.png").string() + "'");
    EXPECT_NE(bad.exit_code, 0) << bad.output;
    EXPECT_FALSE(fs::exists(dir / "bad")) << bad.output;
}

/// An output that cannot be written is found before the first frame, with nothing written:
/// two outputs naming one file (the image would be replaced by the report's JSON), a contact
/// sheet or report in a folder that takes no file (/proc). Usage errors: exit 2.
TEST(Cli, OutputsAreCheckedBeforeTheFirstFrame) {
    const fs::path dir = fresh_dir("outputs");
    const std::string a = (dir / "a.png").string();
    const CliRun same = run_dynrt("render sphere:10 --res 8x8 --out '" + a + "' --report '" + a + "'");
    EXPECT_EQ(same.exit_code, 2) << same.output;
    EXPECT_NE(same.output.find("dynrt: error: --out '" + a + "' and --report '" + a + "' are the same file"),
              std::string::npos) << same.output;
    EXPECT_FALSE(fs::exists(a)) << same.output;
    for (const std::string& flag : {std::string("--contact-sheet /proc/sheet.png"),
                                    std::string("--report /proc/r.json")}) {
        const CliRun run = run_dynrt("render sphere:10 --res 8x8 --anim rigid --frames 0-2 --out '" +
                                     (dir / "f" / "%d.png").string() + "' " + flag);
        SCOPED_TRACE(flag);
        EXPECT_EQ(run.exit_code, 2) << run.output;
        EXPECT_NE(run.output.find("cannot write in folder /proc"), std::string::npos) << run.output;
        EXPECT_EQ(run.output.find("partial"), std::string::npos) << run.output;
        EXPECT_FALSE(fs::exists(dir / "f")) << "frames were rendered first: " << run.output;
    }
}

/// `--frames N` is frame N alone (Blender's -f N), and the render says so once, with the
/// range form; A-B is a range.
TEST(Cli, FramesNIsFrameNAlone) {
    const fs::path dir = fresh_dir("frames_n");
    const CliRun run = run_dynrt("render sphere:10 --res 8x8 --anim rigid --frames 3 --out '" +
                                 (dir / "%d.png").string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(fs::exists(dir / "3.png"));
    // That one image, beside the render's journal (every numbered render keeps one).
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 2);
    EXPECT_TRUE(fs::exists(dir / ".dynrt-frames.jsonl"));
    EXPECT_NE(run.output.find("frames: frame 3 alone (--frames N is one frame; a range is A-B, "
                              "e.g. --frames 0-2 for 3 frames)"),
              std::string::npos) << run.output;
    const CliRun range = run_dynrt("render sphere:10 --res 8x8 --anim rigid --frames 0-1 --out '" +
                                   (dir / "r%d.png").string() + "'");
    ASSERT_EQ(range.exit_code, 0) << range.output;
    EXPECT_EQ(range.output.find("alone"), std::string::npos) << range.output;
    EXPECT_NE(run_dynrt("render --help").output.find("frame N alone"), std::string::npos);
    // bench --frames reads N the same way, and says so too.
    const CliRun bench = run_dynrt("bench sphere:10 --res 8x8 --anim rigid --frames 3");
    ASSERT_EQ(bench.exit_code, 0) << bench.output;
    EXPECT_NE(bench.output.find("frames: frame 3 alone"), std::string::npos) << bench.output;
    EXPECT_NE(bench.output.find("frames 3-3"), std::string::npos) << bench.output;
}

/// Every error of the command line is one "dynrt: error:" line and exit 2, CLI11's included;
/// a failure while running (a scene that cannot be read) exits 1.
TEST(Cli, UsageErrorsExit2WithThePrefixAndFailuresExit1) {
    for (const std::string& args : {std::string("render sphere:10 --fps 0"),
                                    std::string("render sphere:10 --threads 0"),
                                    std::string("--threads 0 info sphere:10"),
                                    std::string("render sphere:10 --bogus"),
                                    std::string("render sphere:10 soup:10"),
                                    std::string("render sphere:10 --res 8x8 --res 9x9"),
                                    std::string("render sphere:10 --frames 3-1"),
                                    std::string("render sphere:10 --normals wobbly"), std::string("")}) {
        const CliRun run = run_dynrt(args);
        SCOPED_TRACE(args);
        EXPECT_EQ(run.exit_code, 2) << run.output;
        EXPECT_EQ(run.output.rfind("dynrt: error: ", 0), 0u) << run.output;
    }
    const CliRun twice = run_dynrt("render sphere:10 --res 8x8 --res 9x9");
    EXPECT_NE(twice.output.find("dynrt: error: --res: given more than once; give it once"),
              std::string::npos) << twice.output;
    EXPECT_EQ(twice.output.find("At Most"), std::string::npos) << twice.output;
    const CliRun missing = run_dynrt("render /no/such/file.gltf");
    EXPECT_EQ(missing.exit_code, 1) << missing.output;
    EXPECT_NE(missing.output.find("dynrt: error: "), std::string::npos) << missing.output;
    EXPECT_NE(run_dynrt("--help").output.find("Exit codes: 0 done; 1 a failure"), std::string::npos);
}

/// Two clips that drive the same node are alternatives: asked for together they are refused,
/// naming both and a node (Fox's Survey and Walk drive one skeleton; skipped without
/// ../shared/scenes).
TEST(Cli, TwoClipsDrivingOneNodeAreRefused) {
    const fs::path fox = fs::path(DYNRT_SHARED_SCENES_DIR) / "fox" / "Fox.glb";
    if (!fs::exists(fox)) GTEST_SKIP() << fox << " not found";
    const fs::path dir = fresh_dir("clip_overlap");
    const std::string render = "render '" + fox.string() + "' --res 8x8 --frames 0-1 --out '" +
                               (dir / "%d.png").string() + "'";
    const CliRun both = run_dynrt(render + " --clip Survey --clip Walk");
    EXPECT_EQ(both.exit_code, 2) << both.output;
    EXPECT_NE(both.output.find("dynrt: error: --clip 'Survey' and --clip 'Walk' both animate node '"),
              std::string::npos) << both.output;
    EXPECT_FALSE(fs::exists(dir / "0.png"));
    const CliRun twice = run_dynrt(render + " --clip Walk --clip 1");
    EXPECT_NE(twice.output.find("--clip 'Walk' is given twice"), std::string::npos) << twice.output;
    EXPECT_EQ(run_dynrt(render + " --clip Walk").exit_code, 0);
}

TEST(Cli, InfoListsObjects) {
    const CliRun run = run_dynrt("info 'sphere:100+soup:10'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("sphere:100"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("soup:10"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("2 objects"), std::string::npos) << run.output;
}

/// The timeline of a file with alternative clips (Fox: Survey, Walk, Run drive the same
/// skeleton): `info` lists them with their times, `render` plays the first and says so, and
/// frames past the end draw a warning unless --loop. Skipped without ../shared/scenes.
TEST(Cli, ClipsAreListedChosenAndWarnedPastTheirEnd) {
    const fs::path fox = fs::path(DYNRT_SHARED_SCENES_DIR) / "fox" / "Fox.glb";
    if (!fs::exists(fox)) GTEST_SKIP() << fox << " not found";
    const CliRun info = run_dynrt("info '" + fox.string() + "'");
    ASSERT_EQ(info.exit_code, 0) << info.output;
    for (const char* expected : {"frame rate: 24 fps", "clips: 3 (by default only the first plays",
                                 "Survey", "Walk", "Run", "duration s"}) {
        EXPECT_NE(info.output.find(expected), std::string::npos) << expected << "\n" << info.output;
    }
    const fs::path dir = fresh_dir("clips");
    const std::string render = "render '" + fox.string() + "' --res 16x16 --out '" +
                               (dir / "%d.png").string() + "'";
    const CliRun past = run_dynrt(render + " --frames 500-501");
    ASSERT_EQ(past.exit_code, 0) << past.output;
    EXPECT_NE(past.output.find("clips: playing 'Survey'"), std::string::npos) << past.output;
    EXPECT_NE(past.output.find("warning: frames 500-501 are past the end of the animation"),
              std::string::npos)
        << past.output;
    const CliRun looped = run_dynrt(render + " --frames 500-501 --loop");
    ASSERT_EQ(looped.exit_code, 0) << looped.output;
    EXPECT_EQ(looped.output.find("warning:"), std::string::npos) << looped.output;
    const CliRun walk = run_dynrt(render + " --clip Walk --frames 0-1");
    ASSERT_EQ(walk.exit_code, 0) << walk.output;
    EXPECT_EQ(walk.output.find("clips: playing"), std::string::npos) << walk.output;
}

TEST(Cli, HelpOnEveryCommand) {
    for (const char* cmd : {"--help", "render --help", "bench --help", "info --help"}) {
        const CliRun run = run_dynrt(cmd);
        EXPECT_EQ(run.exit_code, 0) << cmd;
        EXPECT_NE(run.output.find("Usage"), std::string::npos) << cmd << run.output;
    }
}

struct BadCall {
    const char* args;
    const char* expected;  // a fragment the error message must contain
};

class CliErrors : public testing::TestWithParam<BadCall> {};

TEST_P(CliErrors, FailCleanlyWithAMessage) {
    const CliRun run = run_dynrt(GetParam().args);
    EXPECT_NE(run.exit_code, 0) << run.output;
    EXPECT_NE(run.exit_code, 124) << "did not finish: " << run.output;
    EXPECT_LT(run.exit_code, 128) << "crashed: " << run.output;
    EXPECT_NE(run.output.find(GetParam().expected), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("dynrt: error: "), std::string::npos) << run.output;
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, CliErrors,
    testing::Values(BadCall{"", "subcommand"},
                    BadCall{"render sphere:10 --bogus", "--bogus"},
                    BadCall{"render sphere:10 --res 10", "--res"},
                    BadCall{"render sphere:10 --res 0x10", "--res"},
                    BadCall{"render sphere:10 --cost-ratio -1", "cost-ratio"},
                    BadCall{"render sphere:10 --leaf-size 0", "leaf-size"},
                    BadCall{"render sphere:10 --threads 0", "threads"},
                    BadCall{"render sphere:10 --aov depth,colour", "colour"},
                    BadCall{"render sphere:10 --camera eye=1,2", "eye"},
                    BadCall{"render sphere:10 --camera eye=0,0,0,target=0,0,0", "eye equals target"},
                    BadCall{"render sphere:10 --light 1,2", "--light"},
                    BadCall{"render sphere:10 --out /nonexistent-dir/x.png", "nonexistent-dir"},
                    BadCall{"render sphere:10 --out x.unknownext", "x.unknownext"},
                    BadCall{"render /no/such/file.gltf", "/no/such/file.gltf"},
                    BadCall{"render cube:10", "cube:10"},
                    BadCall{"render cube:10", ".aff"},
                    BadCall{"render sphere:10 --light 1,2,3,-1", "intensity must be >= 0"},
                    BadCall{"render sphere:10 --light 1,2,3:sphere=0", "radius must be > 0"},
                    BadCall{"render sphere:10 --light 1,2,3:quad=1,0,0,2,0,0", "edges must not be parallel"},
                    BadCall{"render sphere:10 --light 1,2,3:disc=1", "unknown option 'disc=1' (sphere=, quad=, spot="},
                    BadCall{"render sphere:10 --light 1,2,3:spot=0,-1,0,30,20", "0 <= INNER < OUTER <= 90"},
                    BadCall{"render sphere:10 --light 1,2,3:spot=0,0,0,10,20", "a spot's axis must not be zero"},
                    BadCall{"render sphere:10 --light 0,0,0:directional", "direction must not be zero"},
                    BadCall{"render sphere:10 --light 0,-1,0:directional:falloff", "no falloff or range"},
                    BadCall{"render sphere:10 --light 0,-1,0:directional:sphere=1", "no area"},
                    BadCall{"render sphere:10 --light 1,2,3:color=1,-1,0", "channels must be >= 0"},
                    BadCall{"render sphere:10 --light 1,2,3:range=0", "range must be > 0"},
                    BadCall{"render sphere:10 --environment /no/such/sky.exr",
                            "--environment: environment map '/no/such/sky.exr': no such file"},
                    BadCall{"render sphere:10 --environment-lights 8", "environment lights need an environment map"},
                    BadCall{"render sphere:10 --environment-lights 300", "--environment-lights"},
                    BadCall{"render sphere:10 --spp 0", "--spp"},
                    BadCall{"render sphere:10 --memory-budget 2x", "--memory-budget '2x': expected a size"},
                    BadCall{"render sphere:10 --memory-budget 10K", "at least 1M"},
                    BadCall{"render sphere:10 --memory-budget -2G", "--memory-budget '-2G'"},
                    BadCall{"render sphere:10 --memory-budget 2G --nodes quantized", "excludes"},
                    BadCall{"render sphere:10 --background 1,2", "--background '1,2': expected r,g,b"},
                    BadCall{"render sphere:10 --background 0,-1,0", "three finite numbers >= 0"},
                    BadCall{"render sphere:10 --spp 5000", "--spp"},
                    BadCall{"render sphere:10 --filter gauss", "--filter"},
                    BadCall{"render sphere:10 --aa-contrast -1", "--aa-contrast"},
                    BadCall{"render sphere:10 --spp 4 --adaptive 0.1", "one sample per pixel"},
                    BadCall{"render sphere:10 --lod -1", "--lod"},
                    BadCall{"bench sphere:10 --vs embree --lod 1", "levels of detail"},
                    BadCall{"bench sphere:10 --vs embree --sweep lod=0,1", "levels of detail"},
                    BadCall{"bench sphere:10 --error --sweep lod=0,-1", "levels of detail"},
                    BadCall{"bench sphere:10 --sweep lod=0,1 --plot a.png", "lod"},
                    BadCall{"render sphere:10 --report /nonexistent-dir/r.json", "nonexistent-dir"},
                    BadCall{"bench sphere:10 --sweep leaf=0", "leaf"},
                    BadCall{"bench sphere:10 --sweep depth=3", "depth"},
                    BadCall{"bench sphere:10 --repeat 0", "repeat"},
                    BadCall{"bench sphere:10 --plot chart.svg", "chart.svg"},
                    BadCall{"bench sphere:10 --diff-image d.png", "--vs embree"},
                    BadCall{"info", "scene"},
                    BadCall{"render sphere:10 --frames 0-3 --out one.png", "%04d"},
                    BadCall{"render sphere:10 --frames 3-1", "--frames"},
                    BadCall{"render sphere:10 --frames 0-1 --out f%s.png", "%d"},
                    BadCall{"render sphere:10 --anim spin", "spin"},
                    BadCall{"render sphere:10 --anim wave:nothing", "nothing"},
                    BadCall{"render sphere:10 --treat sphere:10=wobbly", "wobbly"},
                    BadCall{"render sphere:10 --clip walk", "walk"},
                    BadCall{"render sphere:10 --camera gltf", "no camera"},
                    BadCall{"render sphere:10 --fps 0", "--fps"},
                    BadCall{"render sphere:10 --fps 0", "'0' is not a positive number"},
                    BadCall{"render sphere:10 soup:10", "unexpected argument(s) 'soup:10'"},
                    BadCall{"render sphere:10 --out /proc/dynrt-no/%d.png --frames 0-1",
                            "/proc/dynrt-no"},
                    BadCall{"bench sphere:10 --anim wave", "--frames"},
                    BadCall{"bench sphere:10 --frames 2 --sweep leaf=2,4", "--sweep"},
                    BadCall{"bench sphere:10 --error-block 4", "--error"},
                    BadCall{"bench sphere:10 --error-frame 3", "--error"},
                    BadCall{"bench sphere:10 --error --error-block 0", "--error-block"},
                    BadCall{"bench sphere:10 --error --frames 3 --error-frame 1",
                            "--error-frame"},
                    BadCall{"bench sphere:10 --res 8x8 --error --frames 2", "11x11"},
                    BadCall{"bench sphere:10 --error --frames 2 --tracer single --sweep "
                            "adaptive=0.1",
                            "--tracer single"},
                    BadCall{"bench sphere:10 --error --vs embree", "--vs"},
                    BadCall{"bench sphere:10 --sweep update=rebuild,refit", "--error"},
                    BadCall{"bench sphere:10 --error --sweep update=refit,morph", "morph"},
                    BadCall{"bench sphere:10 --error --sweep adaptive=0,-1", "adaptive"},
                    BadCall{"bench sphere:10 --error --sweep adaptive=0,nan", "nan"},
                    BadCall{"bench sphere:10 --error --sweep adaptive=", "adaptive"},
                    BadCall{"bench sphere:10 --error --tracer single --sweep adaptive=0.1",
                            "--tracer single"},
                    BadCall{"bench sphere:10 --tracer single --adaptive 0.1", "--tracer single"},
                    BadCall{"bench sphere:10 --sweep adaptive=0,0.1 --plot a.png", "adaptive"}));

}  // namespace
