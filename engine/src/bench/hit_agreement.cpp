#include "dynrt/bench/hit_agreement.h"

#include "dynrt/engine/image_output.h"

#include <stdexcept>

namespace dynrt {

std::vector<PixelAgreement> classify_hits(const std::vector<std::int32_t>& object_a,
                                          const std::vector<std::int32_t>& prim_a,
                                          const std::vector<std::int32_t>& object_b,
                                          const std::vector<std::int32_t>& prim_b) {
    if (object_a.size() != object_b.size() || prim_a.size() != object_a.size() ||
        prim_b.size() != object_b.size()) {
        throw std::invalid_argument("compare hits: hit sets of different sizes");
    }
    std::vector<PixelAgreement> pixels(object_a.size(), PixelAgreement::same);
    for (std::size_t p = 0; p < pixels.size(); ++p) {
        if (object_a[p] != object_b[p]) {
            pixels[p] = PixelAgreement::object;
        } else if (prim_a[p] != prim_b[p]) {
            pixels[p] = PixelAgreement::prim_only;
        }
    }
    return pixels;
}

HitAgreement count_disagreements(const std::vector<PixelAgreement>& pixels) {
    HitAgreement counts;
    for (PixelAgreement p : pixels) {
        counts.object_differs += p == PixelAgreement::object;
        counts.prim_only_differs += p == PixelAgreement::prim_only;
    }
    return counts;
}

HitAgreement compare_hits(const std::vector<std::int32_t>& object_a,
                          const std::vector<std::int32_t>& prim_a,
                          const std::vector<std::int32_t>& object_b,
                          const std::vector<std::int32_t>& prim_b) {
    return count_disagreements(classify_hits(object_a, prim_a, object_b, prim_b));
}

void write_disagreement_image(const std::filesystem::path& path, const RenderedFrame& frame,
                              const std::vector<PixelAgreement>& pixels) {
    if (pixels.size() != frame.color.size()) {
        throw std::invalid_argument("disagreement image: " + std::to_string(pixels.size()) +
                                    " classified pixels for a " + std::to_string(frame.width) +
                                    "x" + std::to_string(frame.height) + " frame");
    }
    RenderedFrame marked;
    marked.width = frame.width;
    marked.height = frame.height;
    marked.color.resize(pixels.size());
    for (std::size_t p = 0; p < pixels.size(); ++p) {
        switch (pixels[p]) {
        case PixelAgreement::object: marked.color[p] = {1.0f, 0.0f, 0.0f}; break;
        case PixelAgreement::prim_only: marked.color[p] = {1.0f, 0.9f, 0.0f}; break;
        case PixelAgreement::same: marked.color[p] = 0.25f * frame.color[p]; break;
        }
    }
    write_image(path, marked);
}

}  // namespace dynrt
