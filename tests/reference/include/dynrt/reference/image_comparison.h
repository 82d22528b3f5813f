#pragma once
// Pixel-by-pixel comparison of a dynrt::Renderer frame with the reference frame, counting each
// kind of disagreement and separating what the reference says is determined from what float
// rounding may legitimately change.

#include "dynrt/reference/reference_renderer.h"

#include "dynrt/engine/renderer.h"

#include <string>
#include <vector>

namespace dynrt::reference {

struct ComparisonOptions {
    /// Largest |t - t_ref| / t_ref accepted where both report the same triangle; where the
    /// reference allows another triangle (kPrimitive), its t_spread_rel is added.
    double t_rel_tol = 1e-5;
    /// Largest per-channel colour difference accepted on pixels whose hit and shading are both
    /// unambiguous.
    double color_abs_tol = 1e-3;
    /// Largest per-component difference of the unit normal, same pixels.
    double normal_abs_tol = 1e-3;
    /// How many bad pixels to describe in `bad_pixels`.
    int max_listed = 8;
};

struct ImageComparison {
    int pixels = 0;
    // What the reference allows.
    int ambiguous_pixels = 0;          ///< hit ambiguity kPrimitive or kAny
    int any_ambiguous_pixels = 0;      ///< hit ambiguity kAny
    int shading_ambiguous_pixels = 0;  ///< a light's visibility or n . l sign is ambiguous
    // Raw disagreements, ambiguous pixels included.
    int hit_mismatches = 0;     ///< one hits, the other misses
    int object_mismatches = 0;  ///< both hit, different objects
    int prim_mismatches = 0;    ///< both hit the same object, different triangles
    /// Disagreements the reference says cannot happen: any of the above on a kNone pixel, hit
    /// or object on a kPrimitive pixel. Must be zero.
    int unambiguous_mismatches = 0;
    // Depth, on pixels where both hit the same object and the same triangle (or, on kPrimitive
    // pixels, any triangle).
    int t_checked = 0;
    int t_mismatches = 0;
    double max_t_rel_error = 0.0;
    // Colour and normal, on pixels with hit kNone and unambiguous shading.
    int color_checked = 0;
    int color_mismatches = 0;
    double max_color_error = 0.0;
    int normal_mismatches = 0;
    double max_normal_error = 0.0;
    /// "(x,y): ..." descriptions of the first bad pixels (any kind), for failure messages.
    std::vector<std::string> bad_pixels;

    /// True when every determined quantity agrees within tolerance.
    bool passed() const {
        return unambiguous_mismatches == 0 && t_mismatches == 0 && color_mismatches == 0 &&
               normal_mismatches == 0;
    }
    /// Multi-line summary with the counts and the listed bad pixels.
    std::string summary() const;
};

/// Compares `got` with `ref`. Throws std::invalid_argument when the sizes differ or a buffer of
/// `got` has the wrong length.
ImageComparison compare_images(const RenderedFrame& got, const ReferenceFrame& ref,
                               const ComparisonOptions& options = {});

}  // namespace dynrt::reference
