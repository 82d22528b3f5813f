// Runs the `dynrt` executable as a user would: good runs write what they promise, bad flags and
// bad input end with a clear one-line error and a non-zero exit, never a crash.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

struct CliRun {
    int exit_code;
    std::string output;  // stdout and stderr together
};

CliRun run_dynrt(const std::string& args) {
    const std::string command = std::string(DYNRT_CLI_PATH) + " " + args + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return {-1, "popen failed"};
    std::string output;
    std::array<char, 4096> buffer;
    while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
    const int status = pclose(pipe);
    // A signal (a crash) is reported as exit code 128 + signal, as a shell would.
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return {code, output};
}

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::path(testing::TempDir()) / ("dynrt_cli_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

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

TEST(Cli, RenderWritesOneImagePerFrameAndAReportOfEachUpdate) {
    const fs::path dir = fresh_dir("sequence");
    const CliRun run = run_dynrt("render 'plane:2@0,-1,0,3+sphere:200' --anim wave:sphere:200 "
                                 "--res 24x16 --frames 2-4 --out " + (dir / "f%03d.png").string() +
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

TEST(Cli, BenchVsAnUnknownTracerIsAnError) {
    const CliRun run = run_dynrt("bench sphere:10 --res 16x16 --repeat 1 --vs optix");
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find("--vs"), std::string::npos) << run.output;
}

TEST(Cli, InfoListsObjects) {
    const CliRun run = run_dynrt("info 'sphere:100+soup:10'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("sphere:100"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("soup:10"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("2 objects"), std::string::npos) << run.output;
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
    EXPECT_LT(run.exit_code, 128) << "crashed: " << run.output;
    EXPECT_NE(run.output.find(GetParam().expected), std::string::npos) << run.output;
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
                    BadCall{"bench sphere:10 --anim wave", "--frames"},
                    BadCall{"bench sphere:10 --frames 2 --sweep leaf=2,4", "--sweep"},
                    BadCall{"bench sphere:10 --error-block 4", "--error"},
                    BadCall{"bench sphere:10 --error-frame 3", "--error"},
                    BadCall{"bench sphere:10 --error --error-block 0", "--error-block"},
                    BadCall{"bench sphere:10 --error --frames 3", "--error-frame"},
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
