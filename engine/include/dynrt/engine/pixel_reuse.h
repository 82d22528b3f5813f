#pragma once
// How a frame reuses the pixels of the frame before it (FramePipeline; docs/reuse.md "Reusing pixels
// between frames"). Consecutive frames of an animation mostly repeat each other:
//
//   exact         (the default) when the camera, the lights and the image settings are
//                 those of the previous trace, a pixel can change only if its primary ray, or
//                 one of its shadow rays, meets the space that changed: boxes around the old
//                 and new triangles of an object that moved or changed material. Only those
//                 rays are traced again; every other pixel keeps the previous frame's values.
//                 The frame is bit-identical to a full render. Anything else changed: a full
//                 render.
//   render_cache  (approximate; Walter, Drettakis and Parker 1999) when the camera moves, the
//                 previous frame's hit points are reprojected into the new view with a depth
//                 test; pixels that meet moved objects, holes and disocclusions are traced
//                 first, then the oldest, up to the budget; what is left is filled by a small
//                 filter.
//   frameless     (approximate; Bishop et al. 1994, Dayal et al. 2005) a budget of pixels per
//                 displayed frame, traced in a randomised order by priority (pixels that meet
//                 what changed first, then the oldest); the others keep their last value.
//   off           every pixel is traced.

#include <cstdint>
#include <string>
#include <string_view>

namespace dynrt {

enum class PixelReuse : std::uint8_t { off, exact, render_cache, frameless };

/// "off", "exact", "cache", "frameless" (the names parse_reuse reads).
const char* pixel_reuse_name(PixelReuse mode);

/// TraceSettings::reuse.
struct ReuseSettings {
    PixelReuse mode = PixelReuse::exact;
    /// The approximate modes' budget per frame: the share of the image's pixels whose rays are
    /// traced, in (0, 1]. Ignored by exact and off.
    float budget_share = 0.25f;
    /// Above 0, the approximate modes' budget is instead this many milliseconds of tracing per
    /// frame (wall clock; at least one batch of tiles is traced).
    double budget_ms = 0.0;

    bool approximate() const {
        return mode == PixelReuse::render_cache || mode == PixelReuse::frameless;
    }
    bool operator==(const ReuseSettings&) const = default;
};

/// Reads "off", "exact", "cache" or "frameless", optionally followed by ":BUDGET" for the
/// approximate modes, where BUDGET is a share of the pixels ("cache:0.25") or milliseconds
/// ("frameless:8ms"). Throws std::invalid_argument naming the text.
ReuseSettings parse_reuse(std::string_view text);

/// The inverse of parse_reuse: "exact", "cache:0.25", "frameless:8ms".
std::string to_string(const ReuseSettings& reuse);

}  // namespace dynrt
