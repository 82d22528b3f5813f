#pragma once
// The error the glTF helpers throw for bad data inside a model. It carries only "what is wrong";
// load_gltf knows the file and the object and turns it into the user-facing SceneError.

#include <stdexcept>

namespace dynrt {

/// Bad data inside a glTF model (accessor, index, node); message without file or object name.
class GltfDataError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace dynrt
