// `dynrt render` stopped by SIGINT or SIGTERM at random points (seeded: a failure names its
// seed and kill time, and reproduces): every file it leaves is whole (images decode, a GIF ends
// with its trailer, the report parses and lists exactly the frames whose images are there) or
// absent, no temporary file is left, the exit code is 128 + the signal, and --resume finishes
// a numbered render with the bytes of an uninterrupted one.

#include "test_files.h"
#include "shell_command.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>

namespace dynrt {
namespace cli_interrupt_test {

namespace fs = std::filesystem;

using test::run_shell;
using test::ShellRun;

fs::path fresh_dir(const std::string& name) { return test::fresh_test_dir("interrupt_" + name); }

using test::bytes_of;
using test::content_of;

// Eight small frames of a moving sphere over a floor; each is made 150 ms slower
// (DYNRT_TEST_SLOW_FRAMES, a sleep after its render), so that a kill lands in the middle of a
// render, between frames or while the writer writes, depending on its time.
const std::string kRender =
    " render 'plane:2@0,-1,0,3+sphere:200' --anim rigid:sphere:200 --res 24x16 --frames 0-7 "
    "--threads 1";
const std::string kSlow = "DYNRT_TEST_SLOW_FRAMES=0:150,1:150,2:150,3:150,4:150,5:150,6:150,7:150";

/// The render with `args`, sent `signal` after `seconds` (timeout passes on the exit code,
/// 128 + the signal when it ended the process; a render that ignores it is killed after 60 s).
ShellRun render_until(int signal, double seconds, const std::string& args) {
    return run_shell("env " + kSlow + " timeout --preserve-status -k 60 -s " +
                     (signal == SIGINT ? "INT " : "TERM ") + std::to_string(seconds) + " " +
                     DYNRT_CLI_PATH + kRender + " " + args);
}

bool decodes(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return false;
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    return in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
}

/// Every file in `dir` whole, none temporary; returns the frames whose image is there.
std::set<int> check_files_whole(const fs::path& dir) {
    std::set<int> frames;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        const fs::path& path = entry.path();
        const std::string name = path.filename().string();
        EXPECT_EQ(name.find(".partial"), std::string::npos) << "left behind: " << path;
        const std::string ext = path.extension().string();
        if (ext == ".png" || ext == ".exr") {
            EXPECT_TRUE(decodes(path)) << path << " is torn";
            if (name.size() == 8 && ext == ".png" && name.rfind("sheet", 0) != 0) {
                frames.insert(std::stoi(name.substr(0, 4)));
            }
        } else if (ext == ".gif") {
            const std::string gif = bytes_of(path);
            EXPECT_TRUE(!gif.empty() && gif.back() == '\x3b') << path << " has no trailer";
            EXPECT_TRUE(decodes(path)) << path;
        } else if (ext == ".json") {
            std::ifstream in(path);
            const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
            EXPECT_FALSE(doc.is_discarded()) << path << " does not parse";
        }
    }
    return frames;
}

/// The frames the report lists, when there is one.
std::set<int> report_frames(const fs::path& report) {
    std::set<int> frames;
    std::ifstream in(report);
    const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
    if (doc.is_discarded()) return frames;
    for (const nlohmann::json& f : doc["frames"]) frames.insert(f["frame"].get<int>());
    return frames;
}

/// How a run ended.
enum class Ending { finished, stopped_between_frames, killed_before_rendering };

/// Checks a run sent `signal`: it finished first (exit 0), or ended with 128 + the signal, and
/// once its render had started (its first line is out) it stopped between frames, said so, and
/// wrote the report of the frames done. A signal that lands once the render is over (its last
/// line, the report's path, is out) finds the process exiting with the default action back in
/// place, and ends it: that run finished too (under the sanitizers exiting takes a while).
Ending expect_stopped(const ShellRun& run, int signal, const fs::path& report) {
    if (run.exit_code == 0) return Ending::finished;
    EXPECT_EQ(run.exit_code, 128 + signal) << run.output;
    if (run.output.find("dynrt: stopped by ") == std::string::npos &&
        run.output.find("report: " + report.string() + "\n") != std::string::npos) {
        EXPECT_EQ(report_frames(report).size(), 8u) << run.output;
        return Ending::finished;
    }
    if (run.output.find("dynrt: ") != 0 || run.output.find(" -> ") == std::string::npos) {
        return Ending::killed_before_rendering;
    }
    EXPECT_NE(run.output.find(std::string("dynrt: stopped by ") +
                              (signal == SIGINT ? "SIGINT" : "SIGTERM")),
              std::string::npos)
        << run.output;
    EXPECT_TRUE(fs::exists(report)) << run.output;
    return Ending::stopped_between_frames;
}

const char* const kFrameFiles[] = {".png", ".depth.exr"};

/// The numbered render in `dir`, stopped by `stop` (the command that ran it): every file whole,
/// the report listing the frames whose files are there; then --resume finishes it with the
/// files of the uninterrupted render in `reference`. Returns how the stopped run ended.
Ending check_stopped_then_resume(const fs::path& dir, const fs::path& reference, int signal,
                                 const ShellRun& stop, const std::string& args) {
    const Ending ending = expect_stopped(stop, signal, dir / "r.json");
    const std::set<int> present = check_files_whole(dir);
    if (fs::exists(dir / "r.json")) {
        EXPECT_EQ(report_frames(dir / "r.json"), present) << stop.output;
    }
    const ShellRun resumed = run_shell(std::string("timeout 300 ") + DYNRT_CLI_PATH + kRender +
                                       " " + args + " --resume");
    EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
    check_files_whole(dir);
    EXPECT_EQ(report_frames(dir / "r.json"), (std::set<int>{0, 1, 2, 3, 4, 5, 6, 7}));
    for (int f = 0; f < 8; ++f) {
        char name[8];
        std::snprintf(name, sizeof name, "%04d", f);
        for (const char* suffix : kFrameFiles) {
            const std::string file = name + std::string(suffix);
            const std::string expected = content_of(reference / file);
            EXPECT_FALSE(expected.empty()) << file;
            EXPECT_EQ(content_of(dir / file), expected) << file;
        }
    }
    return ending;
}

TEST(CliInterrupt, NumberedFramesStoppedAtRandomPointsAreWholeAndResumeToTheSameBytes) {
    const fs::path reference = fresh_dir("reference");
    const ShellRun whole = run_shell(std::string("timeout 300 ") + DYNRT_CLI_PATH + kRender +
                                     " --aov depth --out " + (reference / "%04d.png").string());
    ASSERT_EQ(whole.exit_code, 0) << whole.output;
    const fs::path dir = fs::path(testing::TempDir()) / "dynrt_interrupt_numbered";
    const std::string args = "--aov depth --out " + (dir / "%04d.png").string() + " --report " +
                             (dir / "r.json").string();
    const unsigned seed = 3401;
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> when(0.05, 2.5);
    for (const int signal : {SIGINT, SIGTERM, SIGINT, SIGTERM}) {
        const double seconds = when(random);
        SCOPED_TRACE("seed " + std::to_string(seed) + ", signal " + std::to_string(signal) +
                     " after " + std::to_string(seconds) + " s");
        fresh_dir("numbered");
        check_stopped_then_resume(dir, reference, signal, render_until(signal, seconds, args), args);
    }
    // And, whatever the machine's speed, once in the middle of the render: the signal is sent
    // when the journal holds two frames' records.
    for (const int signal : {SIGINT, SIGTERM}) {
        SCOPED_TRACE("signal " + std::to_string(signal) + " after two frames");
        fresh_dir("numbered");
        const std::string journal = (dir / "r.json.frames.jsonl").string();
        const ShellRun run = run_shell(
            "env " + kSlow + " " + DYNRT_CLI_PATH + kRender + " " + args + " 2>&1 & job=$!; " +
            "for i in $(seq 600); do [ \"$(wc -l < '" + journal + "' 2>/dev/null || echo 0)\" -ge 3 ] " +
            "&& break; sleep 0.05; done; kill -" + (signal == SIGINT ? "INT" : "TERM") +
            " $job; wait $job");
        EXPECT_EQ(check_stopped_then_resume(dir, reference, signal, run, args),
                  Ending::stopped_between_frames)
            << run.output;
        EXPECT_NE(run.output.find("run the same command with --resume"), std::string::npos) << run.output;
    }
}

TEST(CliInterrupt, AGifAContactSheetAndAReportStoppedAtRandomPointsAreWholeOrAbsent) {
    const unsigned seed = 3402;
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> when(0.05, 2.5);
    for (const int signal : {SIGINT, SIGTERM, SIGTERM, SIGINT}) {
        const double seconds = when(random);
        SCOPED_TRACE("seed " + std::to_string(seed) + ", signal " + std::to_string(signal) +
                     " after " + std::to_string(seconds) + " s");
        const fs::path dir = fresh_dir("gif");
        const ShellRun run = render_until(signal, seconds,
                                          "--out " + (dir / "anim.gif").string() +
                                              " --contact-sheet " + (dir / "sheet.png").string() +
                                              " --report " + (dir / "r.json").string());
        const bool stopped = expect_stopped(run, signal, dir / "r.json") != Ending::finished;
        check_files_whole(dir);
        if (!fs::exists(dir / "anim.gif")) {
            // No GIF only when no frame was done.
            EXPECT_TRUE(report_frames(dir / "r.json").empty()) << run.output;
            continue;
        }
        // The GIF holds the frames the report lists.
        auto in = OIIO::ImageInput::open((dir / "anim.gif").string());
        ASSERT_TRUE(in);
        int frames = 0;
        while (in->seek_subimage(frames, 0)) ++frames;
        if (fs::exists(dir / "r.json")) {
            EXPECT_EQ(int(report_frames(dir / "r.json").size()), frames);
        }
        if (!stopped) {
            EXPECT_EQ(frames, 8);
        }
    }
}

TEST(CliInterrupt, AVideoStoppedPartWayIsWholeOrAbsent) {
    if (run_shell("command -v ffmpeg >/dev/null && command -v ffprobe >/dev/null").exit_code != 0) {
        GTEST_SKIP() << "ffmpeg and ffprobe are not on the PATH";
    }
    const fs::path dir = fresh_dir("video");
    for (const int signal : {SIGINT, SIGTERM}) {
        fs::remove(dir / "anim.mp4");
        const ShellRun run = render_until(signal, 0.7, "--out " + (dir / "anim.mp4").string() +
                                                           " --report " + (dir / "r.json").string());
        expect_stopped(run, signal, dir / "r.json");
        for (const auto& entry : fs::directory_iterator(dir)) {
            EXPECT_EQ(entry.path().string().find(".partial"), std::string::npos) << entry.path();
        }
        if (!fs::exists(dir / "anim.mp4")) continue;
        const ShellRun probe = run_shell("ffprobe -v error -count_frames -select_streams v:0 "
                                         "-show_entries stream=nb_read_frames -of csv=p=0 '" +
                                         (dir / "anim.mp4").string() + "'");
        EXPECT_EQ(probe.exit_code, 0) << probe.output;
    }
}

}  // namespace cli_interrupt_test
}  // namespace dynrt

