#pragma once
// Which files a loaded scene was read from (Scene::files), for the loaders to fill in.

#include "dynrt/scene/scene.h"

#include <string>
#include <vector>

namespace dynrt {

/// Sets scene.files to `read` (the files the loader opened, the scene file first) followed by
/// the files of the scene's textures, each path once in first-seen order.
void set_read_files(Scene& scene, const std::vector<std::string>& read);

}  // namespace dynrt
