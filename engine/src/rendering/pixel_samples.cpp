// Sample positions and light points (pixel_samples.h): Kollig and Keller 2002 ("Efficient
// multidimensional sampling") for the scrambled (0,2)-sequence, Ernst et al. 2006 ("Filter
// importance sampling") for the reconstruction filter as a distribution of sample offsets.

#include "rendering/pixel_samples.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace dynrt {

const char* pixel_filter_name(PixelFilter filter) {
    switch (filter) {
        case PixelFilter::box: return "box";
        case PixelFilter::tent: return "tent";
        case PixelFilter::blackman_harris: return "blackman-harris";
    }
    return "unknown";
}

PixelFilter parse_pixel_filter(std::string_view text) {
    for (PixelFilter f : {PixelFilter::box, PixelFilter::tent, PixelFilter::blackman_harris}) {
        if (text == pixel_filter_name(f)) return f;
    }
    throw std::invalid_argument("pixel filter '" + std::string(text) +
                                "': expected box, tent or blackman-harris");
}

void check_sampling(const PixelSampling& sampling) {
    if (sampling.spp < 1 || sampling.spp > PixelSampling::kMaxSamplesPerPixel) {
        throw std::invalid_argument("samples per pixel " + std::to_string(sampling.spp) + ": must be 1 to " +
                                    std::to_string(PixelSampling::kMaxSamplesPerPixel));
    }
    if (!(sampling.adaptive_contrast >= 0.0f) || !std::isfinite(sampling.adaptive_contrast)) {
        throw std::invalid_argument("adaptive sampling contrast " + std::to_string(sampling.adaptive_contrast) +
                                    ": must be finite and >= 0");
    }
}

std::string to_string(const PixelSampling& sampling) {
    std::string text = std::to_string(sampling.spp);
    if (sampling.spp > 1) text += std::string(" ") + pixel_filter_name(sampling.filter);
    if (sampling.adaptive_contrast > 0.0f) {
        char contrast[32];
        std::snprintf(contrast, sizeof contrast, " adaptive %g", double(sampling.adaptive_contrast));
        text += contrast;
    }
    return text;
}

namespace detail {

glm::uvec2 sequence_point(std::uint32_t index) {
    // Van der Corput: the index's bits mirrored about the binary point.
    std::uint32_t x = index;
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    // Sobol's second dimension: its direction numbers are the rows of Pascal's triangle mod 2,
    // each the one before XOR itself shifted right once.
    std::uint32_t y = 0;
    for (std::uint32_t bits = index, v = 1u << 31; bits != 0; bits >>= 1, v ^= v >> 1) {
        if (bits & 1u) y ^= v;
    }
    return {x, y};
}

namespace {

/// Blackman-Harris' four terms (Harris 1978), over a window kBlackmanHarrisRadius on each side.
constexpr double kBh[4] = {0.35875, 0.48829, 0.14128, 0.01168};
constexpr double kBlackmanHarrisRadius = 0.75;

double blackman_harris(double x) {
    if (std::abs(x) >= kBlackmanHarrisRadius) return 0.0;
    const double t = 2.0 * std::numbers::pi * (x / (2.0 * kBlackmanHarrisRadius) + 0.5);
    return kBh[0] - kBh[1] * std::cos(t) + kBh[2] * std::cos(2.0 * t) - kBh[3] * std::cos(3.0 * t);
}

/// The window's integral over [-r, r] is 2 r kBh[0] (the cosines integrate to zero).
constexpr double kBlackmanHarrisArea = 2.0 * kBlackmanHarrisRadius * kBh[0];

/// Blackman-Harris' inverse cumulative distribution, tabulated: entry i is the offset below
/// which a share i / kSteps of the weight lies, read with linear interpolation between
/// entries (the table is made once, by integrating the window in fine steps).
class BlackmanHarrisTable {
public:
    static constexpr int kSteps = 1024;

    BlackmanHarrisTable() {
        constexpr int kFine = 1 << 16;
        const double dx = 2.0 * kBlackmanHarrisRadius / kFine;
        double cdf = 0.0;
        int next = 1;
        inverse_[0] = float(-kBlackmanHarrisRadius);
        for (int i = 0; i < kFine && next < kSteps; ++i) {
            const double x0 = -kBlackmanHarrisRadius + i * dx;
            const double step = 0.5 * (blackman_harris(x0) + blackman_harris(x0 + dx)) * dx / kBlackmanHarrisArea;
            while (next < kSteps && cdf + step >= double(next) / kSteps) {
                const double share = (double(next) / kSteps - cdf) / step;
                inverse_[next++] = float(x0 + share * dx);
            }
            cdf += step;
        }
        while (next <= kSteps) inverse_[next++] = float(kBlackmanHarrisRadius);
    }

    float offset(float u) const {
        const float at = u * float(kSteps);
        const int i = std::clamp(int(at), 0, kSteps - 1);
        const float f = at - float(i);
        return inverse_[i] + f * (inverse_[i + 1] - inverse_[i]);
    }

private:
    std::array<float, kSteps + 1> inverse_{};
};

/// Made once, at start-up (no guard on every lookup).
const BlackmanHarrisTable kBlackmanHarrisTable;

float filter_axis(PixelFilter filter, float u) {
    switch (filter) {
        case PixelFilter::box: return u - 0.5f;
        case PixelFilter::tent:
            // The triangle 1 - |x| on [-1, 1]: its cumulative distribution inverted per half.
            return u < 0.5f ? -1.0f + std::sqrt(2.0f * u) : 1.0f - std::sqrt(2.0f * (1.0f - u));
        case PixelFilter::blackman_harris: return kBlackmanHarrisTable.offset(u);
    }
    return 0.0f;
}

}  // namespace

glm::vec2 filter_offset(PixelFilter filter, glm::vec2 u) {
    return {filter_axis(filter, u.x), filter_axis(filter, u.y)};
}

float filter_density(PixelFilter filter, float x) {
    switch (filter) {
        case PixelFilter::box: return std::abs(x) <= 0.5f ? 1.0f : 0.0f;
        case PixelFilter::tent: return std::max(0.0f, 1.0f - std::abs(x));
        case PixelFilter::blackman_harris: return float(blackman_harris(x) / kBlackmanHarrisArea);
    }
    return 0.0f;
}

glm::vec3 light_sample_point(const PointLight& light, std::uint32_t index, std::uint32_t pixel,
                             int sample, int spp) {
    if (light.shape == PointLight::Shape::point) return light.position;
    const std::uint32_t salt = index * 0x632be5abu;
    const std::uint32_t n = std::uint32_t(std::max(spp, 1));
    const std::uint32_t order = (std::uint32_t(sample) + sample_hash(pixel, salt ^ 0x7f4a7c15u)) % n;
    const glm::vec2 u = scrambled_point(order, sample_hash(pixel, salt ^ 0x1b873593u),
                                        sample_hash(pixel, salt ^ 0xe6546b64u));
    if (light.shape == PointLight::Shape::quad) {
        return light.position + (u.x - 0.5f) * light.edge_u + (u.y - 0.5f) * light.edge_v;
    }
    // Uniform over the sphere: z uniform in [-1, 1] (Archimedes), the angle around it uniform.
    const float z = 1.0f - 2.0f * u.x;
    const float ring = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
    return light.position + light.radius * glm::vec3(ring * std::cos(phi), ring * std::sin(phi), z);
}

}  // namespace detail
}  // namespace dynrt
