#include "dynrt/engine/image_output.h"

#include "dynrt/engine/atomic_file.h"
#include "srgb8.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <system_error>

namespace dynrt {

namespace {

constexpr const char* kAovNames[] = {"depth", "object", "prim", "normal", "cost"};
constexpr int kAovCount = int(std::size(kAovNames));

/// PNG files are written fast rather than small: zlib's level 1 instead of OpenImageIO's 6, and
/// every row filtered by "up" (libpng's PNG_FILTER_UP) instead of libpng trying all five
/// filters per row. On a CesiumMan frame at 1024x1024 that took the encoding from 46-77 ms to
/// 12-16 ms for a file 30% larger (130 KB instead of 100 KB); benchmarks/README.md, "Writing
/// frames", has the measurements of each level and filter.
constexpr int kPngCompressionLevel = 1;
constexpr int kPngFilterUp = 0x20;

/// Writes the image to a temporary file beside `path`, then renames it over `path`
/// (atomic_file.h): a render killed part way never leaves a torn image. `data` holds
/// `channels` values of `data_type` per pixel; the file stores them as `file_type`.
void write_pixels(const std::filesystem::path& path, int width, int height, int channels,
                  const void* data, OIIO::TypeDesc data_type, OIIO::TypeDesc file_type,
                  std::vector<std::string> channel_names = {}) {
    const std::filesystem::path partial = partial_path(path);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path.string());
    if (!out) {
        throw std::runtime_error(path.string() + ": unknown or unsupported image format (" +
                                 OIIO::geterror() + ")");
    }
    OIIO::ImageSpec spec(width, height, channels, file_type);
    if (!channel_names.empty()) spec.channelnames = std::move(channel_names);
    spec.attribute("png:compressionLevel", kPngCompressionLevel);
    spec.attribute("png:filter", kPngFilterUp);
    if (!out->open(partial.string(), spec) || !out->write_image(data_type, data) ||
        !out->close()) {
        std::string message = out->geterror();
        std::error_code ignored;
        std::filesystem::remove(partial, ignored);
        throw std::runtime_error(path.string() + ": " + name_user_file(message, partial, path));
    }
    commit_partial(partial, path);
}

}  // namespace

const char* aov_name(Aov aov) { return kAovNames[int(aov)]; }

std::vector<Aov> parse_aov_list(const std::string& list) {
    std::vector<Aov> aovs;
    std::size_t start = 0;
    while (start < list.size()) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const std::string name = list.substr(start, comma - start);
        start = comma + 1;
        bool known = false;
        for (int a = 0; a < kAovCount; ++a) {
            if (name != kAovNames[a]) continue;
            known = true;
            const Aov aov = Aov(a);
            if (std::find(aovs.begin(), aovs.end(), aov) != aovs.end()) {
                throw std::invalid_argument("--aov: '" + name + "' given twice");
            }
            aovs.push_back(aov);
        }
        if (!known) {
            throw std::invalid_argument("--aov: unknown output '" + name +
                                        "' (known: depth, object, prim, normal, cost)");
        }
    }
    return aovs;
}

void write_image(const std::filesystem::path& path, const RenderedFrame& frame, const DisplayTransform& display) {
    // Float formats keep linear radiance; the rest expect display-encoded values.
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    const bool float_file = ext == ".exr" || ext == ".hdr" || ext == ".pfm";
    if (float_file) {
        // glm::vec3 is three packed floats: the colour buffer is RGB interleaved already.
        static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
        write_pixels(path, frame.width, frame.height, 3, frame.color.data(),
                     OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT);
        return;
    }
    const std::vector<std::uint8_t> rgb = display_rgb8(frame, display);
    write_pixels(path, frame.width, frame.height, 3, rgb.data(), OIIO::TypeDesc::UINT8,
                 OIIO::TypeDesc::UINT8);
}

void write_image_rgb8(const std::filesystem::path& path, int width, int height, std::span<const std::uint8_t> rgb) {
    if (rgb.size() != std::size_t(width) * std::size_t(height) * 3) {
        throw std::invalid_argument(path.string() + ": " + std::to_string(rgb.size()) + " bytes for a " +
                                    std::to_string(width) + "x" + std::to_string(height) + " RGB image");
    }
    write_pixels(path, width, height, 3, rgb.data(), OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8);
}

std::vector<std::uint8_t> display_rgb8(const RenderedFrame& frame, const DisplayTransform& display) {
    std::vector<std::uint8_t> rgb(frame.color.size() * 3);
    if (display.identity()) {
        encode_srgb8(frame.color, rgb.data());
    } else {
        std::vector<glm::vec3> shown(frame.color);
        apply_display(display, shown);
        encode_srgb8(shown, rgb.data());
    }
    return rgb;
}

void check_image_path(const std::filesystem::path& path) {
    if (!OIIO::ImageOutput::create(path.string())) {
        throw std::invalid_argument(path.string() +
                                    ": unknown image format (use .png, .exr, .jpg, .tif, ...)");
    }
    const std::filesystem::path parent = path.parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent)) {
        throw std::invalid_argument(path.string() + ": folder " + parent.string() +
                                    " does not exist");
    }
}

std::filesystem::path aov_path(const std::filesystem::path& image, Aov aov) {
    std::filesystem::path out = image;
    out.replace_filename(image.stem().string() + "." + kAovNames[int(aov)] + ".exr");
    return out;
}

void write_aov(const std::filesystem::path& image, Aov aov, const RenderedFrame& frame) {
    const std::filesystem::path path = aov_path(image, aov);
    std::vector<float> data;
    int channels = 1;
    std::vector<std::string> names;
    switch (aov) {
    case Aov::depth: data = frame.depth; break;
    case Aov::object: data.assign(frame.object.begin(), frame.object.end()); break;
    case Aov::prim: data.assign(frame.prim.begin(), frame.prim.end()); break;
    case Aov::normal:
        channels = 3;
        data.resize(frame.normal.size() * 3);
        for (std::size_t i = 0; i < frame.normal.size(); ++i) {
            for (int c = 0; c < 3; ++c) data[3 * i + c] = frame.normal[i][c];
        }
        break;
    case Aov::cost:
        if (frame.cost.size() != std::size_t(frame.width) * std::size_t(frame.height)) {
            throw std::invalid_argument(path.string() + ": the frame was traced without its pixel costs "
                                        "(TraceSettings::pixel_cost)");
        }
        channels = 2;
        names = {"nodes", "triangles"};
        data.resize(frame.cost.size() * 2);
        for (std::size_t i = 0; i < frame.cost.size(); ++i) {
            data[2 * i] = float(frame.cost[i].nodes);
            data[2 * i + 1] = float(frame.cost[i].triangles);
        }
        break;
    }
    write_pixels(path, frame.width, frame.height, channels, data.data(), OIIO::TypeDesc::FLOAT,
                 OIIO::TypeDesc::FLOAT, std::move(names));
}

}  // namespace dynrt
