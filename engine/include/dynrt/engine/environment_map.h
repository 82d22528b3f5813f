#pragma once
// An environment map: what a ray that leaves the scene sees, by its direction, from an
// equirectangular (latitude-longitude) image, the format HDR panoramas come in (.exr, .hdr).
//
// Direction d (unit) to image coordinates: u = 1/2 + atan2(d.x, -d.z) / (2 pi) across, v =
// acos(d.y) / pi down, so +Y is the top row, the image's centre looks down -Z (dynrt's and
// glTF's forward), +X is three quarters across. Looked up bilinearly between texel centres,
// wrapping across and clamped at the poles. Texels are linear RGB times `scale`.

#include <glm/vec3.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace dynrt {

class EnvironmentMap {
public:
    /// Reads `path` with OpenImageIO (float images as they are, 8-bit ones from sRGB), its first
    /// three channels (a grey image is grey). Throws std::runtime_error naming the file and the
    /// reason when it cannot be read, is empty, or holds a value not finite or negative.
    static std::shared_ptr<const EnvironmentMap> read(const std::filesystem::path& path, float scale = 1.0f);

    /// `texels` row by row from the top, width * height of them.
    EnvironmentMap(int width, int height, std::vector<glm::vec3> texels, float scale, std::string source);

    /// The radiance seen along `direction` (any length but zero).
    glm::vec3 radiance(const glm::vec3& direction) const;

    /// Texel (x, y) (0 <= x < width, 0 <= y < height, rows from the top) times the scale.
    glm::vec3 texel(int x, int y) const { return scale_ * texels_[std::size_t(y) * std::size_t(width_) + std::size_t(x)]; }

    int width() const { return width_; }
    int height() const { return height_; }
    float scale() const { return scale_; }
    /// The file it was read from, for reports and errors.
    const std::string& source() const { return source_; }

private:
    int width_, height_;
    std::vector<glm::vec3> texels_;
    float scale_;
    std::string source_;
};

}  // namespace dynrt
