#include "dynrt/api/engine.h"
#include "dynrt/api/types.h"

#include <cmath>

namespace dynrt {

Transform Transform::from_column_major(const float* values) {
    Transform t;
    for (int i = 0; i < 16; ++i) t.m[i] = values[i];
    return t;
}

Transform Transform::translation(Vec3 offset) {
    Transform t;
    t.m[12] = offset.x;
    t.m[13] = offset.y;
    t.m[14] = offset.z;
    return t;
}

Transform Transform::rotation(Vec3 axis, float radians, Vec3 offset) {
    // Rodrigues' formula: R = c I + s [a]x + (1 - c) a a^T, for the unit axis a.
    const float c = std::cos(radians), s = std::sin(radians), k = 1.0f - c;
    const float x = axis.x, y = axis.y, z = axis.z;
    Transform t;
    t.m = {c + k * x * x,     k * x * y + s * z, k * x * z - s * y, 0.0f,
           k * x * y - s * z, c + k * y * y,     k * y * z + s * x, 0.0f,
           k * x * z + s * y, k * y * z - s * x, c + k * z * z,     0.0f,
           offset.x,          offset.y,          offset.z,          1.0f};
    return t;
}

const char* motion_name(Motion motion) {
    switch (motion) {
        case Motion::automatic: return "automatic";
        case Motion::static_: return "static";
        case Motion::rigid: return "rigid";
        case Motion::deformable: return "deformable";
        case Motion::exploding: return "exploding";
    }
    return "unknown";
}

}  // namespace dynrt
