// The front door for scene input: file or spec, and where the bundled default scene lives.

#include "dynrt/engine/scene_loading.h"

#include "gltf_file.h"

#include <system_error>

namespace dynrt {

Scene load_scene(const std::string& source) {
    // Both loaders end with check_scene, so the result already meets the contract.
    if (is_gltf_path(source)) return load_gltf(source);
    return make_procedural_scene(source);
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
