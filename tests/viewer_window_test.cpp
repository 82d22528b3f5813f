// `dynrt view`'s window, driven by a script on an Xvfb server as a user would drive it (orbit,
// change the tracer and the depth on the fly, play, step, turn the panels off): what the window
// shows, read back from it, is byte for byte the screenshot's PNG and `dynrt render`'s image
// of the same camera and settings. And the ways it cannot open: no display, a scene that
// cannot be read, a bad script: one clear line, no window, no hang. Skipped when this dynrt
// was built without its window or Xvfb is not installed.

#include "dynrt/engine/pixel_cost.h"
#include "test_files.h"
#include "shell_command.h"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using dynrt::test::run_shell;

/// The leak checker of a sanitized build would report the GL driver's own allocations.
const std::string kEnv = "timeout 300 env ASAN_OPTIONS=detect_leaks=0 ";

/// An X server of its own for this test program: Xvfb on a display numbered after the process,
/// which it names on a pipe once it accepts connections (-displayfd), so that test programs run
/// in parallel never share one (xvfb-run -a can pick the same), and which does not reset between
/// its clients (-noreset: a reset refuses connections for a moment); stopped when the program
/// ends.
class Xvfb {
public:
    Xvfb() {
        int fds[2];
        if (pipe(fds) != 0) return;
        // A display number of this process's own: one Xvfb shutting down (its lock file gone,
        // its socket not yet) must not be taken for another's.
        const std::string number = ":" + std::to_string(200 + getpid() % 20000);
        pid_ = fork();
        if (pid_ == 0) {
            close(fds[0]);
            const std::string fd = std::to_string(fds[1]);
            const int null = open("/dev/null", O_WRONLY);
            dup2(null, 1);
            dup2(null, 2);
            execlp("Xvfb", "Xvfb", number.c_str(), "-displayfd", fd.c_str(), "-screen", "0", "640x480x24", "-nolisten", "tcp", "-noreset",
                   static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        char text[32] = {};
        const ssize_t n = pid_ > 0 ? read(fds[0], text, sizeof(text) - 1) : -1;
        // Kept open while the server runs: it may write its number once more (and dies when it
        // cannot, "Cannot write display number").
        notify_ = fds[0];
        if (n <= 0) return;
        const std::string display = ":" + std::string(text, std::size_t(n) - (text[n - 1] == '\n' ? 1 : 0));
        // It names its display before it takes connections: wait until its socket answers.
        const std::string socket_path = "/tmp/.X11-unix/X" + display.substr(1);
        for (int attempt = 0; attempt < 200 && display_.empty(); ++attempt) {
            const int s = socket(AF_UNIX, SOCK_STREAM, 0);
            sockaddr_un address{};
            address.sun_family = AF_UNIX;
            std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", socket_path.c_str());
            if (connect(s, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0) display_ = display;
            close(s);
            if (display_.empty()) usleep(25000);
        }
    }
    ~Xvfb() {
        if (notify_ >= 0) close(notify_);
        if (pid_ > 0) {
            kill(pid_, SIGTERM);
            waitpid(pid_, nullptr, 0);
        }
    }
    Xvfb(const Xvfb&) = delete;
    Xvfb& operator=(const Xvfb&) = delete;

    /// ":N", or empty when no server could be started (Xvfb not installed).
    const std::string& display() const { return display_; }

    static const Xvfb& shared() {
        static const Xvfb server;
        return server;
    }

private:
    pid_t pid_ = -1;
    int notify_ = -1;
    std::string display_;
};

/// The command prefix that runs on the shared X server.
std::string on_xvfb() { return kEnv + "DISPLAY=" + Xvfb::shared().display() + " "; }

std::vector<unsigned char> pixels_of(const fs::path& png) {
    auto in = OIIO::ImageInput::open(png.string());
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<unsigned char> bytes(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, bytes.data());
    return bytes;
}

bool has_xvfb() { return !Xvfb::shared().display().empty(); }

TEST(ViewerWindow, AScriptedSessionShowsWhatRenderWrites) {
#ifndef DYNRT_HAVE_VIEWER
    GTEST_SKIP() << "built without the viewer's window (GLFW, Dear ImGui)";
#else
    if (!has_xvfb()) GTEST_SKIP() << "Xvfb is not installed";
    const fs::path dir = dynrt::test::fresh_test_dir("viewer_window");
    const fs::path script = dir / "script.txt";
    {
        std::ofstream out(script);
        out << "0 wait-frames 2\n"
               "0 orbit 35 -8\n"
               "0 zoom 1.2\n"
               "0 set tracer single\n"
               "0 set depth 2\n"
               "0 play\n"
               "0 wait-frames 5\n"
               "0 step 1\n"
               "0 overlay off\n"
               "0 wait-frames 2\n"
               "0 screenshot " << (dir / "shot.png").string() << "\n"
               "0 capture " << (dir / "window.png").string() << "\n"
               "0 overlay on\n"
               "0 wait-frames 1\n"
               "0 capture " << (dir / "panels.png").string() << "\n"
               "0 quit\n";
    }
    const std::string scene = "'plane:2@0,-1,0,4#c0c0c0+sphere:600@0,0,0,0.7#e04020'";
    const auto run = run_shell(on_xvfb() + DYNRT_CLI_PATH + " view " + scene +
                               " --res 160x120 --anim rigid --script " + script.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    // The screenshot's report names its camera and frame.
    std::ifstream json_file(dir / "shot.json");
    const nlohmann::json shot = nlohmann::json::parse(json_file);
    const std::string camera = shot.at("camera");
    const int frame = shot.at("frame");
    EXPECT_GT(frame, 0) << "it played";
    const auto render = run_shell(kEnv + DYNRT_CLI_PATH + " render " + scene + " --res 160x120 --anim rigid --tracer single "
                                  "--depth 2 --frames " + std::to_string(frame) + " --camera '" + camera + "' --out " +
                                  (dir / "render.png").string() + " -q");
    ASSERT_EQ(render.exit_code, 0) << render.output;
    const std::vector<unsigned char> window = pixels_of(dir / "window.png"), screenshot = pixels_of(dir / "shot.png"),
                                     rendered = pixels_of(dir / "render.png"), panels = pixels_of(dir / "panels.png");
    ASSERT_EQ(window.size(), std::size_t(160 * 120 * 3));
    EXPECT_TRUE(window == screenshot) << "the window does not show the frame's image";
    EXPECT_TRUE(window == rendered) << "the viewer's frame is not dynrt render's";
    // The panels draw over the image.
    EXPECT_FALSE(panels == window);
#endif
}

TEST(ViewerWindow, AStillViewRefinesToWhatRenderWritesWithItsSamples) {
#ifndef DYNRT_HAVE_VIEWER
    GTEST_SKIP() << "built without the viewer's window (GLFW, Dear ImGui)";
#else
    if (!has_xvfb()) GTEST_SKIP() << "Xvfb is not installed";
    const fs::path dir = dynrt::test::fresh_test_dir("viewer_refine");
    const fs::path script = dir / "script.txt";
    std::ofstream(script) << "0 orbit -20 10\n0 wait-still\n0 overlay off\n0 screenshot " << (dir / "shot.png").string()
                          << "\n0 capture " << (dir / "window.png").string() << "\n0 quit\n";
    const std::string scene = "'plane:2@0,-1,0,4#c0c0c0+sphere:600@0,0,0,0.7#e04020'";
    const auto run = run_shell(on_xvfb() + DYNRT_CLI_PATH + " view " + scene + " --res 96x72 --spp 4 --script " + script.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::ifstream json_file(dir / "shot.json");
    const std::string camera = nlohmann::json::parse(json_file).at("camera");
    const auto render = run_shell(kEnv + DYNRT_CLI_PATH + " render " + scene + " --res 96x72 --spp 4 --camera '" + camera +
                                  "' --out " + (dir / "render.png").string() + " -q");
    ASSERT_EQ(render.exit_code, 0) << render.output;
    const std::vector<unsigned char> window = pixels_of(dir / "window.png");
    ASSERT_EQ(window.size(), std::size_t(96 * 72 * 3));
    EXPECT_TRUE(window == pixels_of(dir / "shot.png"));
    EXPECT_TRUE(window == pixels_of(dir / "render.png")) << "not refined to --spp 4's image";
#endif
}

// The window resized: the image follows it and is still `dynrt render`'s at the new size; the
// cost view shows the heat map of the pixel costs `dynrt render --aov cost` writes.
TEST(ViewerWindow, AResizedWindowAndItsCostViewShowWhatRenderWrites) {
#ifndef DYNRT_HAVE_VIEWER
    GTEST_SKIP() << "built without the viewer's window (GLFW, Dear ImGui)";
#else
    if (!has_xvfb()) GTEST_SKIP() << "Xvfb is not installed";
    const fs::path dir = dynrt::test::fresh_test_dir("viewer_resize");
    const fs::path script = dir / "script.txt";
    std::ofstream(script) << "0 overlay off\n0 resize 120 80\n0 wait-frames 1\n0 screenshot " << (dir / "shot.png").string()
                          << "\n0 capture " << (dir / "window.png").string() << "\n0 set view triangles\n0 set cost-scale 40\n"
                          << "0 wait-frames 1\n0 capture " << (dir / "cost.png").string() << "\n0 quit\n";
    const std::string scene = "'plane:2@0,-1,0,4#c0c0c0+sphere:600@0,0,0,0.7#e04020'";
    const auto run = run_shell(on_xvfb() + DYNRT_CLI_PATH + " view " + scene + " --res 64x48 --script " + script.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::ifstream json_file(dir / "shot.json");
    const std::string camera = nlohmann::json::parse(json_file).at("camera");
    const auto render = run_shell(kEnv + DYNRT_CLI_PATH + " render " + scene + " --res 120x80 --camera '" + camera +
                                  "' --aov cost --out " + (dir / "render.png").string() + " -q");
    ASSERT_EQ(render.exit_code, 0) << render.output;
    const std::vector<unsigned char> window = pixels_of(dir / "window.png");
    ASSERT_EQ(window.size(), std::size_t(120 * 80 * 3)) << "the window was not resized";
    EXPECT_TRUE(window == pixels_of(dir / "shot.png"));
    EXPECT_TRUE(window == pixels_of(dir / "render.png")) << "not dynrt render's image at the new size";
    // The heat map of the render's triangle counts, white at 40.
    auto in = OIIO::ImageInput::open((dir / "render.cost.exr").string());
    ASSERT_TRUE(in);
    std::vector<float> counts(std::size_t(120 * 80 * 2));
    ASSERT_TRUE(in->read_image(0, 0, 0, 2, OIIO::TypeDesc::FLOAT, counts.data()));
    std::vector<dynrt::PixelCost> costs(std::size_t(120 * 80));
    for (std::size_t i = 0; i < costs.size(); ++i) {
        costs[i] = dynrt::PixelCost{std::uint32_t(counts[2 * i]), std::uint32_t(counts[2 * i + 1])};
    }
    const std::vector<std::uint8_t> heat = dynrt::cost_heat_rgb8(costs, dynrt::CostMeasure::triangles, 40);
    EXPECT_TRUE(pixels_of(dir / "cost.png") == std::vector<unsigned char>(heat.begin(), heat.end()))
        << "the cost view is not the heat map of render --aov cost";
#endif
}

TEST(ViewerWindow, WhereItCannotOpenItSaysWhyInOneLine) {
#ifndef DYNRT_HAVE_VIEWER
    const auto built_without = run_shell(std::string(DYNRT_CLI_PATH) + " view sphere:10");
    EXPECT_EQ(built_without.exit_code, 1);
    EXPECT_NE(built_without.output.find("built without its window"), std::string::npos) << built_without.output;
#else
    // No display.
    const auto headless = run_shell(std::string("timeout 60 env -u DISPLAY -u WAYLAND_DISPLAY ") + DYNRT_CLI_PATH + " view sphere:10");
    EXPECT_EQ(headless.exit_code, 1) << headless.output;
    EXPECT_NE(headless.output.find("no display available"), std::string::npos) << headless.output;
    if (!has_xvfb()) GTEST_SKIP() << "Xvfb is not installed";
    const std::string xvfb = on_xvfb();
    // A scene that cannot be read: the render command's error.
    const auto missing = run_shell(xvfb + DYNRT_CLI_PATH + " view /no/such/scene.gltf");
    EXPECT_EQ(missing.exit_code, 1) << missing.output;
    EXPECT_NE(missing.output.find("/no/such/scene.gltf"), std::string::npos) << missing.output;
    // A bad script: its line, before the window opens; a bad setting in it: its line too.
    const fs::path dir = dynrt::test::fresh_test_dir("viewer_errors");
    { std::ofstream(dir / "bad.txt") << "0 orbit 10 10\n0 spin\n"; }
    const auto bad = run_shell(xvfb + DYNRT_CLI_PATH + " view sphere:10 --res 32x32 --script " + (dir / "bad.txt").string());
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_NE(bad.output.find("line 2: unknown command 'spin'"), std::string::npos) << bad.output;
    { std::ofstream(dir / "setting.txt") << "0 set tracer laser\n"; }
    const auto setting = run_shell(xvfb + DYNRT_CLI_PATH + " view sphere:10 --res 32x32 --script " + (dir / "setting.txt").string());
    EXPECT_EQ(setting.exit_code, 1);
    EXPECT_NE(setting.output.find("line 1: tracer 'laser'"), std::string::npos) << setting.output;
#endif
}

}  // namespace
