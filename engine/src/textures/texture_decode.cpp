// decode_texture (texture_decode.h) over OpenImageIO's ImageInput: files by name, embedded
// images through an in-memory IOProxy under a name whose extension tells OpenImageIO the
// format.

#include "textures/texture_decode.h"

#include "textures/mip_pyramid.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>

namespace dynrt::textures {

namespace {

/// The file extension OpenImageIO picks a reader by, for an embedded image's MIME type.
std::string extension_of(const std::string& mime_type) {
    if (mime_type == "image/png") return ".png";
    if (mime_type == "image/jpeg" || mime_type == "image/jpg") return ".jpg";
    if (mime_type == "image/bmp") return ".bmp";
    if (mime_type == "image/gif") return ".gif";
    if (mime_type == "image/webp") return ".webp";
    if (mime_type == "image/ktx2") return ".ktx2";
    return ".png";  // glTF allows PNG and JPEG; a wrong guess fails to read and is reported
}

std::string one_line(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? std::string("no reason given") : text;
}

std::string too_large(long long width, long long height) {
    return std::to_string(width) + "x" + std::to_string(height) + " texels: dynrt holds images of 1 to " +
           std::to_string(kMaxTextureSide) + " texels a side";
}

bool fits(long long width, long long height) {
    return width > 0 && height > 0 && width <= kMaxTextureSide && height <= kMaxTextureSide;
}

void zero_non_finite(TexelArray& image) {
    if (!image.floating) return;
    const std::size_t n = image.bytes.size() / sizeof(float);
    for (std::size_t i = 0; i < n; ++i) {
        float v;
        std::memcpy(&v, image.bytes.data() + i * sizeof v, sizeof v);
        if (!std::isfinite(v)) {
            v = 0.0f;
            std::memcpy(image.bytes.data() + i * sizeof v, &v, sizeof v);
        }
    }
}

/// The texels given as an array, checked as the library API checks them.
TexelArray given_texels(const TexelArray& texels, std::string& problem) {
    if (!fits(texels.width, texels.height)) {
        problem = too_large(texels.width, texels.height);
        return {};
    }
    const std::size_t expected = std::size_t(texels.width) * std::size_t(texels.height) *
                                 std::size_t(texels.channels) * (texels.floating ? sizeof(float) : 1);
    if (texels.channels < 1 || texels.channels > 4 || texels.bytes.size() != expected) {
        problem = "its texel array does not hold width x height x channels (1-4) values";
        return {};
    }
    TexelArray image = texels;
    zero_non_finite(image);
    return image;
}

}  // namespace

TexelArray decode_texture(const Texture& texture, std::string& problem) {
    problem.clear();
    if (!texture.texels.empty()) return given_texels(texture.texels, problem);
    OIIO::ImageSpec config;
    // Colours as the file stores them: OpenImageIO would otherwise multiply RGB by alpha.
    config.attribute("oiio:UnassociatedAlpha", 1);
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    std::string name = texture.path;
    if (name.empty()) {
        if (texture.encoded.empty()) {
            problem = "the file holds no bytes for it";
            return {};
        }
        name = "embedded" + extension_of(texture.mime_type);
        // IOMemReader only reads; its constructor takes a non-const pointer.
        proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(const_cast<unsigned char*>(texture.encoded.data()),
                                                                texture.encoded.size());
        // OpenImageIO 2.4's readers take the proxy from the configuration.
        OIIO::Filesystem::IOProxy* pointer = proxy.get();
        config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &pointer);
    } else {
        std::error_code ignored;
        if (!std::filesystem::exists(name, ignored)) {
            problem = "no such file";
            return {};
        }
    }
    std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(name, &config, proxy.get());
    if (!input) {
        problem = one_line(OIIO::geterror());
        return {};
    }
    const OIIO::ImageSpec& spec = input->spec();
    if (!fits(spec.width, spec.height) || spec.depth > 1) {
        problem = too_large(spec.width, std::int64_t(spec.height) * std::max(spec.depth, 1));
        return {};
    }
    if (spec.nchannels < 1) {
        problem = "it has no channels";
        return {};
    }
    TexelArray image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels = std::min(spec.nchannels, 4);
    image.floating = spec.format != OIIO::TypeDesc::UINT8 && spec.format != OIIO::TypeDesc::INT8;
    image.bytes.resize(std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels) *
                       (image.floating ? sizeof(float) : 1));
    const OIIO::TypeDesc format = image.floating ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
    if (!input->read_image(0, 0, 0, image.channels, format, image.bytes.data())) {
        problem = one_line(input->geterror());
        return {};
    }
    zero_non_finite(image);
    return image;
}

}  // namespace dynrt::textures
