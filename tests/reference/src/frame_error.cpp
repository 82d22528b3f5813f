#include "dynrt/reference/frame_error.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace dynrt::reference {

namespace {

/// SplitMix64 (Steele, Lea and Flood 2014): a stateless hash of the square's index, so each
/// square's pixel does not depend on which squares came before.
std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

}  // namespace

std::vector<PixelCoord> stratified_pixels(int width, int height, int block, std::uint64_t seed) {
    if (width < 1 || height < 1 || block < 1) {
        throw std::invalid_argument("stratified_pixels: image " + std::to_string(width) + "x" +
                                    std::to_string(height) + ", block " +
                                    std::to_string(block) + ": all must be >= 1");
    }
    const int blocks_x = (width + block - 1) / block;
    const int blocks_y = (height + block - 1) / block;
    std::vector<PixelCoord> pixels;
    pixels.reserve(std::size_t(blocks_x) * std::size_t(blocks_y));
    for (int by = 0; by < blocks_y; ++by) {
        for (int bx = 0; bx < blocks_x; ++bx) {
            const int x0 = bx * block, y0 = by * block;
            const int w = std::min(block, width - x0), h = std::min(block, height - y0);
            const std::uint64_t r =
                mix(seed ^ mix(std::uint64_t(by) * std::uint64_t(blocks_x) + std::uint64_t(bx)));
            // Two independent 32-bit halves; the modulo bias is below 2^-24 for blocks <= 256.
            pixels.push_back(PixelCoord{x0 + int((r & 0xffffffffu) % std::uint64_t(w)),
                                        y0 + int((r >> 32) % std::uint64_t(h))});
        }
    }
    return pixels;
}

FrameError frame_error(const RenderedFrame& got, std::span<const PixelCoord> pixels,
                       std::span<const ReferencePixel> reference) {
    if (pixels.size() != reference.size()) {
        throw std::invalid_argument("frame_error: " + std::to_string(pixels.size()) +
                                    " pixels but " + std::to_string(reference.size()) +
                                    " reference values");
    }
    const std::size_t n = std::size_t(got.width) * std::size_t(got.height);
    if (got.color.size() != n || got.object.size() != n || got.prim.size() != n) {
        throw std::invalid_argument("frame_error: the frame needs its colour and hit buffers "
                                    "(RenderOptions::hit_buffers)");
    }
    FrameError error;
    double squared_sum = 0.0;
    for (std::size_t k = 0; k < pixels.size(); ++k) {
        const PixelCoord p = pixels[k];
        if (p.x < 0 || p.x >= got.width || p.y < 0 || p.y >= got.height) {
            throw std::invalid_argument("frame_error: pixel (" + std::to_string(p.x) + "," +
                                        std::to_string(p.y) + ") is outside the frame");
        }
        const std::size_t i = std::size_t(p.y) * std::size_t(got.width) + std::size_t(p.x);
        const ReferencePixel& r = reference[k];
        const Ambiguity amb = r.hit.ambiguity;
        ++error.samples;
        if (amb != Ambiguity::kNone) ++error.ambiguous_samples;

        const bool got_hit = got.object[i] >= 0;
        const bool hit_or_object_differs =
            got_hit != r.hit.is_hit() || (got_hit && got.object[i] != r.hit.object);
        const bool prim_differs = got_hit && !hit_or_object_differs && got.prim[i] != r.hit.prim;
        if (hit_or_object_differs || prim_differs) {
            ++error.hit_differs;
            const bool determined = amb == Ambiguity::kNone ||
                                    (amb == Ambiguity::kPrimitive && hit_or_object_differs);
            ++(determined ? error.determined_differs : error.ambiguous_differs);
        }
        const glm::dvec3 d = glm::dvec3(got.color[i]) - r.color;
        squared_sum += d.x * d.x + d.y * d.y + d.z * d.z;
    }
    if (error.samples > 0) {
        error.mse = squared_sum / (3.0 * double(error.samples));
        error.rmse = std::sqrt(error.mse);
        error.psnr_db = error.mse > 0.0 ? 10.0 * std::log10(1.0 / error.mse)
                                        : std::numeric_limits<double>::infinity();
    }
    return error;
}

std::string format_psnr(double psnr_db) {
    if (std::isinf(psnr_db) && psnr_db > 0) return "inf";
    std::ostringstream out;
    out << std::fixed << std::setprecision(1) << psnr_db;
    return out.str();
}

}  // namespace dynrt::reference
