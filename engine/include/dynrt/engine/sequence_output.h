#pragma once
// Outputs that take a whole sequence rather than one image per frame: an animated GIF or a
// video (`--out anim.gif`, `--out anim.mp4`, the latter through the ffmpeg program when it is
// installed) and a contact sheet (`--contact-sheet sheet.png`, thumbnails of the frames in a
// grid).

#include "dynrt/engine/renderer.h"

#include <filesystem>
#include <memory>
#include <vector>

namespace dynrt {

/// One file that holds a whole sequence, written frame by frame as the frames come (nothing
/// is kept): an animated GIF through OpenImageIO, or a video through ffmpeg.
class SequenceFile {
public:
    virtual ~SequenceFile() = default;
    /// Appends one frame (sRGB-encoded, 8 bits); every frame must have the first one's size.
    /// Throws std::runtime_error naming the file.
    virtual void add(const RenderedFrame& frame) = 0;
    /// Finishes the file. Throws std::runtime_error naming it on failure. A file destroyed
    /// without close() (an error part way) keeps what was written.
    virtual void close() = 0;
};

/// True for names of such files: .gif, and the video formats .mp4, .mov, .mkv, .webm, .avi.
bool is_sequence_file(const std::filesystem::path& path);

/// Throws std::invalid_argument, before any rendering, when `path` cannot be written as a
/// sequence file: a video needs the ffmpeg program on the PATH, and the message says how to
/// install it or what to write instead.
void check_sequence_file(const std::filesystem::path& path);

/// Opens `path` (a name is_sequence_file accepts) for frames at `fps` frames per second; a
/// GIF loops for ever, a video is H.264 (or the container's default codec) in yuv420p.
std::unique_ptr<SequenceFile> open_sequence_file(const std::filesystem::path& path, double fps);

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
