#pragma once
// Files the CLI, writer and MPI tests make and compare: fresh folders under GoogleTest's
// temporary folder, a file's bytes, and an image's content for bit-for-bit comparison.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace dynrt::test {

/// The empty folder `dynrt_<name>` under GoogleTest's temporary folder (emptied if it exists).
inline std::filesystem::path fresh_test_dir(const std::string& name) {
    const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / ("dynrt_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

/// The bytes of the file at `path` (empty when it cannot be read).
inline std::string bytes_of(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// What a file holds for comparison: a PNG's (or any non-EXR file's) bytes; an EXR's pixels as
/// bits, since its header has the time it was written (capDate). Empty when unreadable.
inline std::string content_of(const std::filesystem::path& path) {
    if (path.extension() != ".exr") return bytes_of(path);
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) return {};
    return std::string(reinterpret_cast<const char*>(pixels.data()), pixels.size() * sizeof(float));
}

}  // namespace dynrt::test
