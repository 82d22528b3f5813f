#include "dynrt/reference/image_comparison.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dynrt::reference {
namespace {

std::string describe(int x, int y, const char* what, const ReferencePixel& ref,
                     const RenderedFrame& got, std::size_t i) {
    std::ostringstream out;
    out.precision(9);
    out << "(" << x << "," << y << ") " << what << ": reference ";
    if (ref.hit.is_hit()) {
        out << "object " << ref.hit.object << " prim " << ref.hit.prim << " t " << ref.hit.t
            << " uv (" << ref.hit.u << ", " << ref.hit.v << ")";
    } else {
        out << "miss";
    }
    out << " [ambiguity " << to_string(ref.hit.ambiguity)
        << (ref.shading_ambiguous ? ", shading ambiguous" : "") << "] color (" << ref.color.x
        << ", " << ref.color.y << ", " << ref.color.z << "); renderer ";
    if (got.object[i] >= 0) {
        out << "object " << got.object[i] << " prim " << got.prim[i] << " t " << got.depth[i];
    } else {
        out << "miss";
    }
    out << " color (" << got.color[i].x << ", " << got.color[i].y << ", " << got.color[i].z
        << ")";
    return out.str();
}

double max_abs_diff(const glm::dvec3& a, const glm::vec3& b) {
    const glm::dvec3 d = glm::abs(a - glm::dvec3(b));
    return std::max({d.x, d.y, d.z});
}

}  // namespace

ImageComparison compare_images(const RenderedFrame& got, const ReferenceFrame& ref,
                               const ComparisonOptions& options) {
    if (got.width != ref.width || got.height != ref.height) {
        throw std::invalid_argument("compare_images: renderer frame is " +
                                    std::to_string(got.width) + "x" + std::to_string(got.height) +
                                    ", reference is " + std::to_string(ref.width) + "x" +
                                    std::to_string(ref.height));
    }
    const std::size_t n = ref.pixels.size();
    if (got.color.size() != n || got.depth.size() != n || got.object.size() != n ||
        got.prim.size() != n || got.normal.size() != n) {
        throw std::invalid_argument("compare_images: renderer buffers have the wrong size");
    }

    ImageComparison result;
    result.pixels = static_cast<int>(n);
    auto note = [&](int x, int y, const char* what, std::size_t i) {
        if (static_cast<int>(result.bad_pixels.size()) < options.max_listed) {
            result.bad_pixels.push_back(describe(x, y, what, ref.pixels[i], got, i));
        }
    };

    for (int y = 0; y < ref.height; ++y) {
        for (int x = 0; x < ref.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(ref.width) +
                                  static_cast<std::size_t>(x);
            const ReferencePixel& r = ref.pixels[i];
            const Ambiguity amb = r.hit.ambiguity;
            if (amb != Ambiguity::kNone) ++result.ambiguous_pixels;
            if (amb == Ambiguity::kAny) ++result.any_ambiguous_pixels;
            if (r.shading_ambiguous) ++result.shading_ambiguous_pixels;

            // ---- Hit, object, primitive --------------------------------------------------
            const bool got_hit = got.object[i] >= 0;
            const bool same_object = got_hit && r.hit.is_hit() && got.object[i] == r.hit.object;
            const bool same_prim = same_object && got.prim[i] == r.hit.prim;
            bool determined_mismatch = false;
            if (got_hit != r.hit.is_hit()) {
                ++result.hit_mismatches;
                determined_mismatch = amb != Ambiguity::kAny;
            } else if (got_hit && !same_object) {
                ++result.object_mismatches;
                determined_mismatch = amb != Ambiguity::kAny;
            } else if (got_hit && !same_prim) {
                ++result.prim_mismatches;
                determined_mismatch = amb == Ambiguity::kNone;
            }
            if (determined_mismatch) {
                ++result.unambiguous_mismatches;
                note(x, y, "hit mismatch", i);
            }

            // ---- Depth -------------------------------------------------------------------
            if (same_prim || (same_object && amb == Ambiguity::kPrimitive)) {
                ++result.t_checked;
                const double err = std::abs(double(got.depth[i]) - r.hit.t) / r.hit.t;
                result.max_t_rel_error = std::max(result.max_t_rel_error, err);
                const double allowed =
                    options.t_rel_tol + (same_prim ? 0.0 : r.hit.t_spread_rel);
                if (!(err <= allowed)) {
                    ++result.t_mismatches;
                    note(x, y, "depth mismatch", i);
                }
            }

            // ---- Colour and normal ---------------------------------------------------------
            if (amb == Ambiguity::kNone && !r.shading_ambiguous && !determined_mismatch) {
                ++result.color_checked;
                const double color_err = max_abs_diff(r.color, got.color[i]);
                result.max_color_error = std::max(result.max_color_error, color_err);
                if (!(color_err <= options.color_abs_tol)) {
                    ++result.color_mismatches;
                    note(x, y, "colour mismatch", i);
                }
                const double normal_err = max_abs_diff(r.normal, got.normal[i]);
                result.max_normal_error = std::max(result.max_normal_error, normal_err);
                if (!(normal_err <= options.normal_abs_tol)) {
                    ++result.normal_mismatches;
                    note(x, y, "normal mismatch", i);
                }
            }
        }
    }
    return result;
}

std::string ImageComparison::summary() const {
    std::ostringstream out;
    out << pixels << " pixels: " << unambiguous_mismatches << " unambiguous mismatches ("
        << hit_mismatches << " hit/miss, " << object_mismatches << " object, " << prim_mismatches
        << " prim, ambiguous included); " << ambiguous_pixels << " ambiguous ("
        << any_ambiguous_pixels << " any), " << shading_ambiguous_pixels
        << " shading-ambiguous; depth: " << t_mismatches << " of " << t_checked
        << " off, max rel error " << max_t_rel_error << "; colour: " << color_mismatches
        << " of " << color_checked << " off, max error " << max_color_error << "; normal: "
        << normal_mismatches << " off, max error " << max_normal_error;
    for (const std::string& line : bad_pixels) out << "\n  " << line;
    return out.str();
}

}  // namespace dynrt::reference
