// `mpirun dynrt render` (engine/cli/distributed): runs the CLI under Open MPI's mpirun with 1, 2
// and 3 processes on this machine (--oversubscribe) and checks that images and AOVs are the
// bits of a render in one process, in both modes; that the hand-out gives a slow rank's frames
// to the others; that a job killed part way resumes with no frame lost or rendered twice; and
// that a rank failing on a frame stops the job naming the rank and the frame. Skipped, with
// the reason, when dynrt was built without MPI or mpirun is missing. The three tests driven by
// sleeps (slow frames, a job stopped part way, a rank killed) are Heavy: like the other Heavy*
// cases they run in the optimised build only, since the sanitizer run's processes start several
// times slower and those paths are also run by the resume test without mpirun.

#include "test_files.h"
#include "shell_command.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace dynrt {
namespace mpi_render_test {

namespace fs = std::filesystem;

using test::run_shell;
using test::ShellRun;

/// Why the MPI runs cannot be tested here, or empty when they can.
std::string why_skipped() {
#ifndef DYNRT_HAVE_MPI
    return "dynrt was built without MPI (install Open MPI: bash scripts/install-deps.sh)";
#else
    if (run_shell("command -v mpirun").exit_code != 0) return "mpirun is not on the PATH";
    return {};
#endif
}

#define SKIP_WITHOUT_MPI()                                   \
    do {                                                     \
        const std::string why = why_skipped();               \
        if (!why.empty()) GTEST_SKIP() << why;               \
    } while (false)

// Three objects moving three ways over a floor that takes their shadows; 72x40 has clipped
// edge tiles on both axes.
const std::string kScene =
    "'plane:8@0,-1,0,4#808080+sphere:600@-0.8,-0.4,0.3,0.6#e04020+sphere:300@1.2,-0.5,-0.6,0.5#2050e0"
    "+soup:600@-0.6,-1,-2,1.4#40c060' --anim rigid:sphere:600@-0.8,-0.4,0.3,0.6#e04020 "
    "--anim wave:sphere:300@1.2,-0.5,-0.6,0.5#2050e0 --anim explode:soup:600@-0.6,-1,-2,1.4#40c060 "
    "--res 72x40 --threads 1";

/// `dynrt render` of kScene with `args`, under mpirun with `ranks` processes (0: no mpirun).
/// `env` ("NAME=VALUE ...") is set for it.
std::string render_command(int ranks, const std::string& args, const std::string& env = "") {
    std::string command = "timeout 120 env " + env + " ";
    if (ranks > 0) {
        // Root may run mpirun in a container; leak checks see Open MPI's own allocations.
        command += "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun "
                   "--oversubscribe -np " + std::to_string(ranks) + " ";
#ifdef DYNRT_SANITIZED_CLI
        command += "-x ASAN_OPTIONS=detect_leaks=0 ";
#endif
    }
    return command + DYNRT_CLI_PATH + " render " + kScene + " " + args;
}

fs::path fresh_dir(const std::string& name) { return test::fresh_test_dir("mpi_" + name); }

/// The pixels of an image file as floats, bit for bit.
std::vector<float> pixels_of(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> pixels(std::size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) return {};
    return pixels;
}

const char* const kAovs[] = {"depth", "object", "prim", "normal"};

/// Every frame's image and AOVs in `dir` equal those in `expected`, pixel bits compared.
void expect_same_frames(const fs::path& dir, const fs::path& expected, int first, int last) {
    for (int f = first; f <= last; ++f) {
        char name[16];
        std::snprintf(name, sizeof name, "%04d", f);
        std::vector<std::string> files{std::string(name) + ".png"};
        for (const char* aov : kAovs) files.push_back(std::string(name) + "." + aov + ".exr");
        for (const std::string& file : files) {
            const std::vector<float> a = pixels_of(dir / file), b = pixels_of(expected / file);
            ASSERT_FALSE(b.empty()) << expected / file;
            EXPECT_TRUE(a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * 4) == 0)
                << dir / file << " differs from the single-process render";
        }
    }
}

