#pragma once
// Outputs that take a whole sequence rather than one image per frame: an animated GIF
// (`--out anim.gif`) and a contact sheet (`--contact-sheet sheet.png`, thumbnails of the
// frames in a grid). Video formats are recognised so that they get a clear refusal.

#include "dynrt/engine/renderer.h"

#include <filesystem>
#include <memory>
#include <vector>

namespace dynrt {

/// True for an output that holds a whole sequence in one file (.gif).
bool is_animated_image(const std::filesystem::path& path);

/// Throws std::invalid_argument for a video file name (.mp4, .mov, .mkv, .webm, .avi), saying
/// what to use instead: dynrt writes numbered images or an animated GIF, which any video tool
/// turns into a video (the message gives the ffmpeg command).
void refuse_video(const std::filesystem::path& path);

/// Writes frames one after the other into one animated GIF at `fps` frames per second, looping
/// for ever, through OpenImageIO. Frames are written as they come (nothing is kept), and must
/// all have the first one's size. The file is complete after close(); a writer destroyed
/// without close() (an error part way) leaves what was written.
class AnimatedImageWriter {
public:
    /// Throws std::invalid_argument when OpenImageIO cannot write several frames to `path`.
    AnimatedImageWriter(const std::filesystem::path& path, double fps);
    ~AnimatedImageWriter();
    AnimatedImageWriter(const AnimatedImageWriter&) = delete;
    AnimatedImageWriter& operator=(const AnimatedImageWriter&) = delete;

    /// Appends one frame (sRGB-encoded, 8 bits). Throws std::runtime_error naming the file.
    void add(const RenderedFrame& frame);
    /// Finishes the file. Throws std::runtime_error naming it on failure.
    void close();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Thumbnails of a sequence's frames in a grid, written as one image. Keeps at most
/// `max_frames` thumbnails (every k-th frame of a longer sequence, k chosen up front from the
/// frame count), each at most `thumb` pixels on its long side (box-filtered).
class ContactSheet {
public:
    ContactSheet(int frame_count, int max_frames = 64, int thumb = 192);
    /// Offers frame number `index` (0 for the first frame of the sequence).
    void add(int index, const RenderedFrame& frame);
    /// The grid as an image: columns ceil(sqrt(n)), one pixel of background between cells.
    /// Throws std::runtime_error naming the file on failure, std::logic_error without frames.
    void write(const std::filesystem::path& path) const;
    /// Frames kept so far.
    int size() const { return int(thumbs_.size()); }

private:
    int step_;
    int max_frames_;
    int thumb_;
    std::vector<RenderedFrame> thumbs_;
};

}  // namespace dynrt
