// `dynrt view`'s model without its window (engine/viewer/): the orbit camera's moves and its
// --camera text read back exactly, the script's parsing and its errors, and the session: its
// frames are the Renderer's for the same camera and settings, a setting changed on the fly
// keeps the trees and gives the image a fresh renderer with that setting gives, a bad one
// changes nothing, and the clock steps, seeks, plays and loops as documented.

#include "dynrt/engine/camera.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include "gltf_test_file.h"
#include "orbit_camera.h"
#include "render_worker.h"
#include "script_runner.h"
#include "viewer_script.h"
#include "viewer_session.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <thread>
#include <stdexcept>
#include <string>

namespace dynrt::viewer {
namespace {

Camera start_camera() {
    Camera c;
    c.eye = glm::vec3(1.0f, 2.0f, 6.0f);
    c.target = glm::vec3(0.5f, 0.0f, -1.0f);
    c.fov_y_deg = 50.0f;
    return c;
}

TEST(OrbitCamera, OrbitsPansZoomsAndFliesAroundItsTarget) {
    OrbitCamera camera(start_camera());
    const float distance = glm::length(start_camera().eye - start_camera().target);
    EXPECT_NEAR(glm::length(camera.camera().eye - start_camera().eye), 0.0f, 1e-4f);
    camera.orbit(90.0f, 0.0f);
    EXPECT_NEAR(glm::length(camera.camera().eye - camera.camera().target), distance, 1e-4f);
    EXPECT_GT(glm::length(camera.camera().eye - start_camera().eye), 1.0f);
    camera.orbit(0.0f, 500.0f);  // held short of straight up
    const glm::vec3 d = glm::normalize(camera.camera().eye - camera.camera().target);
    EXPECT_NEAR(d.y, std::sin(89.0f * 3.14159265f / 180.0f), 1e-4f);
    const glm::vec3 before = camera.camera().target;
    camera.pan(0.1f, 0.0f);
    EXPECT_NEAR(glm::length(camera.camera().target - before), 0.1f * distance, 1e-4f);
    camera.zoom(2.0f);
    EXPECT_NEAR(glm::length(camera.camera().eye - camera.camera().target), 0.5f * distance, 1e-4f);
    camera.zoom(1e9f);  // not through the target
    EXPECT_GT(glm::length(camera.camera().eye - camera.camera().target), 0.0f);
    const glm::vec3 target = camera.camera().target;
    camera.fly(0.0f, 0.0f, 1.0f);
    EXPECT_GT(camera.camera().target.y, target.y);
    Camera same = start_camera();
    same.eye = same.target;
    EXPECT_THROW(OrbitCamera{same}, std::invalid_argument);
}

TEST(OrbitCamera, ItsCameraTextReadsBackToTheSameFloats) {
    OrbitCamera camera(start_camera());
    camera.orbit(33.3f, -12.7f);
    camera.pan(0.013f, -0.021f);
    const Camera c = camera.camera();
    const Camera back = parse_camera(camera.camera_text(), Camera{});
    EXPECT_EQ(back.eye, c.eye);
    EXPECT_EQ(back.target, c.target);
    EXPECT_EQ(back.up, c.up);
    EXPECT_EQ(back.fov_y_deg, c.fov_y_deg);
}

TEST(ViewerScript, ParsesTimedCommandsAndNamesTheLineOfAMistake) {
    const auto commands = parse_script("# a demo\n0 orbit 30 -10\n\n0.5 set tracer single  # the other tracer\n1 quit\n", "demo");
    ASSERT_EQ(commands.size(), 3u);
    EXPECT_EQ(commands[0].name, "orbit");
    EXPECT_EQ(commands[0].args, (std::vector<std::string>{"30", "-10"}));
    EXPECT_EQ(commands[1].at_seconds, 0.5);
    EXPECT_EQ(commands[1].line, 4);
    const auto refused = [](const std::string& text, const std::string& fragment) {
        try {
            parse_script(text, "s.txt");
            ADD_FAILURE() << "accepted: " << text;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    refused("0 spin 3\n", "script s.txt, line 1: unknown command 'spin'");
    refused("0 play\nsoon quit\n", "line 2: 'soon' is not a time");
    refused("1 play\n0.5 pause\n", "line 2: its time 0.5 is before the line above's");
    refused("0 orbit 30\n", "'orbit' takes 2 argument(s), not 1");
    refused("-1 play\n", "not a time");
    refused("0\n", "a time with no command");
}

ViewArgs small_args(const std::string& scene = "plane:2@0,-1,0,4#808080+sphere:400@0,0,0,0.7#e04020") {
    ViewArgs args;
    args.scene = scene;
    args.res = "64x48";
    args.reuse = "off";
    return args;
}

TEST(ViewerSession, FramesAreTheRenderersForTheSameCameraAndSettings) {
    ViewerSession session(small_args());
    session.camera().orbit(25.0f, 10.0f);
    const RenderedFrame& shown = session.render();
    Renderer renderer(session.options());
    RenderedFrame want;
    renderer.render(session.scene(), session.camera().camera(), 0, want);
    EXPECT_EQ(shown.color, want.color);
    EXPECT_EQ(session.display_bytes().size(), std::size_t(64 * 48 * 3));
    EXPECT_EQ(session.history().size(), 1u);
}

TEST(ViewerSession, ASettingChangedOnTheFlyKeepsTheTreesAndGivesItsImage) {
    ViewerSession session(small_args());
    session.render();
    session.set("depth", "0");
    session.set("tracer", "single");
    const RenderedFrame& shown = session.render();
    EXPECT_EQ(shown.stats.objects_rebuilt, 0u) << "the trees were built again";
    RenderOptions options = session.options();
    EXPECT_EQ(options.tracer, Tracer::single);
    EXPECT_EQ(options.secondary.max_depth, 0);
    Renderer fresh(options);
    RenderedFrame want;
    fresh.render(session.scene(), session.camera().camera(), 0, want);
    EXPECT_EQ(shown.color, want.color);
    // A bad value or an unknown setting is refused, naming it, and changes nothing.
    const auto settings = session.settings();
    EXPECT_THROW(session.set("tracer", "laser"), std::invalid_argument);
    EXPECT_THROW(session.set("depth", "deep"), std::invalid_argument);
    EXPECT_THROW(session.set("depth", "65"), std::invalid_argument);
    try {
        session.set("gamma", "2");
        ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("unknown setting 'gamma'"), std::string::npos) << e.what();
    }
    EXPECT_EQ(session.settings(), settings);
}

// The cost view: the heat map of the renderer's own pixel costs for the same frame, its legend,
// a screenshot of what is shown, and back to the image without rebuilding anything.
TEST(ViewerSession, TheCostViewShowsTheFramesPixelCostsAsAHeatMap) {
    ViewerSession session(small_args());
    EXPECT_TRUE(session.display_bytes().empty());  // nothing rendered yet
    session.render();
    EXPECT_TRUE(session.legend().empty());
    session.set("view", "nodes");
    EXPECT_TRUE(session.options().pixel_cost);
    const RenderedFrame& shown = session.render();
    EXPECT_EQ(shown.stats.objects_rebuilt, 0u);
    ASSERT_EQ(shown.cost.size(), std::size_t(64 * 48));
    RenderOptions options = session.options();
    Renderer fresh(options);
    RenderedFrame want;
    fresh.render(session.scene(), session.camera().camera(), 0, want);
    ASSERT_EQ(want.cost, shown.cost);
    const std::uint32_t scale = cost_scale(want.cost, CostMeasure::nodes);
    const std::vector<std::uint8_t> heat = cost_heat_rgb8(want.cost, CostMeasure::nodes, scale);
    EXPECT_EQ(session.display_bytes(), std::vector<unsigned char>(heat.begin(), heat.end()));
    EXPECT_NE(session.legend().find("node visits per pixel: black 0, white " + std::to_string(scale)), std::string::npos)
        << session.legend();
    // A fixed white, and the triangle count.
    session.set("cost-scale", "7");
    session.set("view", "triangles");
    session.render();
    const std::vector<std::uint8_t> triangles = cost_heat_rgb8(want.cost, CostMeasure::triangles, 7);
    EXPECT_EQ(session.display_bytes(), std::vector<unsigned char>(triangles.begin(), triangles.end()));
    EXPECT_NE(session.legend().find("triangle tests per pixel: black 0, white 7 or more"), std::string::npos);
    // The screenshot is what is shown.
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "dynrt_viewer_cost_test";
    std::filesystem::create_directories(dir);
    session.screenshot(dir / "cost.png");
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open((dir / "cost.png").string());
    ASSERT_TRUE(in);
    std::vector<unsigned char> read(std::size_t(64 * 48 * 3));
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, read.data()));
    EXPECT_EQ(read, std::vector<unsigned char>(triangles.begin(), triangles.end()));
    std::filesystem::remove_all(dir);
    EXPECT_THROW(session.set("view", "heat"), std::invalid_argument);
    EXPECT_THROW(session.set("cost-scale", "-1"), std::invalid_argument);
    session.set("view", "image");
    EXPECT_FALSE(session.options().pixel_cost);
    EXPECT_TRUE(session.render().cost.empty());
    EXPECT_TRUE(session.legend().empty());
    EXPECT_EQ(session.display_bytes(), display_rgb8(session.image(), session.display()));
}

#ifdef DYNRT_HAVE_EMBREE
// The panel's backend switch: Embree's trees built for it, dynrt's used again after.
TEST(ViewerSession, TheBackendSwitchesToEmbreeAndBack) {
    ViewerSession session(small_args());
    EXPECT_EQ(session.render().stats.backend, "dynrt");
    session.set("backend", "embree");
    const RenderedFrame& embree = session.render();
    EXPECT_NE(embree.stats.backend.find("embree"), std::string::npos) << embree.stats.backend;
    EXPECT_GT(embree.stats.primary_rays, 0u);
    session.set("backend", "dynrt");
    EXPECT_EQ(session.render().stats.backend, "dynrt");
}
#endif

TEST(ViewerSession, TheClockStepsSeeksPlaysAndLoops) {
    // A still scene has one frame: stepping and seeking stay at 0.
    ViewerSession still(small_args());
    still.step(3);
    EXPECT_EQ(still.frame(), 0);
    // Procedural motions never end: the clock runs on at the frame rate times the speed.
    ViewArgs moving = small_args();
    moving.anims = {"rigid"};
    ViewerSession session(moving);
    EXPECT_EQ(session.frame(), 0);
    session.advance(1.0);  // paused: no time passes
    EXPECT_EQ(session.frame(), 0);
    session.play();
    session.advance(10.0 / session.fps());
    EXPECT_EQ(session.frame(), 10);
    session.set_speed(2.0);
    session.advance(5.0 / session.fps());
    EXPECT_EQ(session.frame(), 20);
    session.step(-3);
    EXPECT_FALSE(session.playing());
    EXPECT_EQ(session.frame(), 17);
    session.seek(4);
    EXPECT_EQ(session.frame(), 4);
    // Frames rendered follow the clock: the moving object is elsewhere.
    const std::vector<glm::vec3> at4 = session.render().color;
    session.seek(30);
    EXPECT_NE(session.render().color, at4);
}

TEST(ViewerSession, LooksThroughTheFilesCameras) {
    test::GltfTestFile file;
    const int mesh = file.add_mesh({-1, -1, 0, 1, -1, 0, 0, 1, 0});
    file.add_node({{"mesh", mesh}});
    file.doc()["cameras"] = nlohmann::json::array(
        {{{"type", "perspective"}, {"name", "front"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}});
    file.add_node({{"camera", 0}, {"translation", {0.5, 0.0, 4.0}}});
    ViewerSession session(small_args(file.write("viewer_cameras.gltf").string()));
    EXPECT_EQ(session.camera_names(), std::vector<std::string>{"front"});
    session.camera().orbit(60.0f, 20.0f);
    session.use_scene_camera(0);
    const Camera c = session.camera().camera();
    EXPECT_LT(glm::length(c.eye - glm::vec3(0.5f, 0.0f, 4.0f)), 1e-4f);
    EXPECT_LT(glm::length(glm::normalize(c.target - c.eye) - glm::vec3(0.0f, 0.0f, -1.0f)), 1e-4f);
    EXPECT_NEAR(c.fov_y_deg, 0.7f * 180.0f / 3.14159265f, 1e-3f);
    EXPECT_THROW(session.use_scene_camera(1), std::out_of_range);
    EXPECT_THROW(run_command(session, parse_script("0 camera 3", "t").at(0), "t"), std::invalid_argument);
}

/// Polls `worker` until `done` holds for its newest frame (10 s at most); that frame.
RenderWorker::Shown wait_for(const RenderWorker& worker, const std::function<bool(const RenderWorker::Shown&)>& done) {
    RenderWorker::Shown shown;
    for (int i = 0; i < 2000; ++i) {
        worker.take(shown);
        if (shown.number > 0 && done(shown)) return shown;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ADD_FAILURE() << "the worker never got there";
    return shown;
}

/// The display bytes of `camera`'s view under `options`, rendered by a Renderer of its own.
std::vector<unsigned char> rendered_bytes(const Scene& scene, const RenderOptions& options, const Camera& camera) {
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, camera, 0, frame);
    return display_rgb8(frame);
}

TEST(RenderWorker, RefinesAStillViewToItsSamplesAndShowsWhatWasPosted) {
    ViewArgs args = small_args();
    args.spp = 4;
    ViewerSession session(args);
    const RenderOptions options = session.options();
    OrbitCamera camera = session.camera();
    const Scene& scene = session.scene();
    RenderWorker worker(session);
    // Still: refined to 4 samples per pixel, the image `dynrt render --spp 4` makes.
    RenderWorker::Shown shown = wait_for(worker, [](const RenderWorker::Shown& s) { return s.converged(); });
    EXPECT_EQ(shown.samples, 4);
    EXPECT_EQ(shown.bytes, rendered_bytes(scene, options, camera.camera()));
    // A camera move is shown, first at one sample per pixel, then refined again.
    const std::uint64_t moved = worker.post([](ViewerSession& s) {
        s.camera().orbit(30.0f, 0.0f);
        return true;
    });
    camera.orbit(30.0f, 0.0f);
    shown = wait_for(worker, [&](const RenderWorker::Shown& s) { return s.applied >= moved && s.converged(); });
    EXPECT_EQ(shown.bytes, rendered_bytes(scene, options, camera.camera()));
    // A change that leaves the view alone renders nothing again: the same frame, published.
    const std::uint64_t number = shown.number;
    const std::uint64_t noted = worker.post([](ViewerSession&) { return false; });
    const RenderWorker::Shown again = wait_for(worker, [&](const RenderWorker::Shown& s) { return s.applied >= noted; });
    EXPECT_EQ(again.number, number + 1);
    EXPECT_EQ(again.bytes, shown.bytes);
    EXPECT_EQ(again.history.size(), shown.history.size()) << "it rendered again";
    // A change that fails is reported with the next frame, and the worker goes on.
    const std::uint64_t bad = worker.post([](ViewerSession& s) {
        s.set("tracer", "laser");
        return true;
    });
    const RenderWorker::Shown failed = wait_for(worker, [&](const RenderWorker::Shown& s) { return s.applied >= bad; });
    EXPECT_NE(failed.error.find("tracer 'laser'"), std::string::npos) << failed.error;
}

TEST(ViewerScript, CommandsRunOnTheSessionAndBadArgumentsNameTheLine) {
    ViewerSession session(small_args());
    const auto run = [&](const std::string& line) { return run_command(session, parse_script(line, "t").at(0), "t"); };
    const Camera before = session.camera().camera();
    run("0 orbit 40 5");
    EXPECT_NE(session.camera().camera().eye, before.eye);
    run("0 reset-camera");
    EXPECT_EQ(session.camera().camera().eye, OrbitCamera(before).camera().eye);
    run("0 set spp 4");
    EXPECT_EQ(session.options().sampling.spp, 4);
    EXPECT_EQ(run("0 capture x.png").action, WindowStep::Action::capture);
    EXPECT_EQ(run("0 wait-frames 3").frames, 3);
    EXPECT_EQ(run("0 overlay off").on, false);
    try {
        run("0 set spp lots");
        ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("script t, line 1: spp 'lots'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(run("0 zoom far"), std::invalid_argument);
    EXPECT_THROW(run("0 loop maybe"), std::invalid_argument);
}

}  // namespace
}  // namespace dynrt::viewer