/// The whole frame records of a journal (after its header line).
std::vector<nlohmann::json> journal_records(const fs::path& path) {
    std::vector<nlohmann::json> records;
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        // A line torn by a kill is not a record (dynrt skips it too).
        const nlohmann::json record = nlohmann::json::parse(line, nullptr, false);
        if (!record.is_discarded()) records.push_back(record);
    }
    return records;
}

const std::string kOut = " --aov depth,object,prim,normal --out ";

/// The numbers of processes the equality tests run. Under the sanitizers, whose processes start
/// several times slower, one of each mode: what they look for (memory errors) does not depend
/// on the count, and the optimised run covers every count.
#ifdef DYNRT_SANITIZED_CLI
const std::vector<int> kFramesRanks{3};
const std::vector<int> kTilesRanks{2};
#else
const std::vector<int> kFramesRanks{1, 2, 3};
const std::vector<int> kTilesRanks{2, 3};
#endif

/// The single-process render of frames 0-`last` the runs of the same frames are compared with
/// (made once per test program). The same range: the default camera frames the scene over it.
fs::path reference_frames(int last) {
    static std::map<int, fs::path> made;
    if (made.contains(last)) return made[last];
    // Per process: the test program's shards run side by side, each making its own.
    const fs::path dir = fresh_dir("reference_" + std::to_string(last) + "_" + std::to_string(getpid()));
    const ShellRun run = run_shell(render_command(0, "--frames 0-" + std::to_string(last) + kOut +
                                                    (dir / "%04d.png").string()));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return made[last] = dir;
}

TEST(MpiRender, FramesHandedOutMatchOneProcessOnOneTwoAndThreeRanks) {
    SKIP_WITHOUT_MPI();
    const fs::path expected = reference_frames(9);
    for (const int ranks : kFramesRanks) {
        SCOPED_TRACE(std::to_string(ranks) + " ranks");
        const fs::path dir = fresh_dir("frames_" + std::to_string(ranks));
        const ShellRun run = run_shell(render_command(ranks, "--frames 0-9" + kOut + (dir / "%04d.png").string() +
                                                            " --report " + (dir / "r.json").string()));
        ASSERT_EQ(run.exit_code, 0) << run.output;
        expect_same_frames(dir, expected, 0, 9);
        std::ifstream report(dir / "r.json");
        const nlohmann::json doc = nlohmann::json::parse(report);
        ASSERT_EQ(doc["frames"].size(), 10u);
        std::set<int> ranks_seen;
        for (int f = 0; f < 10; ++f) {
            EXPECT_EQ(doc["frames"][f]["frame"], f);
            const int rank = doc["frames"][f]["rank"];
            EXPECT_TRUE(rank >= 0 && rank < ranks) << rank;
            ranks_seen.insert(rank);
            EXPECT_TRUE(doc["frames"][f].contains("handout_ms"));
        }
        EXPECT_EQ(journal_records(dir / "r.json.frames.jsonl").size(), 10u);
        EXPECT_NE(run.output.find("rank 0: "), std::string::npos) << run.output;
        if (ranks == 1) {
            EXPECT_NE(run.output.find("rank 0: 10 frames in 1 run (0-9)"), std::string::npos) << run.output;
        }
    }
}

TEST(MpiRender, SharedTilesMatchOneProcessOnTwoAndThreeRanks) {
    SKIP_WITHOUT_MPI();
    const fs::path expected = reference_frames(9);
    for (const int ranks : kTilesRanks) {
        SCOPED_TRACE(std::to_string(ranks) + " ranks");
        const fs::path dir = fresh_dir("tiles_" + std::to_string(ranks));
        const ShellRun run = run_shell(render_command(ranks, "--distribute tiles --frames 0-9" + kOut +
                                                            (dir / "%04d.png").string() + " --report " +
                                                            (dir / "r.json").string()));
        ASSERT_EQ(run.exit_code, 0) << run.output;
        expect_same_frames(dir, expected, 0, 9);
        std::ifstream report(dir / "r.json");
        const nlohmann::json doc = nlohmann::json::parse(report);
        ASSERT_EQ(doc["frames"].size(), 10u);
        for (const nlohmann::json& frame : doc["frames"]) {
            EXPECT_EQ(frame["rank_trace_ms"].size(), std::size_t(ranks));
            EXPECT_GE(frame["gather_ms"].get<double>(), 0.0);
            // The shares' rays add up to the whole image's.
            EXPECT_EQ(frame["pixels_traced"].get<int>() + frame["pixels_shadows_retraced"].get<int>() +
                          frame["pixels_reused"].get<int>(),
                      72 * 40);
        }
    }
}

