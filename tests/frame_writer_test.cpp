// The output stage (dynrt/engine/frame_writer.h): files written on its thread are the bytes
// written on the render thread (EXRs: the pixels, as their header holds the time); a GIF's frames stay in order; a file it cannot write is an
// error on the render thread naming the frame and the user's path, with what was written
// before left whole.

#include "test_files.h"
#include "dynrt/engine/frame_writer.h"
#include "dynrt/engine/sequence_output.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace dynrt {
namespace frame_writer_test {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) { return test::fresh_test_dir("frame_writer_" + name); }

using test::bytes_of;
using test::content_of;

/// The outputs of a render to `out` with `aovs`, nothing else.
FrameOutputs outputs_to(const fs::path& out, std::vector<Aov> aovs = {}) {
    FrameOutputs outputs;
    outputs.out = out.string();
    outputs.aovs = std::move(aovs);
    return outputs;
}

/// A frame of noise (every pixel differs from its neighbours and from the other frames'), with
/// hit buffers for the AOVs.
RenderedFrame noise_frame(int number, int width = 29, int height = 17) {
    std::mt19937 random(unsigned(number) + 1);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    RenderedFrame frame;
    frame.width = width;
    frame.height = height;
    frame.stats.frame = number;
    for (int i = 0; i < width * height; ++i) {
        frame.color.emplace_back(value(random), value(random), value(random));
        frame.depth.push_back(value(random) * 10.0f);
        frame.object.push_back(int(random() % 5) - 1);
        frame.prim.push_back(int(random() % 1000) - 1);
        frame.normal.emplace_back(value(random), value(random), value(random));
    }
    return frame;
}

TEST(FrameWriter, NumberedImagesAndAovsAreTheBytesOfWritingOnTheRenderThread) {
    const fs::path dir = fresh_dir("numbered");
    const FrameOutputs threaded = outputs_to(dir / "a" / "%02d.png", {Aov::depth, Aov::prim});
    const FrameOutputs direct = outputs_to(dir / "b" / "%02d.png", {Aov::depth, Aov::prim});
    fs::create_directories(dir / "a");
    fs::create_directories(dir / "b");
    FrameWriter writer(threaded, 2);
    RenderedFrame frame;
    for (int f = 0; f < 6; ++f) {
        frame = noise_frame(f);
        writer.submit(frame);
        // The render reuses its buffers at once: the writer must have taken a copy.
        frame.color.assign(frame.color.size(), glm::vec3(0.0f));
        write_frame_now(direct, noise_frame(f));
    }
    writer.finish();
    const std::vector<FrameStats> written = writer.take_written();
    ASSERT_EQ(written.size(), 6u);
    for (int f = 0; f < 6; ++f) {
        EXPECT_EQ(written[std::size_t(f)].frame, f);
        EXPECT_GT(written[std::size_t(f)].write_ms, 0.0);
        char name[8];
        std::snprintf(name, sizeof name, "%02d", f);
        for (const std::string suffix : {".png", ".depth.exr", ".prim.exr"}) {
            const std::string a = content_of(dir / "a" / (name + suffix));
            EXPECT_FALSE(a.empty()) << name << suffix;
            EXPECT_EQ(a, content_of(dir / "b" / (name + suffix))) << name << suffix;
        }
    }
}

TEST(FrameWriter, AGifsFramesStayInOrderAndEqualASynchronousGif) {
    const fs::path dir = fresh_dir("gif");
    FrameOutputs outputs = outputs_to(dir / "threaded.gif");
    outputs.fps = 10;
    outputs.contact_sheet = (dir / "sheet.png").string();
    outputs.frame_count = 5;
    FrameWriter writer(outputs, 1);  // one frame in flight: the render waits on every hand-over
    const std::unique_ptr<SequenceFile> direct = open_sequence_file(dir / "direct.gif", 10);
    ContactSheet sheet(5);
    for (int f = 0; f < 5; ++f) {
        const RenderedFrame frame = noise_frame(f);
        writer.submit(frame);
        direct->add(frame);
        sheet.add(f, frame);
    }
    EXPECT_FALSE(fs::exists(dir / "threaded.gif")) << "a GIF is under its name only once whole";
    writer.finish();
    direct->close();
    sheet.write(dir / "direct_sheet.png");
    EXPECT_EQ(bytes_of(dir / "threaded.gif"), bytes_of(dir / "direct.gif"));
    EXPECT_EQ(bytes_of(dir / "sheet.png"), bytes_of(dir / "direct_sheet.png"));
    EXPECT_EQ(writer.contact_sheet_frames(), 5);
    EXPECT_EQ(bytes_of(dir / "threaded.gif").back(), '\x3b');  // the GIF trailer
}

TEST(FrameWriter, AGifWithoutFramesIsNotMade) {
    const fs::path dir = fresh_dir("empty_gif");
    FrameWriter writer(outputs_to(dir / "none.gif"));
    writer.finish();
    EXPECT_TRUE(fs::is_empty(dir));
}

