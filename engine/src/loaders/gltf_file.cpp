// GLB container layout (glTF 2.0 section 4.4): a 12-byte header (magic "glTF", version 2, total
// length) then chunks of (length, type, data), the first one JSON, an optional second one BIN.
// tinygltf 2.7 checks the BIN chunk's length against the GLB length without its 8-byte header,
// so a corrupt file could make it read past the end; the container is checked here first.

#include "gltf_file.h"

#include "dynrt/scene/scene_error.h"
#include "dynrt/scene/warnings.h"

#include "message_text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dynrt {

namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
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

std::uint32_t read_u32(std::span<const unsigned char> bytes, std::size_t offset) {
    return static_cast<std::uint32_t>(bytes[offset]) | static_cast<std::uint32_t>(bytes[offset + 1]) << 8 |
           static_cast<std::uint32_t>(bytes[offset + 2]) << 16 |
           static_cast<std::uint32_t>(bytes[offset + 3]) << 24;
}

/// One chunk of a GLB: where its data starts, its length and type.
struct GlbChunk {
    std::size_t offset = 0;
    std::size_t length = 0;
    std::uint32_t type = 0;
};

/// Checks the GLB header and that every chunk lies within the declared length, reading the
/// container's `size` bytes through `read(offset, count)` (the header and chunk headers only);
/// returns its chunks.
template <class Read>
std::vector<GlbChunk> check_glb_container(const std::string& path, std::size_t size, const Read& read) {
    if (size < kGlbHeaderSize) {
        fail(path, cat("truncated GLB: ", size, " bytes, shorter than the 12-byte header"));
    }
    const std::vector<unsigned char> header = read(0, kGlbHeaderSize);
    if (read_u32(header, 0) != kGlbMagic) fail(path, "not a GLB file (the first 4 bytes are not 'glTF')");
    const std::uint32_t version = read_u32(header, 4);
    if (version != 2) fail(path, cat("unsupported GLB version ", version, " (expected 2)"));
    const std::size_t length = read_u32(header, 8);
    if (length > size) {
        fail(path, cat("truncated GLB: the header says ", length, " bytes, the file has ", size));
    }
    if (length < kGlbHeaderSize) {
        fail(path, cat("corrupt GLB: the header says ", length, " bytes, shorter than the header itself"));
    }
    std::vector<GlbChunk> chunks;
    std::size_t offset = kGlbHeaderSize;
    for (int chunk = 0; offset < length; ++chunk) {
        if (length - offset < kChunkHeaderSize) {
            fail(path, cat("truncated GLB: chunk ", chunk, " header at byte ", offset, " is cut off"));
        }
        const std::vector<unsigned char> chunk_header = read(offset, kChunkHeaderSize);
        const std::size_t chunk_length = read_u32(chunk_header, 0);
        const std::uint32_t chunk_type = read_u32(chunk_header, 4);
        if (chunk == 0 && chunk_type != kChunkJson) fail(path, "corrupt GLB: the first chunk is not JSON");
        if (chunk_length > length - offset - kChunkHeaderSize) {
            fail(path, cat("truncated GLB: chunk ", chunk, " at byte ", offset, " claims ", chunk_length,
                           " bytes, only ", length - offset - kChunkHeaderSize, " remain"));
        }
        chunks.push_back(GlbChunk{offset + kChunkHeaderSize, chunk_length, chunk_type});
        offset += kChunkHeaderSize + chunk_length;
    }
    if (chunks.empty()) fail(path, "truncated GLB: no JSON chunk");
    return chunks;
}

