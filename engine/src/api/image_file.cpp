#include "dynrt/api/engine.h"

#include "dynrt/engine/image_output.h"
#include "dynrt/engine/renderer.h"

#include <cstddef>
#include <string>

namespace dynrt {

void save_image(const std::string& path, int width, int height, std::span<const float> rgb) {
    if (width <= 0 || height <= 0 ||
        rgb.size() != 3 * std::size_t(width) * std::size_t(height)) {
        throw Error(Error::Code::invalid_argument,
                    "dynrt::save_image '" + path + "': " + std::to_string(rgb.size()) +
                        " floats for a " + std::to_string(width) + "x" + std::to_string(height) +
                        " image (3 per pixel expected)");
    }
    RenderedFrame frame;
    frame.width = width;
    frame.height = height;
    frame.color.resize(std::size_t(width) * std::size_t(height));
    for (std::size_t p = 0; p < frame.color.size(); ++p) {
        frame.color[p] = {rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]};
    }
    try {
        check_image_path(path);
        write_image(path, frame);
    } catch (const std::exception& e) {
        throw Error(Error::Code::invalid_argument, std::string("dynrt::save_image: ") + e.what());
    }
}

}  // namespace dynrt
