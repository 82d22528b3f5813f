#pragma once
// What a command tells a person on stderr besides its errors: warnings grouped once per kind of
// problem (dynrt/scene/warnings.h), every one of them with --verbose, none with --quiet, which
// also silences the progress bar and the table (the output files and the exit code remain).

#include "dynrt/scene/warnings.h"

namespace dynrt::cli {

enum class Verbosity { quiet, normal, verbose };

/// Collects every warning of the command while it lives (warnings from any thread), and prints
/// what is left when it ends, also when the command fails.
class CommandWarnings {
public:
    explicit CommandWarnings(Verbosity verbosity);
    ~CommandWarnings();
    CommandWarnings(const CommandWarnings&) = delete;
    CommandWarnings& operator=(const CommandWarnings&) = delete;
};

/// The running command's verbosity (normal when no CommandWarnings is alive).
Verbosity verbosity();

/// Prints the warnings collected so far on stderr; the commands call it once the scene has
/// loaded and before their table, so that warnings come before the figures, not among them.
void flush_warnings();

}  // namespace dynrt::cli
