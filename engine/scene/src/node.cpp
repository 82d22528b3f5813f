// glTF 2.0 section 3.5.2 "Transformations": local = T * R * S, with the rotation matrix of a
// unit quaternion.

#include "dynrt/scene/node.h"

#include <cmath>

namespace dynrt {

glm::dmat3 quaternion_matrix(const glm::dvec4& q) {
    const double length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    const double x = q.x / length, y = q.y / length, z = q.z / length, w = q.w / length;
    glm::dmat3 r;  // r[column][row]
    r[0] = glm::dvec3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y));
    r[1] = glm::dvec3(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x));
    r[2] = glm::dvec3(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));
    return r;
}

glm::dmat4 trs_matrix(const glm::dvec3& translation, const glm::dvec4& rotation, const glm::dvec3& scale) {
    const glm::dmat3 r = quaternion_matrix(rotation);
    glm::dmat4 m(1.0);
    for (int column = 0; column < 3; ++column) m[column] = glm::dvec4(r[column] * scale[column], 0.0);
    m[3] = glm::dvec4(translation, 1.0);
    return m;
}

glm::dmat4 Node::rest_local() const { return matrix ? *matrix : trs_matrix(translation, rotation, scale); }

}  // namespace dynrt
