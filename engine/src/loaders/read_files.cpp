#include "read_files.h"

#include <algorithm>

namespace dynrt {

void set_read_files(Scene& scene, const std::vector<std::string>& read) {
    scene.files.clear();
    const auto add = [&](const std::string& path) {
        if (!path.empty() && std::find(scene.files.begin(), scene.files.end(), path) == scene.files.end()) {
            scene.files.push_back(path);
        }
    };
    for (const std::string& path : read) add(path);
    for (const Texture& texture : scene.textures) add(texture.path);
}

}  // namespace dynrt
