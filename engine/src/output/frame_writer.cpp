// The output stage (dynrt/engine/frame_writer.h): one writer thread behind a bounded queue.
// One thread, not a few: it keeps a sequence file's frames in order without reordering, and
// with the fast PNG level one frame's encoding (about 10-20 ms at 1024x1024) is well under a
// frame's render, which is the only rate it has to keep.

#include "dynrt/engine/frame_writer.h"

#include "dynrt/engine/sequence.h"
#include "dynrt/engine/sequence_output.h"
#include "dynrt/engine/stopwatch.h"

#include <stdexcept>
#include <utility>

namespace dynrt {

void write_frame_now(const FrameOutputs& outputs, const RenderedFrame& frame) {
    const std::string path = frame_path(outputs.out, frame.stats.frame);
    write_image(path, frame, outputs.display);
    for (const Aov aov : outputs.aovs) write_aov(path, aov, frame);
}

FrameWriter::FrameWriter(FrameOutputs outputs, int frames_in_flight)
    : outputs_(std::move(outputs)), capacity_(std::size_t(std::max(1, frames_in_flight))) {
    if (is_sequence_file(outputs_.out) && !has_frame_number(outputs_.out)) {
        sequence_file_ = open_sequence_file(outputs_.out, outputs_.fps);
    }
    if (!outputs_.contact_sheet.empty()) sheet_ = std::make_unique<ContactSheet>(outputs_.frame_count);
    thread_ = std::thread([this] { run(); });
}

FrameWriter::~FrameWriter() {
    if (!finished_) {
        try {
            finish();
        } catch (const std::exception&) {
            // Destroyed on the way out of an error already being reported: that one stands.
        }
    }
}

void FrameWriter::submit(const RenderedFrame& frame) {
    Stopwatch waiting;
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return error_ || queue_.size() < capacity_; });
    wait_ms_ += waiting.elapsed_ms();
    rethrow_error();
    // A written frame's buffers again, when there is one: the copy then reuses its allocations.
    RenderedFrame copy;
    if (!spare_.empty()) {
        copy = std::move(spare_.back());
        spare_.pop_back();
    }
    lock.unlock();
    copy = frame;  // member by member: each buffer's copy reuses its allocation when big enough
    copy.reuse_stamp = 0;  // a copy: never the frame a trace wrote
    lock.lock();
    queue_.push_back(std::move(copy));
    changed_.notify_all();
}

std::vector<FrameStats> FrameWriter::take_written() {
    const std::lock_guard lock(mutex_);
    return std::exchange(written_, {});
}

void FrameWriter::flush() {
    Stopwatch waiting;
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return error_ || queue_.empty(); });
    wait_ms_ += waiting.elapsed_ms();
    rethrow_error();
}

void FrameWriter::finish() {
    if (finished_) throw std::logic_error("FrameWriter::finish called twice");
    finished_ = true;
    Stopwatch waiting;
    {
        const std::lock_guard lock(mutex_);
        closing_ = true;
        changed_.notify_all();
    }
    thread_.join();
    wait_ms_ += waiting.elapsed_ms();
    std::unique_lock lock(mutex_);
    rethrow_error();
}

int FrameWriter::contact_sheet_frames() const { return sheet_ ? sheet_->size() : 0; }

void FrameWriter::rethrow_error() {
    if (error_) std::rethrow_exception(error_);
}

void FrameWriter::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        changed_.wait(lock, [&] { return closing_ || !queue_.empty(); });
        if (queue_.empty() || error_) break;  // closing, with nothing (more) to write
        RenderedFrame& frame = queue_.front();
        lock.unlock();
        std::exception_ptr error;
        try {
            write(frame);
        } catch (const std::exception& e) {
            error = std::make_exception_ptr(FrameWriteError(frame.stats.frame, e.what()));
        }
        lock.lock();
        if (error) {
            error_ = error;
        } else {
            written_.push_back(frame.stats);
        }
        spare_.push_back(std::move(queue_.front()));
        queue_.pop_front();
        changed_.notify_all();
    }
    queue_.clear();
    lock.unlock();
    // The files that hold the whole sequence: closed whole, with the frames they got, also
    // after an error part way (what was written stays intact).
    std::exception_ptr error;
    try {
        // Without a frame there is no file to finish: none was made.
        if (sequence_file_ && sequence_frames_ > 0) sequence_file_->close();
        sequence_file_.reset();
        if (sheet_ && sheet_->size() > 0) sheet_->write(outputs_.contact_sheet);
    } catch (...) {
        error = std::current_exception();
    }
    lock.lock();
    if (!error_) error_ = error;
}

void FrameWriter::write(RenderedFrame& frame) {
    Stopwatch clock;
    if (sequence_file_) {
        // AOVs of a one-frame sequence file: beside it, named after it.
        for (const Aov aov : outputs_.aovs) write_aov(outputs_.out, aov, frame);
        apply_display(outputs_.display, frame.color);  // the writer's own copy; all 8-bit from here
        sequence_file_->add(frame);
        ++sequence_frames_;
    } else {
        write_frame_now(outputs_, frame);
        if (sheet_) apply_display(outputs_.display, frame.color);
    }
    if (sheet_) sheet_->add(frame.stats.frame - outputs_.first_frame, frame);
    frame.stats.write_ms = clock.elapsed_ms();
}

}  // namespace dynrt
