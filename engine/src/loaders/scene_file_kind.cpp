// Telling a scene file's kind by its extension and content (scene_file_kind.h).

#include "scene_file_kind.h"

#include "gltf_file.h"

#include <cctype>
#include <fstream>

namespace dynrt {

namespace {

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool starts_with_glb_magic(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    return in.read(magic, 4) && magic[0] == 'g' && magic[1] == 'l' && magic[2] == 'T' && magic[3] == 'F';
}

}  // namespace

SceneFileKind scene_file_kind(const std::filesystem::path& path) {
    if (is_gltf_path(path) || starts_with_glb_magic(path)) return SceneFileKind::gltf;
    if (lower_extension(path) == ".aff") return SceneFileKind::aff;
    return SceneFileKind::assimp;
}

bool looks_like_file_path(const std::string& source) {
    if (source.find('/') != std::string::npos) return true;
    const std::string ext = std::filesystem::path(source).extension().string();
    if (ext.size() < 2 || !std::isalpha(static_cast<unsigned char>(ext[1]))) return false;
    for (std::size_t i = 1; i < ext.size(); ++i) {
        if (!std::isalnum(static_cast<unsigned char>(ext[i]))) return false;
    }
    return true;
}

}  // namespace dynrt
