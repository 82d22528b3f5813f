#pragma once
// Rendering a sequence of frames: which frames (--frames), where each one's image goes (--out
// 'frames/%04d.png').

#include <optional>
#include <string>
#include <string_view>

namespace dynrt {

/// The largest frame number dynrt renders. A frame's time is frame / fps in float, which past
/// about ten million frames at 24 fps (116 hours) no longer resolves one frame from the next;
/// the bound also keeps every frame loop (first..last inclusive) clear of int overflow.
inline constexpr int kFrameMax = 9'999'999;

/// Frames first..last, both included; 0 <= first <= last <= kFrameMax.
struct FrameRange {
    int first = 0;
    int last = 0;
    int count() const { return last - first + 1; }
};

/// "N" (frame N alone, 0 <= N <= kFrameMax, as Blender's -f reads it) or "A-B" (frames A to
/// B, both included, 0 <= A <= B <= kFrameMax). Throws std::invalid_argument naming the text
/// and the bound.
FrameRange parse_frame_range(std::string_view text);

/// True when `pattern` holds a printf-style integer conversion for the frame number (%d, with
/// optional flags and width, as in "frames/%04d.png"); "%%" is a literal percent sign.
/// Throws std::invalid_argument for a pattern with any other conversion or with several.
bool has_frame_number(std::string_view pattern);

/// `pattern` with its frame conversion replaced by `frame` ("frames/%04d.png", 7 ->
/// "frames/0007.png"); a pattern without one is returned as it is (with "%%" unescaped).
std::string frame_path(std::string_view pattern, int frame);

/// The frame whose file under `pattern` is `path` (frame_path(pattern, n) == path), or nothing
/// when no frame in 0..kFrameMax has that name (a pattern without a frame number: nothing).
std::optional<int> frame_of_path(std::string_view pattern, std::string_view path);

}  // namespace dynrt
