#pragma once
// Which frames of a sequence a process renders next, when several render it together
// (`mpirun dynrt render --frames A-B`): guided self-scheduling (Polychronopoulos and Kuck,
// "Guided Self-Scheduling: A Practical Scheduling Scheme for Parallel Supercomputers", IEEE
// Trans. Computers 1987). A process that asks gets the next run of consecutive frames, as long
// as the frames left divided by twice the processes: long runs while much is left, so each
// process's trees stay warm (refit, pixel reuse) from frame to frame, and single frames near
// the end, so a slow frame does not leave the others idle.

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace dynrt::cli {

class FrameHandout {
public:
    /// `todo`: the frames to render, in order (a resumed job leaves out the ones done);
    /// `processes` >= 1.
    FrameHandout(std::vector<int> todo, int processes)
        : todo_(std::move(todo)), processes_(std::size_t(processes)) {
        if (processes < 1) throw std::invalid_argument("FrameHandout: no processes");
    }

    /// The next run for whoever asks: consecutive entries of `todo`, empty once none is left.
    std::vector<int> take() {
        // Twice the processes, not once: a process that got a run of slow frames early still
        // leaves half the frames for the others to share.
        const std::size_t run = std::max<std::size_t>(1, (left() + 2 * processes_ - 1) / (2 * processes_));
        const std::size_t end = std::min(todo_.size(), next_ + run);
        std::vector<int> frames(todo_.begin() + std::ptrdiff_t(next_), todo_.begin() + std::ptrdiff_t(end));
        next_ = end;
        return frames;
    }

    /// Frames not yet handed out.
    std::size_t left() const { return todo_.size() - next_; }

private:
    std::vector<int> todo_;
    std::size_t next_ = 0;
    std::size_t processes_;
};

}  // namespace dynrt::cli
