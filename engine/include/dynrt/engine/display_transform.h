#pragma once
// How a render's linear colours become an 8-bit image's (PNG, JPEG, GIF, video, the contact
// sheet): exposure, then a tone curve, then sRGB encoding. Float outputs (.exr, .hdr, .pfm) stay
// linear, untouched. The identity (exposure 0, linear curve), the default, writes the bytes a
// renderer without it wrote.
//
//   linear    clamps to [0, 1] (values above 1 clip);
//   reinhard  x / (1 + x) per channel (Reinhard et al. 2002, "Photographic tone reproduction
//             for digital images", the global operator);
//   aces      Narkowicz's fit of the ACES filmic curve (2015, "ACES filmic tone mapping
//             curve"): x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), per channel.

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <string_view>

namespace dynrt {

enum class ToneCurve : std::uint8_t { linear, reinhard, aces };

/// "linear", "reinhard", "aces".
const char* tone_curve_name(ToneCurve curve);
/// Reads a tone_curve_name; throws std::invalid_argument naming the text and the choices.
ToneCurve parse_tone_curve(std::string_view text);

struct DisplayTransform {
    /// Stops: colours are multiplied by 2^exposure before the curve. Finite.
    float exposure = 0.0f;
    ToneCurve curve = ToneCurve::linear;

    bool identity() const { return exposure == 0.0f && curve == ToneCurve::linear; }
    /// One linear colour as the 8-bit encoder is to see it.
    glm::vec3 apply(const glm::vec3& linear) const;
    bool operator==(const DisplayTransform&) const = default;
};

/// apply() to every colour of `colors`, in place.
void apply_display(const DisplayTransform& display, std::span<glm::vec3> colors);

}  // namespace dynrt
