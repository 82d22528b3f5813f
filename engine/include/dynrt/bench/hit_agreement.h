#pragma once
// Pixel-by-pixel agreement between two tracers' closest hits on the same rays (dynrt against
// Embree in `dynrt bench --vs embree`), and the picture of where they disagree.

#include "dynrt/engine/renderer.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace dynrt {

/// How two hits on one pixel relate. Ordered from best to worst, so the worst of several
/// comparisons is their maximum.
enum class PixelAgreement : std::uint8_t {
    same,       ///< same object and primitive (or both miss)
    prim_only,  ///< same object, other primitive: expected at shared edges, where both are right
    object,     ///< hit against miss, or another object: a bug in one of the tracers
};

/// Counts of the disagreeing pixels.
struct HitAgreement {
    std::size_t object_differs = 0;
    std::size_t prim_only_differs = 0;
};

/// Classifies every pixel of two hit sets given as object and primitive indices per pixel (-1
/// on a miss). Throws std::invalid_argument unless all four vectors have the same size.
std::vector<PixelAgreement> classify_hits(const std::vector<std::int32_t>& object_a,
                                          const std::vector<std::int32_t>& prim_a,
                                          const std::vector<std::int32_t>& object_b,
                                          const std::vector<std::int32_t>& prim_b);

/// The counts of classify_hits.
HitAgreement count_disagreements(const std::vector<PixelAgreement>& pixels);

/// compare_hits(a, b) = count_disagreements(classify_hits(a, b)).
HitAgreement compare_hits(const std::vector<std::int32_t>& object_a,
                          const std::vector<std::int32_t>& prim_a,
                          const std::vector<std::int32_t>& object_b,
                          const std::vector<std::int32_t>& prim_b);

/// Writes an image of `frame`'s size showing where `pixels` (one per pixel of `frame`)
/// disagree: red where hit/miss or object differs, yellow where only the primitive does, and
/// elsewhere `frame`'s own image darkened to a quarter so the marks stand out. Any format
/// write_image takes. Throws std::invalid_argument on a size mismatch and std::runtime_error
/// if the file cannot be written.
void write_disagreement_image(const std::filesystem::path& path, const RenderedFrame& frame,
                              const std::vector<PixelAgreement>& pixels);

}  // namespace dynrt
