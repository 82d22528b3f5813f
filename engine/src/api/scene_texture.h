#pragma once
// The scene's Texture for a TextureDesc (Engine::add_texture), and its wrap mode for a Surface's,
// checked: one source among a path,
// an image file's bytes and an array of texels, and texels that keep TextureDesc's rules. A pure
// function of the description, kept in a header so that tests/api checks the Texture it makes
// (libdynrt exports only the API).

#include "dynrt/api/engine.h"
#include "dynrt/api/error.h"
#include "dynrt/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <sstream>
#include <string>
#include <system_error>

namespace dynrt::api_detail {

/// The longest side of a texel array: the longest dynrt holds (scene.h).
inline constexpr int kTexelSideMax = kMaxTextureSide;

/// The MIME type an image file's first bytes announce, or "" when they announce none known.
inline std::string mime_type_of(std::span<const unsigned char> bytes) {
    const auto starts = [&](std::initializer_list<unsigned char> head, std::size_t at = 0) {
        return bytes.size() >= at + head.size() && std::equal(head.begin(), head.end(), bytes.begin() + std::ptrdiff_t(at));
    };
    if (starts({0x89, 'P', 'N', 'G'})) return "image/png";
    if (starts({0xFF, 0xD8, 0xFF})) return "image/jpeg";
    if (starts({'G', 'I', 'F', '8'})) return "image/gif";
    if (starts({'R', 'I', 'F', 'F'}) && starts({'W', 'E', 'B', 'P'}, 8)) return "image/webp";
    if (starts({'B', 'M'})) return "image/bmp";
    return {};
}

/// Whether `desc` gives texels (values, or any of their sizes): then it must give them right.
inline bool gives_texels(const TextureDesc& desc) {
    return !desc.texels8.empty() || !desc.texels_float.empty() || desc.width != 0 || desc.height != 0 ||
           desc.channels != 0;
}

/// `desc`'s texels, checked (TextureDesc's rules) and copied; `what` starts each error message.
inline TexelArray checked_texels(const TextureDesc& desc, const std::string& what) {
    const auto invalid = [&](const std::string& message) {
        return Error(Error::Code::invalid_argument, "dynrt::Engine: " + what + ": " + message);
    };
    if (!desc.texels8.empty() && !desc.texels_float.empty()) {
        throw invalid("give texels8 or texels_float, not both");
    }
    if (desc.width < 1 || desc.width > kTexelSideMax || desc.height < 1 || desc.height > kTexelSideMax) {
        throw invalid("texels' size " + std::to_string(desc.width) + " x " + std::to_string(desc.height) +
                      ": each side must be in [1, " + std::to_string(kTexelSideMax) + "]");
    }
    if (desc.channels < 1 || desc.channels > 4) {
        throw invalid("texels have " + std::to_string(desc.channels) +
                      " channels, not 1 to 4 (grey, grey and alpha, RGB, RGBA)");
    }
    const bool floating = !desc.texels_float.empty();
    const std::size_t count = std::size_t(desc.width) * std::size_t(desc.height) * std::size_t(desc.channels);
    const std::size_t given = floating ? desc.texels_float.size() : desc.texels8.size();
    const std::string expected = std::to_string(desc.width) + " x " + std::to_string(desc.height) + " x " +
                                 std::to_string(desc.channels) + " = " + std::to_string(count) + " expected";
    if (given == 0) throw invalid("no texels in texels8 or texels_float, " + expected);
    if (given != count) {
        throw invalid(std::string(floating ? "texels_float" : "texels8") + " holds " + std::to_string(given) +
                      " values, " + expected);
    }
    if (floating) {
        // A negative texel would shade darker than black, as a negative diffuse colour would
        // (add_mesh refuses those).
        const auto bad = std::find_if(desc.texels_float.begin(), desc.texels_float.end(),
                                      [](float v) { return !(std::isfinite(v) && v >= 0.0f); });
        if (bad != desc.texels_float.end()) {
            const std::size_t k = std::size_t(bad - desc.texels_float.begin());
            const std::size_t texel = k / std::size_t(desc.channels);
            std::ostringstream out;
            out << "texels_float value " << k << " (texel x " << texel % std::size_t(desc.width) << ", y "
                << texel / std::size_t(desc.width) << ", channel " << k % std::size_t(desc.channels) << ") is "
                << *bad << ": texels must be finite and >= 0";
            throw invalid(out.str());
        }
    }
    TexelArray texels;
    texels.width = desc.width;
    texels.height = desc.height;
    texels.channels = desc.channels;
    texels.floating = floating;
    texels.bytes.resize(floating ? count * sizeof(float) : count);
    if (floating) {
        std::memcpy(texels.bytes.data(), desc.texels_float.data(), texels.bytes.size());
    } else {
        std::memcpy(texels.bytes.data(), desc.texels8.data(), texels.bytes.size());
    }
    return texels;
}

/// The scene's wrap mode for a Surface's.
inline TextureWrap scene_wrap(Wrap wrap) {
    switch (wrap) {
        case Wrap::repeat: return TextureWrap::repeat;
        case Wrap::clamp: return TextureWrap::clamp;
        case Wrap::mirror: return TextureWrap::mirror;
    }
    return TextureWrap::repeat;
}

/// The scene's Texture for `desc`, added as texture `id` (which names it when `desc` gives no
/// name and no path). Throws Error (invalid_argument) naming the texture for a bad description.
inline Texture texture_of(const TextureDesc& desc, std::uint32_t id) {
    Texture texture;
    texture.name = !desc.name.empty() ? desc.name : !desc.path.empty() ? desc.path : "texture " + std::to_string(id);
    const std::string what = "add_texture '" + texture.name + "'";
    const bool path = !desc.path.empty(), bytes = !desc.encoded.empty(), texels = gives_texels(desc);
    if (!path && !bytes && !texels) {
        throw Error(Error::Code::invalid_argument,
                    "dynrt::Engine: " + what +
                        ": no path and no bytes (an image file's path, its bytes, or an array of texels is needed)");
    }
    if (int(path) + int(bytes) + int(texels) > 1) {
        const std::string given = path && bytes && texels ? "a path, bytes and texels"
                                  : path && bytes         ? "a path and bytes"
                                  : path                  ? "a path and texels"
                                                          : "bytes and texels";
        throw Error(Error::Code::invalid_argument,
                    "dynrt::Engine: " + what + ": give one of a path, bytes or texels, not several (" + given + ")");
    }
    if (texels) texture.texels = checked_texels(desc, what);
    // Read at the first render that shows it: made absolute now, so that it names the file it
    // named here whatever the working folder is then.
    if (path) {
        std::error_code ignored;
        const std::filesystem::path absolute = std::filesystem::absolute(desc.path, ignored);
        texture.path = absolute.empty() ? desc.path : absolute.string();
    }
    texture.encoded.assign(desc.encoded.begin(), desc.encoded.end());
    texture.mime_type = desc.mime_type.empty() ? mime_type_of(desc.encoded) : desc.mime_type;
    texture.srgb = desc.srgb;
    return texture;
}

}  // namespace dynrt::api_detail
