#pragma once
// Stopping a render between frames on SIGINT (Ctrl-C, `timeout -s INT`) or SIGTERM (`kill`,
// a batch system's time limit): the handler only records the signal; the frame loop asks
// between frames, lets the output stage finish what it was handed, writes the report and the
// journal of the frames done, and exits 128 + the signal, as a shell reports a process the
// signal ended. A second signal, a second or more after the first (`timeout` sends its signal
// twice at once), ends the process at once (the default action): every file is
// written beside its name and renamed over it once whole (atomic_file.h), so even then no torn
// file is left under the user's name.

#include <string>

namespace dynrt::cli {

/// While one exists, SIGINT and SIGTERM are recorded instead of ending the process (the first
/// of them; a second one a second or more later ends it). Restores the previous handlers when destroyed. One at a time.
class InterruptGuard {
public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// The signal received since construction (SIGINT or SIGTERM), or 0. Async-signal-safe.
    static int received();

    /// The exit code for received(): 130 for SIGINT, 143 for SIGTERM.
    static int exit_code();

    /// "SIGINT" or "SIGTERM".
    static std::string signal_name();
};

}  // namespace dynrt::cli