/// check_glb_container over bytes in memory; returns the container's length.
std::size_t check_glb_bytes(const std::string& path, std::span<const unsigned char> bytes) {
    const std::vector<GlbChunk> chunks =
        check_glb_container(path, bytes.size(), [&](std::size_t offset, std::size_t count) {
            return std::vector<unsigned char>(bytes.begin() + std::ptrdiff_t(offset),
                                              bytes.begin() + std::ptrdiff_t(offset + count));
        });
    return chunks.back().offset + chunks.back().length;
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
        const std::size_t length = check_glb_bytes(name, bytes);
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

// A GLB read from its file, once: tinygltf copies a GLB's BIN chunk out of the bytes it is
// given, so reading the whole file first held the data twice. Instead the JSON chunk alone is
// read and handed to tinygltf as a .gltf document whose buffer 0 names the BIN chunk by a URI of
// dynrt's own, which the filesystem callbacks below read from the file straight into the
// buffer (tinygltf swaps the vector it is given into place).
constexpr std::string_view kBinChunkUri = "dynrt-glb-bin-chunk:";

/// Where buffer 0's bytes lie in the GLB file, for the callbacks.
struct BinChunkSource {
    std::filesystem::path file;
    std::size_t offset = 0;
    std::size_t length = 0;  ///< buffer 0's byteLength (at most the chunk's)
};

bool names_bin_chunk(const std::string& path) { return path.ends_with(kBinChunkUri); }

bool glb_file_exists(const std::string& path, void* user) {
    return names_bin_chunk(path) || tinygltf::FileExists(path, user);
}

bool read_file_or_bin_chunk(std::vector<unsigned char>* out, std::string* error, const std::string& path,
                            void* user) {
    if (!names_bin_chunk(path)) return tinygltf::ReadWholeFile(out, error, path, nullptr);
    const BinChunkSource& source = *static_cast<const BinChunkSource*>(user);
    std::ifstream in(source.file, std::ios::binary);
    out->resize(source.length);
    in.seekg(std::streamoff(source.offset));
    in.read(reinterpret_cast<char*>(out->data()), std::streamsize(source.length));
    if (!in) {
        if (error) *error = "cannot read the GLB's BIN chunk";
        return false;
    }
    return true;
}

/// Reads the GLB at `path` (its container checked first) into a model, its BIN chunk once.
tinygltf::Model read_glb_file(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(name, "cannot open file");
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) fail(name, "cannot read file");
    const auto read = [&](std::size_t offset, std::size_t count) {
        std::vector<unsigned char> bytes(count);
        in.seekg(std::streamoff(offset));
        in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(count));
        if (!in) fail(name, "cannot read file");
        return bytes;
    };
    const std::vector<GlbChunk> chunks = check_glb_container(name, std::size_t(size), read);
    const std::vector<unsigned char> json_bytes = read(chunks[0].offset, chunks[0].length);
    std::string json(json_bytes.begin(), json_bytes.end());
    BinChunkSource source{path, 0, 0};
    // tinygltf's own checks of the BIN chunk, with its words.
    if (chunks.size() > 1) {
        const GlbChunk& bin = chunks[1];
        if (bin.length < 4) fail(name, "invalid glTF: Insufficient Chunk1(BIN) data size.");
        if (bin.length % 4 != 0) fail(name, "invalid glTF: BIN Chunk end does not aligned to a 4-byte boundary.");
        if (bin.type != kChunkBin) fail(name, "invalid glTF: Invalid type for chunk1 data.");
    }
    // Buffer 0 without a URI is the BIN chunk (glTF 2.0 section 4.4.3.3): give it dynrt's URI.
    // A document that does not parse here is handed over as it is, for tinygltf to report.
    nlohmann::json document = nlohmann::json::parse(json, nullptr, false);
    if (!document.is_discarded() && document.is_object() && document.contains("buffers") &&
        document["buffers"].is_array() && !document["buffers"].empty() && document["buffers"][0].is_object() &&
        !document["buffers"][0].contains("uri")) {
        nlohmann::json& buffer = document["buffers"][0];
        if (chunks.size() < 2) fail(name, "invalid glTF: Invalid binary data in `Buffer', or GLB with empty BIN chunk.");
        if (buffer.contains("byteLength") && buffer["byteLength"].is_number_unsigned()) {
            const std::uint64_t length = buffer["byteLength"].get<std::uint64_t>();
            if (length > chunks[1].length) {
                fail(name, cat("invalid glTF: Invalid `byteLength'. Must be equal or less than binary size: "
                               "`byteLength' = ", length, ", binary size = ", chunks[1].length));
            }
            source.offset = chunks[1].offset;
            source.length = std::size_t(length);
            buffer["uri"] = std::string(kBinChunkUri);
            try {
                json = document.dump();
            } catch (const std::exception& e) {
                fail(name, cat("invalid glTF: ", e.what()));
            }
        }
    }
    document = nullptr;
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks files{.FileExists = &glb_file_exists,
                                .ExpandFilePath = &tinygltf::ExpandFilePath,
                                .ReadWholeFile = &read_file_or_bin_chunk,
                                .WriteWholeFile = &tinygltf::WriteWholeFile,
                                .user_data = &source};
    loader.SetFsCallbacks(files);
    if (json.size() > UINT32_MAX) fail(name, cat("a ", json.size(), "-byte glTF JSON chunk is larger than 4 GiB"));
    tinygltf::Model model = run_tinygltf(loader, name, [&](tinygltf::Model& m, std::string& error, std::string& warnings) {
        return loader.LoadASCIIFromString(&m, &error, &warnings, json.data(), static_cast<unsigned int>(json.size()),
                                          path.parent_path().string());
    });
    // The URI was dynrt's, not the file's.
    if (source.length != 0 && !model.buffers.empty()) model.buffers[0].uri.clear();
    return model;
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
    if (lowercase_extension(path) == ".glb") return read_glb_file(path);
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
