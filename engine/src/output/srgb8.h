#pragma once
// Linear colours straight to 8-bit sRGB, with exactly the bytes of the float path it replaces:
// srgb_encode (srgb.h, a pow per channel) into a float buffer, then OpenImageIO's float to
// UINT8 conversion, which is round(v * 255) half away from zero, i.e. std::lround (checked over
// every float in [0, 1]). That composition is non-decreasing in the input (also checked over
// every float in [0, 1]), so it is a step function with 255 steps: the encoder keeps the step
// edges as float bit patterns (non-negative floats order as their bits do) and a coarse table
// keyed on the input's top bits gives the level at the start of its bucket; at most a step or
// two is added from there. The table is built from srgb_encode itself, once per process.

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace dynrt {

/// The 8-bit sRGB code of a linear value: std::lround(srgb_encode(linear) * 255), clamped to
/// [0, 1] first; NaN gives 0. Thread-safe.
std::uint8_t srgb8_encode(float linear);

/// `pixels` as 8-bit sRGB, RGB interleaved: `out` holds 3 * pixels.size() bytes. Thread-safe.
void encode_srgb8(std::span<const glm::vec3> pixels, std::uint8_t* out);

}  // namespace dynrt
