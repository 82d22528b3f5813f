#pragma once
// What a slow stage of a command (loading a big scene, or its first frame's build:
// sphere:40000000 takes 3.4 s and 23 s) tells a person while it runs: how long it has taken so
// far and how much memory the process holds, which grows as the scene is read. Nothing for a
// stage that ends quickly.

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

namespace dynrt::cli {

class StageProgress {
public:
    using Clock = std::chrono::steady_clock;

    /// Starts watching the stage `what` (e.g. "loading sphere:100000000"). Once it has run for
    /// `quiet_for`, writes "WHAT: 6 s, 1.3 GB resident" to `out` every `every` (redrawn in
    /// place when `in_place`, on a terminal; else a line each), and a closing "WHAT: done in
    /// 21.3 s, 2.4 GB resident" when it ran that long. `out` must outlive this object.
    StageProgress(std::string what, std::ostream& out, bool in_place, Clock::duration quiet_for,
                  Clock::duration every);
    /// Ends the stage; when it ends by an exception the closing line says "stopped after".
    ~StageProgress();
    StageProgress(const StageProgress&) = delete;
    StageProgress& operator=(const StageProgress&) = delete;

    /// On stderr: on a terminal redrawn in place every second after two; else a line every ten
    /// seconds after ten. Silent under --quiet (command_warnings.h).
    explicit StageProgress(std::string what);

private:
    void watch();
    void write(const char* state);

    std::string what_;
    std::ostream* out_;
    bool in_place_;
    Clock::time_point start_;
    Clock::duration quiet_for_, every_;
    int exceptions_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool done_ = false;
    std::thread watcher_;
};

}  // namespace dynrt::cli
