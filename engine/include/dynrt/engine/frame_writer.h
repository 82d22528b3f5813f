#pragma once
// The output stage of a render: each frame's files are encoded and written on a writer thread
// while the render thread goes on to the next frame. Every file a render writes goes through
// it: numbered images or one image, AOVs, an animated GIF's or a video's frames (in frame
// order, as they come) and the contact sheet's thumbnails. At most `frames_in_flight` frames
// wait or are being written at once (each a copy of the render's buffers), so memory stays
// bounded; a render that outpaces the disk waits at the hand-over, and the time it waited is
// counted (wait_ms). The files are the same, byte for byte, as writing each frame on the render
// thread would make (write_frame_now, which the tests compare against).

#include "dynrt/engine/display_transform.h"
#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/renderer.h"

#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace dynrt {

class SequenceFile;
class ContactSheet;

/// What a render writes of each frame.
struct FrameOutputs {
    /// The image of each frame: a numbered name ('frames/%04d.png'), one image (one frame), or
    /// one sequence file (an animated .gif or a video) for every frame (is_sequence_file).
    std::string out;
    /// AOVs written beside each numbered or single image (not with a sequence file).
    std::vector<Aov> aovs;
    /// Frame rate of a sequence file.
    double fps = 24.0;
    /// The contact sheet's file; empty: none. Its thumbnails are of frames first_frame ...
    /// first_frame + frame_count - 1 (ContactSheet's choice of every k-th frame).
    std::string contact_sheet;
    int first_frame = 0;
    int frame_count = 1;
    /// Exposure and tone curve of the 8-bit files (images, sequence files, the contact sheet);
    /// float images stay linear.
    DisplayTransform display;
};

/// An output stage's failure on a frame: what() is "frame F: FILE: why", naming the frame and
/// the user's file.
class FrameWriteError : public std::runtime_error {
public:
    FrameWriteError(int frame, const std::string& file_error)
        : std::runtime_error("frame " + std::to_string(frame) + ": " + file_error), frame_(frame) {}
    int frame() const { return frame_; }

private:
    int frame_;
};

/// Writes one frame's files (image and AOVs; not sequence files or contact sheets) on the
/// calling thread, as FrameWriter's thread does. Throws std::runtime_error naming the file.
void write_frame_now(const FrameOutputs& outputs, const RenderedFrame& frame);

class FrameWriter {
public:
    /// Starts the writer thread. A sequence file (outputs.out) is opened at its first frame.
    /// Throws std::invalid_argument when outputs.out is a sequence file that cannot be written
    /// (check_sequence_file).
    explicit FrameWriter(FrameOutputs outputs, int frames_in_flight = 2);
    /// Finishes the frames handed over (as finish() does, but errors are dropped): whatever
    /// was handed over is written whole or not at all.
    ~FrameWriter();
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;

    /// Hands over a rendered frame (copied; `frame.stats.frame` is its number): returns once
    /// there is room for it. Throws, on the render thread, the first error the writer met
    /// (std::runtime_error "writing frame F: FILE: why"); after one, nothing more is written.
    /// Not thread-safe: one render thread hands over.
    void submit(const RenderedFrame& frame);

    /// The frames whose files are all in place since the last call, in the order handed over,
    /// each with its stats and write_ms (the writer's time on that frame) filled in. Sequence
    /// files and the contact sheet are complete only after finish().
    std::vector<FrameStats> take_written();

    /// Returns once every frame handed over is written (take_written() then has them all), the
    /// writer still open for more; rethrows the writer's first error. For a caller that must
    /// report every frame before it asks for more work (an MPI rank's records).
    void flush();

    /// Writes everything handed over, closes a sequence file (a GIF gets its trailer; a GIF or
    /// video without a frame is not made) and writes the contact sheet of the frames it got.
    /// Rethrows the writer's first error. Called once; take_written() then holds the rest.
    void finish();

    /// Thumbnails in the contact sheet (0 without one); final after finish().
    int contact_sheet_frames() const;

    /// Milliseconds the render thread spent waiting in submit() and finish() for the writer.
    double wait_ms() const { return wait_ms_; }

private:
    void run();
    void write(RenderedFrame& frame);
    void rethrow_error();

    FrameOutputs outputs_;
    std::size_t capacity_;
    std::unique_ptr<SequenceFile> sequence_file_;
    std::unique_ptr<ContactSheet> sheet_;
    int sequence_frames_ = 0;  ///< frames added to sequence_file_ (writer thread only)

    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<RenderedFrame> queue_;      ///< handed over, not yet written (front: being written)
    std::vector<RenderedFrame> spare_;     ///< written frames' buffers, reused by submit
    std::vector<FrameStats> written_;
    std::exception_ptr error_;
    bool closing_ = false;
    bool finished_ = false;
    double wait_ms_ = 0.0;
    std::thread thread_;
};

}  // namespace dynrt
