#pragma once

#include <stdexcept>
#include <string>

namespace dynrt {

/// Thrown for bad scene input (missing or malformed files, bad specs, out-of-range indices,
/// non-finite positions, no triangles). `what()` is one line naming the source, the object when
/// there is one, and what is wrong, ready to print to a user.
class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace dynrt
