#pragma once
// Where a pixel's samples go and which point of an area light each of them sees
// (dynrt/engine/pixel_sampling.h has the model and its papers): a (0,2)-sequence scrambled per
// pixel, moved by the reconstruction filter's distribution, and the same sequence for the
// lights' points, scrambled and ordered otherwise.

#include "dynrt/engine/pixel_sampling.h"
#include "dynrt/bvh/aabb.h"
#include "dynrt/packet/ray_packet.h"
#include "dynrt/scene/scene.h"

#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace dynrt::detail {

/// A pixel's sample: the pixel's index (y * width + x) and the sample's.
struct PixelSample {
    std::uint32_t pixel = 0;
    std::uint32_t sample = 0;
};

/// One pass of a frame's samples. The default is a frame of one sample per pixel, at the
/// pixels' centres. Two kinds:
///   - sample `index` of `sampling.spp` for each pixel of the image (`samples` null);
///   - a list of samples (`samples`): the pass's frame is then not the image but one tile
///     wide, its pixel v standing for (*samples)[v] of the image_width x image_height image,
///     so that a tile's packet holds 256 samples of a few neighbouring pixels (adaptive
///     anti-aliasing's refinement, whose pixels are too sparse for the image's own tiles).
struct SamplePass {
    PixelSampling sampling;
    int index = 0;
    /// Per pixel of the pass's frame, non-zero where this pass traces it; null: every pixel.
    const std::vector<std::uint8_t>* pixels = nullptr;
    const std::vector<PixelSample>* samples = nullptr;
    int image_width = 0, image_height = 0;  ///< the image's, when `samples` is set

    /// What pixel v of the pass's frame is a sample of.
    PixelSample at(std::uint32_t v) const {
        return samples != nullptr ? (*samples)[v] : PixelSample{v, std::uint32_t(index)};
    }
};

/// Pixel `px`'s index in an image `width` wide: y * width + x, what its samples are hashed by.
inline std::uint32_t pixel_index(const packet::LanePixel& px, int width) {
    return std::uint32_t(px.y) * std::uint32_t(width) + std::uint32_t(px.x);
}

/// A 32-bit hash of `value` under `salt` (a murmur3-style finaliser): the per-pixel scrambles.
constexpr std::uint32_t sample_hash(std::uint32_t value, std::uint32_t salt) {
    std::uint32_t h = value * 0x9e3779b9u ^ salt;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

/// Point `index` of the (0,2)-sequence in base 2 before scrambling, as 32-bit fractions: the
/// van der Corput sequence (x) and Sobol's second dimension (y).
glm::uvec2 sequence_point(std::uint32_t index);

/// `point` (a sequence_point) with its digits XOR-scrambled by `scramble_x` and `scramble_y`,
/// in [0, 1)^2.
inline glm::vec2 scramble(glm::uvec2 point, std::uint32_t scramble_x, std::uint32_t scramble_y) {
    // 24 bits each, so that the float is exact and below 1.
    constexpr float kScale = 1.0f / 16777216.0f;
    return {float((point.x ^ scramble_x) >> 8) * kScale, float((point.y ^ scramble_y) >> 8) * kScale};
}

/// Point `index` of the (0,2)-sequence, scrambled: scramble(sequence_point(index), ...).
inline glm::vec2 scrambled_point(std::uint32_t index, std::uint32_t scramble_x, std::uint32_t scramble_y) {
    return scramble(sequence_point(index), scramble_x, scramble_y);
}

/// The offset from a pixel's centre, in pixels, of the sample at `u` (in [0, 1)^2) under
/// `filter`: each axis through the inverse of the filter's cumulative distribution. Within
/// [-1/2, 1/2] for the box, [-1, 1] for the tent, [-0.75, 0.75] for Blackman-Harris.
glm::vec2 filter_offset(PixelFilter filter, glm::vec2 u);

/// The filter's normalised weight at offset `x` (pixels) along one axis: its distribution's
/// density, which filter_offset inverts (for the tests: it integrates to one).
float filter_density(PixelFilter filter, float x);

/// How far from a pixel's centre `filter` moves a sample at most, on each axis, in pixels.
constexpr float filter_radius(PixelFilter filter) {
    return filter == PixelFilter::box ? 0.5f : filter == PixelFilter::tent ? 1.0f : 0.75f;
}

/// The box that holds every point of `light` (its position for a point light).
inline bvh::Aabb light_bounds(const PointLight& light) {
    glm::vec3 half(0.0f);
    if (light.shape == PointLight::Shape::sphere) half = glm::vec3(light.radius);
    if (light.shape == PointLight::Shape::quad) half = 0.5f * (glm::abs(light.edge_u) + glm::abs(light.edge_v));
    bvh::Aabb box;
    box.extend(light.position - half);
    box.extend(light.position + half);
    return box;
}

/// Where a pixel's sample `sample` lies, as an offset in pixels from its centre (the pixel's
/// index y * width + x scrambles the sequence): the centre itself at one sample per pixel. The
/// sequence's point is made once, for the many pixels of one sample (a pass); `at` gives each
/// pixel's offset.
class SampleOffsets {
public:
    SampleOffsets(const PixelSampling& sampling, int sample)
        : filter_(sampling.filter), point_(sequence_point(std::uint32_t(sample))), centre_(sampling.spp <= 1) {}

    glm::vec2 at(std::uint32_t pixel) const {
        if (centre_) return glm::vec2(0.0f);
        return filter_offset(filter_, scramble(point_, sample_hash(pixel, 0x51ed27u), sample_hash(pixel, 0x2c1b3c6du)));
    }

private:
    PixelFilter filter_;
    glm::uvec2 point_;
    bool centre_;
};

/// SampleOffsets(sampling, sample).at(pixel), for a single sample.
inline glm::vec2 pixel_sample_offset(const PixelSampling& sampling, std::uint32_t pixel, int sample) {
    return SampleOffsets(sampling, sample).at(pixel);
}

/// The point of area light `light` (light number `index` of the frame) that sample `sample`
/// of `spp` of pixel `pixel` sees: a point of the light's own scramble of the sequence,
/// taken in an order rotated per pixel so that it is not tied to where the sample lies in the
/// pixel; uniform over a sphere's surface or the quad. A point light's position otherwise.
glm::vec3 light_sample_point(const PointLight& light, std::uint32_t index, std::uint32_t pixel,
                             int sample, int spp);

}  // namespace dynrt::detail
