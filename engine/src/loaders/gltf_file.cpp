// GLB container layout (glTF 2.0 section 4.4): a 12-byte header (magic "glTF", version 2, total
// length) then chunks of (length, type, data), the first one JSON, an optional second one BIN.
// tinygltf 2.7 checks the BIN chunk's length against the GLB length without its 8-byte header,
// so a corrupt file could make it read past the end; the container is checked here first.

#include "gltf_file.h"

#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/warnings.h"

#include "message_text.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

namespace dynrt {

namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::size_t kGlbHeaderSize = 12;
constexpr std::size_t kChunkHeaderSize = 8;

[[noreturn]] void fail(const std::string& name, const std::string& what) {
    throw SceneError(cat(name, ": ", what));
}

std::string lowercase_extension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension;
}

/// tinygltf messages are several lines; a SceneError is one.
std::string one_line(const std::string& text) {
    std::string line;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::string piece = text.substr(start, end - start);
        if (!piece.empty()) {
            if (!line.empty()) line += "; ";
            line += piece;
        }
        start = end + 1;
    }
    return line;
}

/// The loader callback for images: nothing is decoded here (the renderer reads textures
/// through OpenImageIO), and a missing or unreadable image is no error. A data: URI's bytes,
/// which exist nowhere else, are kept in Image::image; an external file is kept as its uri,
/// and an image in a bufferView is read from the buffer by the loader, with bounds checks.
bool keep_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && image->uri.empty() && bytes != nullptr && size > 0) {
        image->image.assign(bytes, bytes + size);
        image->as_is = true;
    }
    return true;
}

/// Passes tinygltf's warnings (one per line of `warnings`) to dynrt::warn, less those the
/// renderer words better or that are no problem.
void report_warnings(const std::string& name, const std::string& warnings) {
    std::size_t start = 0;
    while (start < warnings.size()) {
        std::size_t end = warnings.find('\n', start);
        if (end == std::string::npos) end = warnings.size();
        const std::string line = warnings.substr(start, end - start);
        // A missing texture is told by the renderer, naming the material that uses it; tinygltf
        // words those as "... for image[i] ..." plus, before it, "File not found" (or "File
        // read error", "File is empty") lines that only optional files, images, produce.
        const bool about_image = line.find("image") != std::string::npos || line.rfind("File ", 0) == 0;
        // tinygltf 2.7 calls a skin without inverseBindMatrices incomplete; glTF 2.0 makes them
        // optional (identity), and the loader supplies that.
        const bool about_optional = line.find("'inverseBindMatrices' property is missing") != std::string::npos;
        if (!line.empty() && !about_image && !about_optional) {
            warn({.source = name, .kind = "glTF reader's warning", .kinds = "glTF reader's warnings", .item = line});
        }
        start = end + 1;
    }
}

std::vector<unsigned char> read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path.string(), "cannot open file");
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) fail(path.string(), "cannot read file");
    return bytes;
}

std::uint32_t read_u32(std::span<const unsigned char> bytes, std::size_t offset) {
    return static_cast<std::uint32_t>(bytes[offset]) | static_cast<std::uint32_t>(bytes[offset + 1]) << 8 |
           static_cast<std::uint32_t>(bytes[offset + 2]) << 16 |
           static_cast<std::uint32_t>(bytes[offset + 3]) << 24;
}

/// Checks the GLB header and that every chunk lies within the declared length; returns it.
std::size_t check_glb_container(const std::string& path, std::span<const unsigned char> bytes) {
    if (bytes.size() < kGlbHeaderSize) {
        fail(path, cat("truncated GLB: ", bytes.size(), " bytes, shorter than the 12-byte header"));
    }
    if (read_u32(bytes, 0) != kGlbMagic) fail(path, "not a GLB file (the first 4 bytes are not 'glTF')");
    const std::uint32_t version = read_u32(bytes, 4);
    if (version != 2) fail(path, cat("unsupported GLB version ", version, " (expected 2)"));
    const std::size_t length = read_u32(bytes, 8);
    if (length > bytes.size()) {
        fail(path, cat("truncated GLB: the header says ", length, " bytes, the file has ", bytes.size()));
    }
    std::size_t offset = kGlbHeaderSize;
    for (int chunk = 0; offset < length; ++chunk) {
        if (length - offset < kChunkHeaderSize) {
            fail(path, cat("truncated GLB: chunk ", chunk, " header at byte ", offset, " is cut off"));
        }
        const std::size_t chunk_length = read_u32(bytes, offset);
        const std::uint32_t chunk_type = read_u32(bytes, offset + 4);
        if (chunk == 0 && chunk_type != kChunkJson) fail(path, "corrupt GLB: the first chunk is not JSON");
        if (chunk_length > length - offset - kChunkHeaderSize) {
            fail(path, cat("truncated GLB: chunk ", chunk, " at byte ", offset, " claims ", chunk_length,
                           " bytes, only ", length - offset - kChunkHeaderSize, " remain"));
        }
        offset += kChunkHeaderSize + chunk_length;
    }
    if (length == kGlbHeaderSize) fail(path, "truncated GLB: no JSON chunk");
    return length;
}

