#include "stage_progress.h"

#include "command_warnings.h"
#include "dynrt/engine/resident_memory.h"

#include <cstdio>
#include <exception>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace dynrt::cli {

StageProgress::StageProgress(std::string what, std::ostream& out, bool in_place, Clock::duration quiet_for,
                             Clock::duration every)
    : what_(std::move(what)), out_(&out), in_place_(in_place), start_(Clock::now()),
      quiet_for_(quiet_for), every_(every), exceptions_(std::uncaught_exceptions()) {
    watcher_ = std::thread([this] { watch(); });
}

namespace {

bool stderr_is_a_terminal() { return isatty(fileno(stderr)) != 0; }

}  // namespace

// On a terminal the line is redrawn every second from two seconds on; in a log (CI, a batch
// job) a line every ten seconds from ten on, so that only a wait worth reading fills it.
StageProgress::StageProgress(std::string what)
    : StageProgress(std::move(what), std::cerr, stderr_is_a_terminal(),
                    std::chrono::seconds(stderr_is_a_terminal() ? 2 : 10),
                    std::chrono::seconds(stderr_is_a_terminal() ? 1 : 10)) {}

StageProgress::~StageProgress() {
    {
        const std::lock_guard lock(mutex_);
        done_ = true;
    }
    wake_.notify_all();
    if (watcher_.joinable()) watcher_.join();
    // A stage that ran past quiet_for closes its lines (also when the watcher, starved of the
    // CPU, wrote none yet). Unwinding: the stage failed, and its error follows.
    if (Clock::now() - start_ < quiet_for_ || verbosity() == Verbosity::quiet) return;
    write(std::uncaught_exceptions() > exceptions_ ? "stopped after" : "done in");
}

void StageProgress::watch() {
    std::unique_lock lock(mutex_);
    if (wake_.wait_until(lock, start_ + quiet_for_, [this] { return done_; })) return;
    if (verbosity() == Verbosity::quiet) return;
    for (;;) {
        write(nullptr);
        if (wake_.wait_for(lock, every_, [this] { return done_; })) return;
    }
}

void StageProgress::write(const char* state) {
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    std::ostringstream line;
    line << what_ << ": " << (state != nullptr ? std::string(state) + " " : std::string()) << std::fixed
         << std::setprecision(state != nullptr ? 1 : 0) << seconds << " s";
    if (const std::size_t resident = resident_memory().current; resident != 0) {
        line << ", " << std::setprecision(1) << double(resident) / 1e9 << " GB resident";
    }
    if (in_place_) {
        *out_ << '\r' << line.str() << (state != nullptr ? "\n" : "  ") << std::flush;
    } else {
        *out_ << line.str() << '\n' << std::flush;
    }
}

}  // namespace dynrt::cli
