#pragma once
// The process's resident set, now and at its peak (the report's rss_bytes and peak_rss_bytes,
// issue 43): what a render really costs in memory, build scratch and allocator overhead
// included, where the byte counts of the engine's containers cannot see; and the memory the
// machine has left, which a backend that would copy a whole scene checks first.

#include <cstddef>

namespace dynrt {

struct ResidentMemory {
    std::size_t current = 0;  ///< bytes resident now (Linux's VmRSS)
    std::size_t peak = 0;     ///< the most ever resident (VmHWM)
};

/// Read from /proc/self/status; zeros where that cannot be read (not Linux).
ResidentMemory resident_memory();

/// Bytes the machine can give the process without swapping (Linux's MemAvailable, from
/// /proc/meminfo); 0 where that cannot be read.
std::size_t available_memory();

/// Starts the peak over from what is resident now (Linux's /proc/self/clear_refs "5"), so that
/// the next resident_memory().peak is the peak since this call: `dynrt bench` measures each
/// row's own. Returns false where it cannot (the peak then runs on).
bool restart_peak_resident();

}  // namespace dynrt
