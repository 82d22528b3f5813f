// Exposure and tone curves for 8-bit outputs (dynrt/engine/display_transform.h, which cites
// the curves).

#include "dynrt/engine/display_transform.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dynrt {

const char* tone_curve_name(ToneCurve curve) {
    switch (curve) {
        case ToneCurve::linear: return "linear";
        case ToneCurve::reinhard: return "reinhard";
        case ToneCurve::aces: return "aces";
    }
    return "unknown";
}

ToneCurve parse_tone_curve(std::string_view text) {
    for (const ToneCurve curve : {ToneCurve::linear, ToneCurve::reinhard, ToneCurve::aces}) {
        if (text == tone_curve_name(curve)) return curve;
    }
    throw std::invalid_argument("tone curve '" + std::string(text) + "': expected linear, reinhard or aces");
}

namespace {

float tone(ToneCurve curve, float x) {
    // Negative channels show black, as the encoder clamps them; NaN stays NaN (black too). Past
    // 65504 both curves have reached white, and their squares would overflow to inf / inf.
    if (x < 0.0f) x = 0.0f;
    if (curve != ToneCurve::linear && x > 65504.0f) x = 65504.0f;
    switch (curve) {
        case ToneCurve::linear: return x;
        case ToneCurve::reinhard: return x / (1.0f + x);
        case ToneCurve::aces: return (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    }
    return x;
}

}  // namespace

glm::vec3 DisplayTransform::apply(const glm::vec3& linear) const {
    const float scale = std::exp2(exposure);
    return {tone(curve, linear.x * scale), tone(curve, linear.y * scale), tone(curve, linear.z * scale)};
}

void apply_display(const DisplayTransform& display, std::span<glm::vec3> colors) {
    if (display.identity()) return;
    for (glm::vec3& c : colors) c = display.apply(c);
}

}  // namespace dynrt
