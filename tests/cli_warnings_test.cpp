// What `dynrt` tells a person besides errors (engine/cli/command_warnings.h): a scene whose
// texture folder is missing gets one warning line per kind of problem, not one per material;
// --verbose lists every one; --quiet prints nothing at all, and still writes the image.

#include "shell_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

/// A BART file of 12 textured triangles, each of its own material, mapping 6 texture files
/// that are not there (as BART's scenes are when their .aff files are copied alone).
fs::path write_scene_without_its_textures() {
    const fs::path dir = fs::path(testing::TempDir()) / "dynrt_cli_warnings";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream aff(dir / "missing.aff");
    aff << "l 0 5 5\n";
    for (int i = 0; i < 12; ++i) {
        aff << "f 0.8 0.5 0.5 1 0 0 0 0\ntt tex_" << i % 6 << ".ppm\n";
        aff << " " << i << " 0 0 0 0\n " << i + 1 << " 0 0 1 0\n " << i << " 1 0 0 1\n";
    }
    return dir / "missing.aff";
}

dynrt::test::ShellRun render_with(const std::string& flags, const fs::path& image) {
    const fs::path scene = write_scene_without_its_textures();
    return dynrt::test::run_shell("timeout 300 " + std::string(DYNRT_CLI_PATH) + " render " +
                                  scene.string() + " --res 32x32 --out " + image.string() + " " + flags);
}

std::size_t count_of(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

TEST(CliWarnings, MissingTexturesAreOneLineWithCountsAndTheFirstNames) {
    const fs::path image = fs::path(testing::TempDir()) / "dynrt_cli_warnings.png";
    const dynrt::test::ShellRun run = render_with("", image);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(count_of(run.output, "warning:"), 1u) << run.output;
    EXPECT_NE(run.output.find("6 textures cannot be read (no such file): "), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("and 3 more (--verbose lists them), used by 12 materials"), std::string::npos)
        << run.output;
    // Before the table, so that the figures are the last thing on the screen.
    EXPECT_LT(run.output.find("warning:"), run.output.find("frame ")) << run.output;
}

TEST(CliWarnings, VerboseListsEveryMaterialAndQuietPrintsNothing) {
    // Not the other test's image: ctest may run the two at once.
    const fs::path image = fs::path(testing::TempDir()) / "dynrt_cli_warnings_verbose.png";
    const dynrt::test::ShellRun verbose = render_with("--verbose", image);
    ASSERT_EQ(verbose.exit_code, 0) << verbose.output;
    EXPECT_EQ(count_of(verbose.output, "warning:"), 12u) << verbose.output;
    fs::remove(image);
    const dynrt::test::ShellRun quiet = render_with("--quiet", image);
    ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
    EXPECT_EQ(quiet.output, "");
    EXPECT_TRUE(fs::exists(image));
    // An error still speaks under --quiet.
    const dynrt::test::ShellRun failed = render_with("--quiet", fs::path("/no/such/folder/x.png"));
    EXPECT_NE(failed.exit_code, 0);
    EXPECT_NE(failed.output.find("error"), std::string::npos) << failed.output;
    const dynrt::test::ShellRun both = render_with("--quiet --verbose", image);
    EXPECT_NE(both.exit_code, 0) << both.output;
}

}  // namespace
