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

}  // namespace frame_writer_test
}  // namespace dynrt
