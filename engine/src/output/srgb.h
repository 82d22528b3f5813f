#pragma once
// The sRGB transfer function (IEC 61966-2-1), for 8-bit image files of linear colours.

#include <algorithm>
#include <cmath>

namespace dynrt {

/// Linear value -> sRGB-encoded value, both in [0, 1] (the input is clamped first).
inline float srgb_encode(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace dynrt
