#include "command_warnings.h"

#include <iostream>
#include <memory>
#include <optional>

namespace dynrt::cli {

namespace {

struct Active {
    Verbosity verbosity = Verbosity::normal;
    WarningLog log;
    std::optional<ScopedWarningLog> scope;
};

/// The one CommandWarnings of the process, if any: a command runs once per process.
std::unique_ptr<Active> active;

WarningDetail detail_of(Verbosity verbosity) {
    switch (verbosity) {
        case Verbosity::quiet: return WarningDetail::none;
        case Verbosity::normal: return WarningDetail::grouped;
        case Verbosity::verbose: return WarningDetail::every;
    }
    return WarningDetail::grouped;
}

}  // namespace

CommandWarnings::CommandWarnings(Verbosity verbosity) {
    active = std::make_unique<Active>();
    active->verbosity = verbosity;
    active->scope.emplace(active->log);
}

CommandWarnings::~CommandWarnings() {
    flush_warnings();
    active.reset();
}

Verbosity verbosity() { return active ? active->verbosity : Verbosity::normal; }

void flush_warnings() {
    if (active) active->log.print(std::cerr, detail_of(active->verbosity));
}

}  // namespace dynrt::cli
