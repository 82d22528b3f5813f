// The front door for scene input: file or spec, and where the bundled default scene lives.

#include "dynrt/engine/scene_loading.h"

#include "aff_parser.h"
#include "aff_scene.h"
#include "gltf_file.h"
#include "message_text.h"
#include "read_files.h"
#include "scene_copies.h"
#include "scene_file_kind.h"

#include "dynrt/scene/scene_error.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

namespace dynrt {

namespace {

bool is_aff_path(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".aff";
}

/// A file with GLB's magic but another extension: read as self-contained GLB.
Scene load_glb_by_content(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && in.fail()) throw SceneError(cat(path, ": cannot read the file"));
    return load_gltf_from_memory(bytes, GltfFormat::binary, path);
}

}  // namespace

Scene load_scene(const std::string& source) {
    // Every loader ends with check_scene, so the result already meets the contract.
    std::error_code ec;
    if (!std::filesystem::exists(source, ec)) {
        // FILE*K: K copies of a scene file on a grid, sharing its meshes.
        if (const std::optional<CopiesSpec> copies = parse_copies_spec(source);
            copies && std::filesystem::is_regular_file(copies->file, ec)) {
            Scene scene = load_scene(copies->file);
            make_copies(scene, copies->copies, source);
            return scene;
        }
        if (is_gltf_path(source) || is_aff_path(source) || looks_like_file_path(source)) {
            throw SceneError(cat(source, ": no such file"));
        }
        return make_procedural_scene(source);
    }
    if (std::filesystem::is_directory(source, ec)) throw SceneError(cat(source, ": is a folder, not a scene file"));
    switch (scene_file_kind(source)) {
        case SceneFileKind::gltf:
            if (is_gltf_path(source)) return load_gltf(source);
            return load_glb_by_content(source);
        case SceneFileKind::aff:
            return load_aff(source);
        case SceneFileKind::assimp:
            break;
    }
    return load_assimp(source);
}

Scene load_aff(const std::filesystem::path& path) {
    const aff::AffModel model = aff::parse_aff_file(path);
    Scene scene = aff::scene_from_aff(model, path.string());
    set_read_files(scene, model.files);
    check_scene(scene);
    return scene;
}

Scene load_aff_text(std::string_view text, const std::filesystem::path& name) {
    Scene scene = aff::scene_from_aff(aff::parse_aff_text(text, name), name.string());
    check_scene(scene);
    return scene;
}

std::filesystem::path default_scene_path() {
    // A build tree runs from next to its sources; an installed binary finds the scene under
    // <prefix>/share/dynrt/scenes. When neither exists, the source path makes the clearer error.
    const std::filesystem::path in_source_tree =
        std::filesystem::path(DYNRT_SOURCE_SCENES_DIR) / "default.gltf";
    std::error_code ec;
    if (std::filesystem::exists(in_source_tree, ec)) return in_source_tree;
    const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path installed =
            (executable.parent_path() / ".." / "share" / "dynrt" / "scenes" / "default.gltf")
                .lexically_normal();
        if (std::filesystem::exists(installed, ec)) return installed;
    }
    return in_source_tree;
}

}  // namespace dynrt
