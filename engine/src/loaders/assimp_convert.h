#pragma once
// What the assimp mapping's files share: assimp's row-major float matrices and vectors in the
// scene model's column-major double glm types, the error its helpers throw, and the lookup of
// nodes by name (assimp's bones, cameras, lights and animation channels name their node).

#include <assimp/matrix4x4.h>
#include <assimp/types.h>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace dynrt {

/// Bad data in an imported assimp scene (a bone naming no node, an index out of range); the
/// message says what is wrong, and load_assimp adds the file and the object.
class AssimpDataError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// assimp's aiMatrix4x4 (row-major: a1..a4 is the first row) as a column-major glm matrix.
inline glm::dmat4 to_dmat4(const aiMatrix4x4& m) {
    const ai_real* rows[4] = {&m.a1, &m.b1, &m.c1, &m.d1};
    glm::dmat4 out;
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 4; ++column) out[column][row] = double(rows[row][column]);
    }
    return out;
}

inline glm::dvec3 to_dvec3(const aiVector3D& v) { return {double(v.x), double(v.y), double(v.z)}; }

inline std::string to_string(const aiString& s) { return std::string(s.C_Str(), s.length); }

/// The scene node (index into Scene::nodes) of each assimp node name; the first node in
/// depth-first order when several share a name, as aiNode::FindNode finds it.
using AssimpNodeNames = std::unordered_map<std::string, std::int32_t>;

}  // namespace dynrt