namespace dynrt {
namespace cli_interrupt_test {

/// A frame that cannot be written ends the render in one process with an error naming the
/// frame and the user's path; the frames before it stay whole and recorded, so --resume, once
/// the way is clear, renders only the rest.
TEST(CliWriter, AnUnwritableFrameEndsTheRenderNamingItAndResumeFinishesIt) {
    const fs::path dir = fresh_dir("unwritable");
    fs::create_directories(dir / "0005.png");  // frame 5's name is taken by a folder
    // The last frame fails: its error comes when the writer finishes, with frame 4 likely still
    // being written, whose record must not be lost.
    std::string render = kRender;
    render.replace(render.find("--frames 0-7"), 12, "--frames 0-5");
    const std::string args = "--out " + (dir / "%04d.png").string();
    const ShellRun run = run_shell(std::string("timeout 300 ") + DYNRT_CLI_PATH + render + " " + args);
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find("dynrt: error: frame 5: " + (dir / "0005.png").string() +
                              ": cannot write: is a folder"),
              std::string::npos)
        << run.output;
    const std::set<int> present = check_files_whole(dir);
    EXPECT_EQ(present, (std::set<int>{0, 1, 2, 3, 4})) << run.output;
    fs::remove(dir / "0005.png");
    const ShellRun resumed = run_shell(std::string("timeout 300 ") + DYNRT_CLI_PATH + render + " " +
                                       args + " --resume");
    EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
    EXPECT_NE(resumed.output.find("resume: 5 frames done, 1 to render"), std::string::npos)
        << resumed.output;
    EXPECT_EQ(check_files_whole(dir), (std::set<int>{0, 1, 2, 3, 4, 5}));
}

}  // namespace cli_interrupt_test
}  // namespace dynrt
