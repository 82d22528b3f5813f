// save_image writes through stb_image_write (Debian's libstb-dev) rather than OpenImageIO, which
// the command line uses: OpenImageIO pulls about 250 shared libraries into every program that
// loads it, which cost an embedding program 0.3-1 s at start-up for one convenience call.
#include "dynrt/api/engine.h"

#include "output/srgb.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace dynrt {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) {
    throw Error(Error::Code::invalid_argument, "dynrt::save_image '" + path + "': " + why);
}

}  // namespace

void save_image(const std::string& path, int width, int height, std::span<const float> rgb) {
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536 ||
        rgb.size() != 3 * std::size_t(width) * std::size_t(height)) {
        fail(path, std::to_string(rgb.size()) + " floats for a " + std::to_string(width) + "x" +
                       std::to_string(height) + " image (3 per pixel expected)");
    }
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent)) {
        fail(path, "folder " + parent.string() + " does not exist");
    }
    int written = 0;
    if (ext == ".hdr") {
        // Radiance HDR keeps the linear floats.
        written = stbi_write_hdr(path.c_str(), width, height, 3, rgb.data());
    } else if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tga") {
        std::vector<std::uint8_t> bytes(rgb.size());
        for (std::size_t i = 0; i < rgb.size(); ++i) {
            const float v = std::isnan(rgb[i]) ? 0.0f : srgb_encode(rgb[i]);
            bytes[i] = std::uint8_t(std::lround(255.0f * v));
        }
        if (ext == ".png") {
            written = stbi_write_png(path.c_str(), width, height, 3, bytes.data(), 3 * width);
        } else if (ext == ".bmp") {
            written = stbi_write_bmp(path.c_str(), width, height, 3, bytes.data());
        } else if (ext == ".tga") {
            written = stbi_write_tga(path.c_str(), width, height, 3, bytes.data());
        } else {
            written = stbi_write_jpg(path.c_str(), width, height, 3, bytes.data(), 95);
        }
    } else {
        fail(path, "unknown image format (use .png, .jpg, .bmp, .tga, or .hdr for linear floats)");
    }
    if (!written) fail(path, "could not be written");
}

}  // namespace dynrt