TEST(FrameWriter, AnUnwritableFrameIsAnErrorNamingItAndItsFileAndEarlierFramesStayWhole) {
    const fs::path dir = fresh_dir("unwritable");
    // Frame 5's image cannot be written: its name is taken by a folder.
    fs::create_directories(dir / "05.png");
    FrameWriter writer(outputs_to(dir / "%02d.png"), 2);
    std::string error;
    try {
        for (int f = 0; f < 10; ++f) writer.submit(noise_frame(f));
        writer.finish();
    } catch (const FrameWriteError& e) {
        error = e.what();
        EXPECT_EQ(e.frame(), 5);
    }
    EXPECT_NE(error.find("frame 5: " + (dir / "05.png").string() + ": cannot write: is a folder"),
              std::string::npos)
        << error;
    std::vector<int> written;
    for (const FrameStats& s : writer.take_written()) written.push_back(s.frame);
    EXPECT_EQ(written, (std::vector<int>{0, 1, 2, 3, 4}));
    for (int f = 0; f < 5; ++f) {
        const fs::path path = dir / ("0" + std::to_string(f) + ".png");
        auto in = OIIO::ImageInput::open(path.string());
        EXPECT_TRUE(in) << path;
    }
    for (const auto& entry : fs::directory_iterator(dir)) {
        EXPECT_EQ(entry.path().string().find(".partial"), std::string::npos) << entry.path();
    }
}

/// The pixels of an image file as floats (OpenImageIO), RGB interleaved.
std::vector<float> pixels_of(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path;
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> out(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.data());
    return out;
}

TEST(DisplayTransform, CurvesAndExposure) {
    const DisplayTransform identity;
    EXPECT_TRUE(identity.identity());
    EXPECT_EQ(identity.apply(glm::vec3(0.25f, 2.0f, -1.0f)), glm::vec3(0.25f, 2.0f, 0.0f));
    const DisplayTransform reinhard{0.0f, ToneCurve::reinhard};
    EXPECT_FLOAT_EQ(reinhard.apply(glm::vec3(1.0f)).x, 0.5f);
    EXPECT_FLOAT_EQ(reinhard.apply(glm::vec3(3.0f)).x, 0.75f);
    const DisplayTransform brighter{1.0f, ToneCurve::linear};
    EXPECT_FLOAT_EQ(brighter.apply(glm::vec3(0.25f)).x, 0.5f);
    const DisplayTransform aces{0.0f, ToneCurve::aces};
    EXPECT_FLOAT_EQ(aces.apply(glm::vec3(0.0f)).x, 0.0f);
    EXPECT_NEAR(aces.apply(glm::vec3(1e30f)).x, 2.51f / 2.43f, 1e-3f);  // no inf / inf
    const DisplayTransform far{60.0f, ToneCurve::reinhard};
    EXPECT_NEAR(far.apply(glm::vec3(1.0f)).x, 1.0f, 1e-4f);
    // Monotone: a brighter colour never shows darker.
    for (const ToneCurve curve : {ToneCurve::reinhard, ToneCurve::aces}) {
        float last = -1.0f;
        for (float x = 0.0f; x < 100.0f; x += 0.37f) {
            const float y = DisplayTransform{0.0f, curve}.apply(glm::vec3(x)).x;
            EXPECT_GE(y, last) << tone_curve_name(curve) << " at " << x;
            last = y;
        }
    }
    EXPECT_EQ(parse_tone_curve("aces"), ToneCurve::aces);
    EXPECT_THROW(parse_tone_curve("filmic"), std::invalid_argument);
}

TEST(FrameWriter, TheToneCurveShapesEightBitFilesAndLeavesFloatFilesLinear) {
    const fs::path dir = fresh_dir("display");
    RenderedFrame frame = noise_frame(0);
    for (glm::vec3& c : frame.color) c *= 4.0f;  // values up to 4: clipped by the linear curve
    FrameOutputs linear = outputs_to(dir / "linear.png");
    FrameOutputs toned = outputs_to(dir / "toned.png");
    toned.display = DisplayTransform{-1.0f, ToneCurve::reinhard};
    FrameOutputs toned_exr = outputs_to(dir / "toned.exr");
    toned_exr.display = toned.display;
    write_frame_now(linear, frame);
    write_frame_now(toned, frame);
    write_frame_now(toned_exr, frame);
    const std::vector<float> a = pixels_of(dir / "linear.png"), b = pixels_of(dir / "toned.png");
    const std::vector<float> exr = pixels_of(dir / "toned.exr");
    ASSERT_EQ(a.size(), frame.color.size() * 3);
    ASSERT_EQ(b.size(), a.size());
    std::size_t clipped = 0, kept = 0;
    for (std::size_t p = 0; p < frame.color.size(); ++p) {
        for (int c = 0; c < 3; ++c) {
            clipped += a[3 * p + std::size_t(c)] == 1.0f ? 1 : 0;
            kept += b[3 * p + std::size_t(c)] < 1.0f ? 1 : 0;
            EXPECT_EQ(exr[3 * p + std::size_t(c)], frame.color[p][c]);  // linear, untouched
        }
    }
    EXPECT_GT(clipped, frame.color.size());  // most channels above 1 clip without a curve
    EXPECT_EQ(kept, frame.color.size() * 3);  // x / (1 + x) never reaches white
}

}  // namespace frame_writer_test
}  // namespace dynrt
