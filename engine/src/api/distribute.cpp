#include "dynrt/api/distribute.h"

#include "dynrt/api/error.h"
#include "dynrt/packet/tiling.h"

#include <string>

namespace dynrt {

namespace {

void check_share(const char* call, int share, int shares) {
    if (shares < 1 || share < 0 || share >= shares) {
        throw Error(Error::Code::invalid_argument, std::string("dynrt::") + call + ": share " + std::to_string(share) + " of " +
                              std::to_string(shares) + " (needs 0 <= share < shares)");
    }
}

}  // namespace

std::vector<std::size_t> tile_share_pixels(int width, int height, int share, int shares) {
    check_share("tile_share_pixels", share, shares);
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536) {
        throw Error(Error::Code::invalid_argument, "dynrt::tile_share_pixels: image size " + std::to_string(width) + "x" +
                              std::to_string(height) + " outside 1..65536");
    }
    const packet::Tiling tiling(width, height, packet::TileShare{share, shares});
    std::vector<std::size_t> pixels;
    pixels.reserve(tiling.pixel_count());
    tiling.for_each_pixel([&](std::size_t p) { pixels.push_back(p); });
    return pixels;
}

RayShare ray_share(std::size_t count, int share, int shares) {
    check_share("ray_share", share, shares);
    const std::size_t n = std::size_t(shares), i = std::size_t(share);
    return RayShare{count * i / n, count * (i + 1) / n};
}

}  // namespace dynrt
