#include "dynrt/engine/environment_map.h"

#include <OpenImageIO/imageio.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace dynrt {

namespace {

float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

std::shared_ptr<const EnvironmentMap> EnvironmentMap::read(const std::filesystem::path& path, float scale) {
    const std::string name = path.string();
    const auto fail = [&](const std::string& why) {
        throw std::runtime_error("environment map '" + name + "': " + why);
    };
    if (!(scale >= 0.0f) || !std::isfinite(scale)) fail("its scale must be finite and >= 0");
    std::error_code ignored;
    if (!std::filesystem::exists(path, ignored)) fail("no such file");
    std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(name);
    if (!input) fail(OIIO::geterror());
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1) fail("it holds no pixels");
    if (std::int64_t(spec.width) * spec.height > (std::int64_t(1) << 28)) fail("it is too large");
    const int channels = spec.nchannels;
    std::vector<float> values(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, values.data())) fail(input->geterror());
    const bool encoded = spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16;
    std::vector<glm::vec3> texels(std::size_t(spec.width) * std::size_t(spec.height));
    for (std::size_t i = 0; i < texels.size(); ++i) {
        for (int a = 0; a < 3; ++a) {
            float v = values[i * std::size_t(channels) + std::size_t(std::min(a, channels - 1))];
            if (encoded) v = srgb_to_linear(v);
            if (!(v >= 0.0f) || !std::isfinite(v)) {
                fail("texel " + std::to_string(i % std::size_t(spec.width)) + "," +
                     std::to_string(i / std::size_t(spec.width)) + " is not finite and >= 0");
            }
            texels[i][a] = v;
        }
    }
    return std::make_shared<const EnvironmentMap>(spec.width, spec.height, std::move(texels), scale, name);
}

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<glm::vec3> texels, float scale, std::string source)
    : width_(width), height_(height), texels_(std::move(texels)), scale_(scale), source_(std::move(source)) {
    if (width_ < 1 || height_ < 1 || texels_.size() != std::size_t(width_) * std::size_t(height_)) {
        throw std::invalid_argument("EnvironmentMap: width * height texels expected");
    }
}

glm::vec3 EnvironmentMap::radiance(const glm::vec3& direction) const {
    const glm::vec3 d = glm::normalize(direction);
    const float u = 0.5f + std::atan2(d.x, -d.z) * float(0.5 / std::numbers::pi);
    const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) * float(1.0 / std::numbers::pi);
    // Texel centres at (i + 1/2) / size: wrap across, clamp down.
    const float x = u * float(width_) - 0.5f, y = std::clamp(v * float(height_) - 0.5f, 0.0f, float(height_ - 1));
    const float x0f = std::floor(x), y0f = std::floor(y);
    const float fx = x - x0f, fy = y - y0f;
    const auto wrap = [&](int i) { return ((i % width_) + width_) % width_; };
    const int x0 = wrap(int(x0f)), x1 = wrap(int(x0f) + 1);
    const int y0 = int(y0f), y1 = std::min(y0 + 1, height_ - 1);
    const auto at = [&](int i, int j) { return texels_[std::size_t(j) * std::size_t(width_) + std::size_t(i)]; };
    const glm::vec3 top = (1.0f - fx) * at(x0, y0) + fx * at(x1, y0);
    const glm::vec3 bottom = (1.0f - fx) * at(x0, y1) + fx * at(x1, y1);
    return scale_ * ((1.0f - fy) * top + fy * bottom);
}

}  // namespace dynrt
