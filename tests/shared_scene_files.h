#pragma once
// Tests that read the third-party models in ../shared/scenes (DYNRT_SHARED_SCENES_DIR) skip
// cleanly when that folder is absent.

#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <filesystem>

/// Loads a shared glTF model into the Scene `scene`, or skips the test when it is not there.
#define LOAD_SHARED_OR_SKIP(scene, relative)                                                        \
    const std::filesystem::path scene##_path = std::filesystem::path(DYNRT_SHARED_SCENES_DIR) / relative; \
    if (!std::filesystem::exists(scene##_path)) GTEST_SKIP() << scene##_path << " does not exist"; \
    const ::dynrt::Scene scene = ::dynrt::load_gltf(scene##_path)
