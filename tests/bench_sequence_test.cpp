// `dynrt bench --frames`: per-frame samples of dynrt and of tracers stepping beside it, and the
// timeline chart of an animated run.

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bench/bench_plot.h"
#include "dynrt/bench/bench_sequence.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace dynrt {
namespace {

/// A tracer that reports fixed times and remembers which frames it was asked for.
class FakeTracer : public SequenceTracer {
public:
    explicit FakeTracer(std::vector<int>& seen) : seen_(seen) {}
    std::string name() const override { return "fake"; }
    SequenceFrameTimes frame(int frame, const Camera&, const RenderedFrame& dynrt_frame) override {
        seen_.push_back(frame);
        EXPECT_EQ(dynrt_frame.stats.frame, frame);  // dynrt rendered this very frame first
        SequenceFrameTimes t;
        t.update_ms = 1.0;
        t.build_ms = 2.0 * frame;
        t.primary_ms = 3.0;
        t.shadow_ms = 4.0;
        t.shade_ms = 0.5;
        t.secondary_ms = 5.0;
        t.vs_dynrt.prim_only_differs = 1;
        return t;
    }

private:
    std::vector<int>& seen_;
};

TEST(BenchSequence, EveryFrameOfEveryRunIsOneSample) {
    Scene scene = load_scene("sphere:300");
    const std::vector<std::string> motions{"wave"};
    anim::add_procedural_motions(scene, motions);
    RenderOptions options;
    options.width = 16;
    options.height = 16;
    // A fixed method: the automatic one's choices depend on measured times.
    options.method = UpdateMethod::threshold;
    std::vector<int> seen;
    std::vector<std::unique_ptr<SequenceTracer>> others;
    others.push_back(std::make_unique<FakeTracer>(seen));
    const SequenceBench bench = bench_sequence(scene, CameraSource::fixed(default_camera(scene_bounds(scene))), options,
                                               FrameRange{2, 5}, 2, 0, others);
    EXPECT_EQ(seen, (std::vector<int>{2, 3, 4, 5, 2, 3, 4, 5}));
    ASSERT_EQ(bench.rows.size(), 2u);
    EXPECT_EQ(bench.rows[0].tracer, "dynrt");
    EXPECT_EQ(bench.rows[1].tracer, "fake");
    // Fake frames cost 1 + 2f + 3 + 4: over f = 2, 3, 4, 5 twice the lower median is f = 3.
    EXPECT_EQ(bench.rows[1].frame_ms.median, 14.0);
    // The whole frame adds shading and the secondary rays.
    EXPECT_EQ(bench.rows[1].secondary_ms.median, 5.0);
    EXPECT_EQ(bench.rows[1].total_ms.median, 19.5);
    EXPECT_EQ(bench.rows[1].frame_ms.min, 12.0);
    EXPECT_EQ(bench.rows[1].frame_ms.max, 18.0);
    EXPECT_EQ(bench.rows[1].vs_dynrt.prim_only_differs, 8u);
    EXPECT_EQ(bench.rows[1].primary_ms.median, 3.0);
    EXPECT_EQ(bench.rows[1].shadow_ms.max, 4.0);
    // dynrt's report is the last run's: each run starts from empty trees.
    ASSERT_EQ(bench.frames.size(), 4u);
    EXPECT_EQ(bench.frames[0].frame, 2);
    EXPECT_EQ(bench.frames[0].objects_rebuilt, 1u);
    EXPECT_EQ(bench.frames[1].objects_refitted, 1u);

    std::ostringstream table;
    print_sequence_table(table, bench);
    EXPECT_NE(table.str().find("fake"), std::string::npos) << table.str();
    const nlohmann::json doc = nlohmann::json::parse(sequence_json(bench));
    EXPECT_EQ(doc["sequence"].size(), 2u);
    EXPECT_EQ(doc["sequence"][1]["shadow_ms"]["median"], 4.0);
    EXPECT_EQ(doc["frames"].size(), 4u);
    EXPECT_TRUE(doc["summary"]["median"].contains("refit_ms"));
}

/// A tracer that remembers the camera it was given for each frame.
class CameraRecorder : public SequenceTracer {
public:
    explicit CameraRecorder(std::vector<Camera>& seen) : seen_(seen) {}
    std::string name() const override { return "cameras"; }
    SequenceFrameTimes frame(int, const Camera& camera, const RenderedFrame&) override {
        seen_.push_back(camera);
        return {};
    }

private:
    std::vector<Camera>& seen_;
};

TEST(BenchSequence, WithoutAFixedCameraEveryTracerGetsTheScenesCameraOfEachFrame) {
    // A BART scene whose camera moves along z, one unit per frame (frame f at time f).
    const Scene scene = load_aff_text(R"(
v
from 0 0 10
at 0 0 0
up 0 1 0
angle 40
hither 1
resolution 16 12
a 0 3 4
p 3
0 0 0
1 0 0
0 1 0
k camera
{
  transl 4
  -1 0 0 11  0 0 0
   0 0 0 10  0 0 0
   3 0 0 7   0 0 0
   4 0 0 6   0 0 0
}
)", "moving_camera.aff");
    RenderOptions options;
    options.width = 16;
    options.height = 12;
    options.pose.fps = scene.setup->fps;
    std::vector<Camera> seen;
    std::vector<std::unique_ptr<SequenceTracer>> others;
    others.push_back(std::make_unique<CameraRecorder>(seen));
    (void)bench_sequence(scene, CameraSource::scene(), options, FrameRange{0, 3}, 1, 0, others);
    ASSERT_EQ(seen.size(), 4u);
    for (int f = 0; f < 4; ++f) EXPECT_NEAR(seen[std::size_t(f)].eye.z, 10.0 - f, 1e-5) << "frame " << f;
    // A scene without a camera of its own needs a fixed one.
    const Scene plain = load_scene("sphere:20");
    EXPECT_THROW((void)bench_sequence(plain, CameraSource::scene(), options, FrameRange{0, 1}, 1, 0, others),
                 std::invalid_argument);
}

TEST(BenchSequence, TimelineStacksEveryStagePerFrame) {
    std::vector<FrameStats> frames(3);
    for (int f = 0; f < 3; ++f) {
        frames[f].frame = 10 + f;
        frames[f].update_ms = 1.5;
        frames[f].refit_ms = 2.5;
        frames[f].shade_ms = 7.25;
    }
    const std::string s = timeline_plot_script(frames, "t", "out/tl.png");
    EXPECT_NE(s.find("rowstacked"), std::string::npos);
    EXPECT_NE(s.find("set output 'out/tl.png'"), std::string::npos);
    EXPECT_NE(s.find("11 1.5 2.5 0 0 0 0 7.25\n"), std::string::npos) << s;
    for (const char* stage : {"'update (animation)'", "'refit'", "'rebuild'", "'top level'",
                              "'primary rays'", "'shadow rays'", "'shade'"}) {
        EXPECT_NE(s.find(stage), std::string::npos) << stage;
    }
    EXPECT_THROW(timeline_plot_script({}, "t", "x.png"), std::invalid_argument);
    // Frames of about one size share the axis, the first included.
    EXPECT_NE(s.find("set yrange [0:*]"), std::string::npos) << s;
    EXPECT_EQ(s.find("off the scale"), std::string::npos) << s;
}

// The cold first frame (every tree built) would squash the steady frames into the bottom of
// the chart: the axis is theirs, and the first frame's time is written over its bar.
TEST(BenchSequence, TimelineKeepsTheAxisForTheSteadyFrames) {
    std::vector<FrameStats> frames(4);
    for (int f = 0; f < 4; ++f) {
        frames[f].frame = f;
        frames[f].primary_ms = 4.0;
        frames[f].shade_ms = f == 2 ? 4.0 : 2.0;  // the slowest steady frame: 8 ms
    }
    frames[0].rebuild_ms = 104.0;  // 110 ms
    const std::string s = timeline_plot_script(frames, "t", "out/tl.png");
    EXPECT_NE(s.find("set yrange [0:10]"), std::string::npos) << s;  // 1.25 x 8 ms
    EXPECT_NE(s.find("set label 1 'first frame 110 ms (cold: every tree built), off the scale'"),
              std::string::npos)
        << s;
    EXPECT_EQ(s.find("set yrange [0:*]"), std::string::npos) << s;
}

}  // namespace
}  // namespace dynrt
