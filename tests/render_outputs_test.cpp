// The outputs of `dynrt render` checked before anything is loaded (engine/cli/render_outputs.h):
// two outputs naming one file, folders that are missing or take no file, an output that is a
// folder; and write errors that name the user's file, never the temporary one.

#include "render_outputs.h"

#include "dynrt/engine/atomic_file.h"
#include "dynrt/engine/image_output.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace dynrt::cli {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) {
    const fs::path dir = fs::path(testing::TempDir()) / ("dynrt_outputs_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

/// The message check_render_outputs refuses `args` with, or "" when it accepts them.
std::string refusal(const RenderArgs& args, bool journal = false) {
    const FrameRange range = args.frames.empty() ? FrameRange{} : parse_frame_range(args.frames);
    try {
        check_render_outputs(render_outputs(args, range, journal), range);
        return "";
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
}

TEST(RenderOutputs, TwoOutputsNamingOneFileAreRefused) {
    const std::string d = fresh("clash").string() + "/";
    RenderArgs a;
    a.out = d + "a.png";
    a.report = d + "a.png";
    EXPECT_NE(refusal(a).find("--out '" + d + "a.png' and --report '" + d + "a.png' are the same file"),
              std::string::npos) << refusal(a);
    RenderArgs sheet;
    sheet.out = d + "a.png";
    sheet.contact_sheet = d + "./a.png";  // the same file, written another way
    EXPECT_NE(refusal(sheet).find("are the same file"), std::string::npos) << refusal(sheet);
    RenderArgs aov;
    aov.out = d + "a.png";
    aov.aov = "depth";
    aov.report = d + "a.depth.exr";
    EXPECT_NE(refusal(aov).find("--aov depth"), std::string::npos) << refusal(aov);
    // A numbered output clashes with a file when one of the range's frames has its name.
    RenderArgs frames;
    frames.out = d + "%04d.png";
    frames.frames = "0-9";
    frames.report = d + "0007.png";
    EXPECT_NE(refusal(frames).find("(frame 7 of --out)"), std::string::npos) << refusal(frames);
    frames.frames = "0-6";
    EXPECT_EQ(refusal(frames), "");
    frames.aov = "depth";
    frames.contact_sheet = d + "0003.depth.exr";
    EXPECT_NE(refusal(frames).find("(frame 3 of --aov depth)"), std::string::npos) << refusal(frames);
    // The journal beside the frames is an output too.
    RenderArgs journal;
    journal.out = d + "%04d.png";
    journal.contact_sheet = d + ".dynrt-frames.jsonl";
    EXPECT_EQ(refusal(journal), "");
    EXPECT_NE(refusal(journal, true).find("the journal"), std::string::npos) << refusal(journal, true);
}

TEST(RenderOutputs, FoldersAreCheckedBeforeAnythingIsWritten) {
    const fs::path dir = fresh("folders");
    RenderArgs missing;
    missing.out = (dir / "a.png").string();
    missing.report = (dir / "no" / "r.json").string();
    EXPECT_NE(refusal(missing).find("--report '" + missing.report + "': folder " +
                                    (dir / "no").string() + " does not exist"),
              std::string::npos) << refusal(missing);
    // A folder that takes no file (/proc takes none, even from root).
    RenderArgs unwritable;
    unwritable.out = (dir / "a.png").string();
    unwritable.contact_sheet = "/proc/sheet.png";
    EXPECT_NE(refusal(unwritable).find("--contact-sheet '/proc/sheet.png': cannot write in folder /proc"),
              std::string::npos) << refusal(unwritable);
    // Numbered frames make their folder: then the nearest existing one must take files.
    RenderArgs numbered;
    numbered.out = (dir / "new" / "deeper" / "%d.png").string();
    numbered.frames = "0-1";
    EXPECT_EQ(refusal(numbered), "");
    EXPECT_FALSE(fs::exists(dir / "new")) << "the check made a folder";
    numbered.out = "/proc/dynrt-no/%d.png";
    EXPECT_NE(refusal(numbered).find("cannot write in folder /proc"), std::string::npos) << refusal(numbered);
    // An output that is a folder.
    RenderArgs folder;
    folder.out = (dir / "a.png").string();
    folder.report = dir.string();
    EXPECT_NE(refusal(folder).find("is a folder"), std::string::npos) << refusal(folder);
    // No probe file is left behind.
    for (const auto& entry : fs::directory_iterator(dir)) {
        EXPECT_EQ(entry.path().filename().string().find(".dynrt-probe"), std::string::npos) << entry.path();
    }
}

/// An image that cannot be written is named as the user named it: the error never mentions
/// the temporary file (".sheet.partial.png") it is written to first.
TEST(RenderOutputs, WriteErrorsNameTheUsersFileNotTheTemporaryOne) {
    RenderedFrame frame;
    frame.width = frame.height = 2;
    frame.color.assign(4, glm::vec3(0.5f));
    try {
        write_image("/proc/sheet.png", frame);
        ADD_FAILURE() << "wrote into /proc";
    } catch (const std::runtime_error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("/proc/sheet.png"), std::string::npos) << message;
        EXPECT_EQ(message.find("partial"), std::string::npos) << message;
    }
    EXPECT_EQ(name_user_file("cannot open \"/d/.a.partial.png\" (.a.partial.png)", "/d/.a.partial.png", "/d/a.png"),
              "cannot open \"/d/a.png\" (a.png)");
}

}  // namespace
}  // namespace dynrt::cli
