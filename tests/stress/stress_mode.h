#pragma once
// The stress suite's two modes: fast (the default, for CI: about a minute in a Release build)
// and long (`dynrt_stress_tests --stress`: 10 to 50 times the rays and frames). Tests size their
// work with scaled(), so both modes run the same checks.

#include <cstdint>

namespace dynrt::stress {

/// True when the program was started with --stress (set once by main, before any test runs).
bool stress_mode();

/// `fast` in the fast mode, `fast * factor` with --stress.
inline std::int64_t scaled(std::int64_t fast, std::int64_t factor) {
    return stress_mode() ? fast * factor : fast;
}

}  // namespace dynrt::stress