TEST(MpiRender, HeavyASlowRanksFramesGoToTheOthers) {
    SKIP_WITHOUT_MPI();
    // Frames 0 and 1 take 0.8 s longer each: whoever gets the first run (frames 0-2) is busy
    // for 1.6 s, while the other renders the 9 frames left.
    const fs::path dir = fresh_dir("uneven");
    const ShellRun run = run_shell(render_command(2, "--frames 0-11 --out " + (dir / "%04d.png").string() +
                                                    " --report " + (dir / "r.json").string(),
                                             "DYNRT_TEST_SLOW_FRAMES=0:800,1:800"));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::ifstream report(dir / "r.json");
    const nlohmann::json doc = nlohmann::json::parse(report);
    ASSERT_EQ(doc["frames"].size(), 12u);
    const int slow_rank = doc["frames"][0]["rank"];
    int slow_rank_frames = 0;
    for (const nlohmann::json& frame : doc["frames"]) slow_rank_frames += frame["rank"] == slow_rank;
    EXPECT_EQ(doc["frames"][1]["rank"], slow_rank);
    EXPECT_EQ(slow_rank_frames, 3) << run.output;
}

/// Starts `command` in the background, waits until `journal` holds `records` frame records,
/// runs `then` (shell) and waits for the job and for every dynrt process writing into
/// `folder_name` to be gone (mpirun may return before its ranks). Returns the job's status.
ShellRun run_until_records(const std::string& command, const fs::path& journal, int records,
                           const std::string& then, const std::string& folder_name) {
    const std::string ranks_pattern = "'^[^ ]*/dynrt render .*" + folder_name + "/'";
    return run_shell(
        command + " > /dev/null & job=$!; for i in $(seq 600); do [ \"$(cat '" + journal.string() +
        "' 2>/dev/null | wc -l)\" -ge " + std::to_string(records + 1) + " ] && break; sleep 0.1; done; " +
        then + "; wait $job; status=$?; for i in $(seq 300); do pgrep -f " + ranks_pattern +
        " > /dev/null || break; sleep 0.1; done; exit $status");
}

TEST(MpiRender, HeavyAJobKilledPartWayResumesWithNoFrameLostOrRenderedTwice) {
    SKIP_WITHOUT_MPI();
    const fs::path expected = reference_frames(9);
    const fs::path dir = fresh_dir("resume");
    std::string slow;
    for (int f = 0; f < 10; ++f) slow += (f ? "," : "") + std::to_string(f) + ":400";
    const std::string args = "--frames 0-9" + kOut + (dir / "%04d.png").string() + " --report " +
                             (dir / "r.json").string();
    // 10 frames of 0.4 s on 2 ranks take 2 s: the job is stopped (SIGTERM, which mpirun
    // passes on to its ranks) once the journal holds two records, whatever the machine's speed.
    const fs::path journal = dir / "r.json.frames.jsonl";
    const ShellRun killed = run_until_records(render_command(2, args, "DYNRT_TEST_SLOW_FRAMES=" + slow),
                                              journal, 2, "kill -TERM $job", "dynrt_mpi_resume");
    ASSERT_NE(killed.exit_code, 0) << killed.output;
    const std::vector<nlohmann::json> before = journal_records(dir / "r.json.frames.jsonl");
    ASSERT_LT(before.size(), 10u) << "the job finished before it was killed";
    ASSERT_GT(before.size(), 0u) << "the job was killed before its first frame: " << killed.output;
    const ShellRun resumed = run_shell(render_command(2, args + " --resume"));
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    EXPECT_NE(resumed.output.find("resume: " + std::to_string(before.size()) + " frames done, " +
                                  std::to_string(10 - before.size()) + " to render"),
              std::string::npos)
        << resumed.output;
    // Each frame recorded once over both runs: none lost, none rendered again once recorded.
    std::multiset<int> recorded;
    for (const nlohmann::json& record : journal_records(dir / "r.json.frames.jsonl")) {
        recorded.insert(record.at("frame").get<int>());
    }
    for (int f = 0; f < 10; ++f) EXPECT_EQ(recorded.count(f), 1u) << "frame " << f;
    EXPECT_EQ(recorded.size(), 10u);
    expect_same_frames(dir, expected, 0, 9);
    // No temporary file of a frame killed while being written is left behind.
    for (const auto& entry : fs::directory_iterator(dir)) {
        EXPECT_EQ(entry.path().string().find(".partial"), std::string::npos) << entry.path();
    }
    std::ifstream report(dir / "r.json");
    EXPECT_EQ(nlohmann::json::parse(report)["frames"].size(), 10u);
}

