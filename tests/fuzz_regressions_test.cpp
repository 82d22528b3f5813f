// The fuzz targets' inputs replayed in the normal test program (gcc, optimised and under
// ASan+UBSan): every crash input the fuzzers found, kept in tests/data/fuzz_regressions/<target>/
// after the engine was fixed, and the seed corpus of fuzz/corpus/<target>/. Each goes through
// the very entry point of its fuzz target (fuzz/fuzz_entry_points.h) and must load or be
// rejected with the engine's documented SceneError; a crash or sanitizer report fails the run.

#include "fuzz_entry_points.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace dynrt {
namespace {

const std::filesystem::path kSourceDir = DYNRT_SOURCE_DIR;

/// The files of `folder`, sorted so failures are reported in a stable order; none when the
/// folder does not exist (a target without regressions yet).
std::vector<std::filesystem::path> files_in(const std::filesystem::path& folder) {
    std::vector<std::filesystem::path> files;
    if (!std::filesystem::is_directory(folder)) return files;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        if (entry.is_regular_file()) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<unsigned char> read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Regressions and seeds of one target.
std::vector<std::filesystem::path> inputs_of(const std::string& target) {
    std::vector<std::filesystem::path> inputs = files_in(kSourceDir / "tests" / "data" / "fuzz_regressions" / target);
    const std::vector<std::filesystem::path> seeds = files_in(kSourceDir / "fuzz" / "corpus" / target);
    inputs.insert(inputs.end(), seeds.begin(), seeds.end());
    return inputs;
}

TEST(FuzzRegressions, GltfLoaderInputsLoadOrGiveTheDocumentedError) {
    const std::vector<std::filesystem::path> inputs = inputs_of("gltf_loader");
    ASSERT_FALSE(inputs.empty()) << "the seed corpus fuzz/corpus/gltf_loader is missing";
    for (const std::filesystem::path& input : inputs) {
        SCOPED_TRACE(input.string());
        fuzz::FuzzOutcome outcome;
        EXPECT_NO_THROW(outcome = fuzz::feed_gltf_loader(read_bytes(input)));
        EXPECT_TRUE(fuzz::keeps_gltf_error_contract(outcome)) << outcome.error;
    }
}

TEST(FuzzRegressions, GltfSeedsAllLoad) {
    // The seeds are there to lead the fuzzer into every part of the loader, which they only do
    // when they load.
    for (const std::filesystem::path& seed : files_in(kSourceDir / "fuzz" / "corpus" / "gltf_loader")) {
        SCOPED_TRACE(seed.string());
        EXPECT_TRUE(fuzz::feed_gltf_loader(read_bytes(seed)).loaded);
    }
}

TEST(FuzzRegressions, ProceduralSpecInputsBuildOrGiveTheDocumentedError) {
    const std::vector<std::filesystem::path> inputs = inputs_of("procedural_spec");
    ASSERT_FALSE(inputs.empty()) << "the seed corpus fuzz/corpus/procedural_spec is missing";
    for (const std::filesystem::path& input : inputs) {
        SCOPED_TRACE(input.string());
        const std::vector<unsigned char> bytes = read_bytes(input);
        fuzz::FuzzOutcome outcome;
        EXPECT_NO_THROW(outcome = fuzz::feed_procedural_spec(
                            std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size())));
        if (!outcome.loaded) {
            EXPECT_TRUE(outcome.error.starts_with("procedural spec '")) << outcome.error;
        }
    }
}

TEST(FuzzRegressions, AnimationSpecInputsPoseOrGiveTheDocumentedError) {
    const std::vector<std::filesystem::path> inputs = inputs_of("animation_specs");
    ASSERT_FALSE(inputs.empty()) << "the seed corpus fuzz/corpus/animation_specs is missing";
    for (const std::filesystem::path& input : inputs) {
        SCOPED_TRACE(input.string());
        const std::vector<unsigned char> bytes = read_bytes(input);
        fuzz::FuzzOutcome outcome;
        EXPECT_NO_THROW(outcome = fuzz::feed_animation_specs(
                            std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size())));
        if (!outcome.loaded) {
            EXPECT_FALSE(outcome.error.empty());
        }
    }
}

TEST(FuzzRegressions, AffSceneInputsLoadOrGiveTheDocumentedError) {
    const std::vector<std::filesystem::path> inputs = inputs_of("aff_scene");
    ASSERT_FALSE(inputs.empty()) << "the seed corpus fuzz/corpus/aff_scene is missing";
    for (const std::filesystem::path& input : inputs) {
        SCOPED_TRACE(input.string());
        const std::vector<unsigned char> bytes = read_bytes(input);
        fuzz::FuzzOutcome outcome;
        EXPECT_NO_THROW(outcome = fuzz::feed_aff_scene(
                            std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size())));
        if (!outcome.loaded) {
            EXPECT_FALSE(outcome.error.empty());
            EXPECT_EQ(outcome.error.find('\n'), std::string::npos) << outcome.error;
        }
    }
}

TEST(FuzzRegressions, AffSeedsAllLoad) {
    for (const std::filesystem::path& seed : files_in(kSourceDir / "fuzz" / "corpus" / "aff_scene")) {
        SCOPED_TRACE(seed.string());
        const std::vector<unsigned char> bytes = read_bytes(seed);
        const fuzz::FuzzOutcome outcome =
            fuzz::feed_aff_scene(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
        EXPECT_TRUE(outcome.loaded) << outcome.error;
    }
}

}  // namespace
}  // namespace dynrt