/// Runs `load` (a tinygltf call) and turns its result into a model or one SceneError line.
template <class Load>
tinygltf::Model run_tinygltf(tinygltf::TinyGLTF& loader, const std::string& name, const Load& load) {
    loader.SetImageLoader(&keep_image, nullptr);
    tinygltf::Model model;
    std::string error, warnings;
    bool ok = false;
    // tinygltf reports through its return value, but its JSON library and some container
    // accesses can still throw on hostile input.
    try {
        ok = load(model, error, warnings);
    } catch (const SceneError&) {
        throw;
    } catch (const std::exception& e) {
        fail(name, cat("invalid glTF: ", e.what()));
    }
    if (!ok) {
        const std::string reason = one_line(error);
        fail(name, cat("invalid glTF: ", reason.empty() ? std::string("tinygltf gave no reason") : reason));
    }
    // tinygltf also appends non-fatal problems to `error` while succeeding.
    report_warnings(name, warnings + "\n" + error);
    return model;
}

/// Parses a whole document held in `bytes`; external files are looked up under `base_dir`
/// through the loader's filesystem callbacks.
tinygltf::Model parse_model(tinygltf::TinyGLTF& loader, std::span<const unsigned char> bytes, GltfFormat format,
                            const std::string& name, const std::string& base_dir) {
    if (format == GltfFormat::binary) {
        // The checked length comes from the 32-bit header field, so the cast is lossless.
        const std::size_t length = check_glb_container(name, bytes);
        return run_tinygltf(loader, name, [&](tinygltf::Model& model, std::string& error, std::string& warnings) {
            return loader.LoadBinaryFromMemory(&model, &error, &warnings, bytes.data(),
                                               static_cast<unsigned int>(length), base_dir);
        });
    }
    if (bytes.size() > UINT32_MAX) fail(name, cat("a ", bytes.size(), "-byte glTF is larger than 4 GiB"));
    return run_tinygltf(loader, name, [&](tinygltf::Model& model, std::string& error, std::string& warnings) {
        return loader.LoadASCIIFromString(&model, &error, &warnings, reinterpret_cast<const char*>(bytes.data()),
                                          static_cast<unsigned int>(bytes.size()), base_dir);
    });
}

// Filesystem callbacks for a document loaded from memory. Every file "exists" but cannot be
// read, so tinygltf names the URI in its "File read error" (an error for a buffer, a dropped
// warning for an image) and never touches the disk.
bool claim_file_exists(const std::string&, void*) { return true; }
std::string keep_file_path(const std::string& path, void*) { return path; }
bool refuse_file_read(std::vector<unsigned char>*, std::string* error, const std::string&, void*) {
    if (error != nullptr) *error = "only data: URIs can be read in a glTF loaded from memory";
    return false;
}
bool refuse_file_write(std::string* error, const std::string&, const std::vector<unsigned char>&, void*) {
    if (error != nullptr) *error = "a glTF loaded from memory writes no files";
    return false;
}

}  // namespace

bool is_gltf_path(const std::filesystem::path& path) {
    const std::string extension = lowercase_extension(path);
    return extension == ".gltf" || extension == ".glb";
}

tinygltf::Model read_gltf_model(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail(path.string(), "no such file");
    if (std::filesystem::is_directory(path, ec)) fail(path.string(), "is a directory, not a glTF file");

    tinygltf::TinyGLTF loader;
    if (lowercase_extension(path) == ".glb") {
        const std::vector<unsigned char> bytes = read_bytes(path);
        return parse_model(loader, bytes, GltfFormat::binary, path.string(), path.parent_path().string());
    }
    return run_tinygltf(loader, path.string(), [&](tinygltf::Model& model, std::string& error, std::string& warnings) {
        return loader.LoadASCIIFromFile(&model, &error, &warnings, path.string());
    });
}

tinygltf::Model read_gltf_model_from_memory(std::span<const unsigned char> bytes, GltfFormat format,
                                            const std::string& name) {
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks no_filesystem{.FileExists = &claim_file_exists,
                                        .ExpandFilePath = &keep_file_path,
                                        .ReadWholeFile = &refuse_file_read,
                                        .WriteWholeFile = &refuse_file_write,
                                        .user_data = nullptr};
    loader.SetFsCallbacks(no_filesystem);
    return parse_model(loader, bytes, format, name, "");
}

}  // namespace dynrt