TEST(MpiRender, HeavyARankKilledFromOutsideEndsTheJobAndResumeFinishesIt) {
    SKIP_WITHOUT_MPI();
    const fs::path dir = fresh_dir("dead");
    std::string slow;
    for (int f = 0; f < 10; ++f) slow += (f ? "," : "") + std::to_string(f) + ":400";
    const std::string args = "--frames 0-9 --out " + (dir / "%04d.png").string();
    const fs::path journal = dir / ".dynrt-frames.jsonl";
    // One rank dies (SIGKILL, as a crashed node would) once a frame is recorded: the job must
    // end, not hang (the command's timeout would exit 124).
    const ShellRun killed = run_until_records(
        render_command(2, args, "DYNRT_TEST_SLOW_FRAMES=" + slow), journal, 1,
        "pkill -KILL -n -f '^[^ ]*/dynrt render .*dynrt_mpi_dead/'", "dynrt_mpi_dead");
    EXPECT_NE(killed.exit_code, 0) << killed.output;
    EXPECT_NE(killed.exit_code, 124) << "the job hung: " << killed.output;
    const std::size_t done = journal_records(journal).size();
    EXPECT_LT(done, 10u);
    const ShellRun resumed = run_shell(render_command(2, args + " --resume"));
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    std::multiset<int> recorded;
    for (const nlohmann::json& record : journal_records(journal)) recorded.insert(record.at("frame").get<int>());
    for (int f = 0; f < 10; ++f) EXPECT_EQ(recorded.count(f), 1u) << "frame " << f;
}

TEST(MpiRender, ARankFailingOnAFrameStopsTheJobNamingRankAndFrame) {
    SKIP_WITHOUT_MPI();
    for (const std::string mode : {"frames", "tiles"}) {
        SCOPED_TRACE(mode);
        const fs::path dir = fresh_dir("fail_" + mode);
        // Frame 5's image cannot be written: its name is taken by a folder.
        fs::create_directories(dir / "0005.png");
        const ShellRun run = run_shell(render_command(2, "--distribute " + mode + " --frames 0-9 --out " +
                                                        (dir / "%04d.png").string()));
        EXPECT_NE(run.exit_code, 0) << run.output;
        EXPECT_NE(run.exit_code, 124) << "the job hung: " << run.output;
        EXPECT_NE(run.output.find(", frame 5: "), std::string::npos) << run.output;
        EXPECT_NE(run.output.find("dynrt: error: rank "), std::string::npos) << run.output;
        EXPECT_NE(run.output.find("0005.png: cannot write: is a folder"), std::string::npos) << run.output;
    }
}

TEST(MpiRender, ResumeWorksInOneProcessWithoutMpirun) {
    // No MPI needed: --resume alone runs the same driver with this process as the only rank.
    const fs::path dir = fresh_dir("resume_local");
    const std::string args = "--frames 0-3 --out " + (dir / "%04d.png").string();
    const ShellRun first = run_shell(render_command(0, args + " --resume"));
    ASSERT_EQ(first.exit_code, 0) << first.output;
    EXPECT_NE(first.output.find("resume: 0 frames done, 4 to render"), std::string::npos) << first.output;
    fs::remove(dir / "0002.png");  // a frame whose image went missing is rendered again
    const ShellRun second = run_shell(render_command(0, args + " --resume"));
    ASSERT_EQ(second.exit_code, 0) << second.output;
    EXPECT_NE(second.output.find("resume: 3 frames done, 1 to render"), std::string::npos) << second.output;
    EXPECT_TRUE(fs::exists(dir / "0002.png"));
    // The same frames with AOVs are another job: its journal is not this one's.
    const ShellRun other = run_shell(render_command(0, args + " --aov depth --resume"));
    EXPECT_EQ(other.exit_code, 2) << other.output;
    EXPECT_NE(other.output.find("rendered with --aov 'none', not 'depth'"), std::string::npos) << other.output;
}

/// A resume with any setting that changes a pixel refused, naming the setting, both values and
/// what to do, with no frame of the job touched (the issue's --camera, --clip, --light,
/// --normals and --depth; --clip is in job_settings_test.cpp, as kScene has no clips).
TEST(MpiRender, ResumeWithOtherSettingsIsRefusedNamingTheSetting) {
    const fs::path dir = fresh_dir("resume_mix");
    const std::string args = "--frames 0-1 --out " + (dir / "%04d.png").string();
    const ShellRun first = run_shell(render_command(0, args + " --resume"));
    ASSERT_EQ(first.exit_code, 0) << first.output;
    fs::remove(dir / "0001.png");  // left to render
    const auto time_of = [&] { return fs::last_write_time(dir / "0000.png"); };
    const fs::file_time_type before = time_of();
    const std::vector<std::pair<std::string, std::string>> changes = {
        {"--camera eye=0,1,6", "--camera 'default', not 'eye=0,1,6'"},
        {"--light 1,2,3", "--light 'default', not '1,2,3,1'"},
        {"--normals flat", "--normals 'smooth', not 'flat'"},
        {"--depth 2", "--depth '5', not '2'"}};
    for (const auto& [flag, expected] : changes) {
        const ShellRun run = run_shell(render_command(0, args + " --resume " + flag));
        SCOPED_TRACE(flag);
        EXPECT_EQ(run.exit_code, 2) << run.output;
        EXPECT_NE(run.output.find("dynrt: error: --resume: this job was rendered with " + expected +
                                  "; render without --resume to start afresh, or resume with the same flags"),
                  std::string::npos) << run.output;
        EXPECT_FALSE(fs::exists(dir / "0001.png")) << "a frame of other settings joined the job";
    }
    EXPECT_EQ(time_of(), before);
    // The same flags finish it, however the work is shared (not part of the job).
    const ShellRun same = run_shell(render_command(0, args + " --resume --distribute tiles"));
    ASSERT_EQ(same.exit_code, 0) << same.output;
    EXPECT_NE(same.output.find("resume: 1 frames done, 1 to render"), std::string::npos) << same.output;
}

/// A scene file edited since the job began is named as such (a BART file and its include).
TEST(MpiRender, ResumeAfterTheSceneFileChangedIsRefusedNamingTheFile) {
    const fs::path dir = fresh_dir("resume_scene_file");
    std::ofstream(dir / "main.aff") << "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\n"
                                       "resolution 16 16\nl 0 5 5\n"
                                       "fm 0.1 0.1 0.1 0.8 0.2 0.2 0 0 0 1 0 1\ni part.aff\n";
    std::ofstream(dir / "part.aff") << "p 3\n-1 -1 0\n1 -1 0\n0 1 0\n";
    const std::string command = std::string("timeout 120 ") + DYNRT_CLI_PATH + " render '" +
                                (dir / "main.aff").string() + "' --frames 0-1 --out '" +
                                (dir / "%d.png").string() + "' --resume";
    const ShellRun first = run_shell(command);
    ASSERT_EQ(first.exit_code, 0) << first.output;
    std::ofstream(dir / "part.aff") << "p 3\n-1 -1 0\n1 -1 0\n0 2 0\n";
    const ShellRun changed = run_shell(command);
    EXPECT_EQ(changed.exit_code, 2) << changed.output;
    EXPECT_NE(changed.output.find("--resume: the scene's file " + (dir / "part.aff").string() +
                                  " has changed since this job was rendered"),
              std::string::npos) << changed.output;
}

}  // namespace mpi_render_test
}  // namespace dynrt
