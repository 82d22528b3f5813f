#include "interrupt.h"

#include <time.h>

#include <atomic>
#include <csignal>
#include <cstdint>

namespace dynrt::cli {

namespace {

// Lock-free, so the handler may use them (async-signal-safe).
std::atomic<int> g_signal{0};
std::atomic<std::int64_t> g_first_ns{0};
static_assert(std::atomic<int>::is_always_lock_free);
static_assert(std::atomic<std::int64_t>::is_always_lock_free);

struct sigaction g_previous_int, g_previous_term;

/// A signal within this long of the first is the same request: `timeout -s INT` sends its
/// signal twice (to the process, then to its process group), and so may a terminal.
constexpr std::int64_t kRepeatNs = 1'000'000'000;

std::int64_t now_ns() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe
    return std::int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

extern "C" void record_signal(int signal) {
    // Not re-entered: the handler blocks both signals while it runs (sa_mask).
    if (g_signal.load() == 0) {
        g_first_ns.store(now_ns());
        g_signal.store(signal);
        return;
    }
    if (now_ns() - g_first_ns.load() < kRepeatNs) return;
    // A second request: its default action, which ends the process at once.
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

}  // namespace

InterruptGuard::InterruptGuard() {
    g_signal.store(0);
    g_first_ns.store(0);
    struct sigaction action = {};
    action.sa_handler = record_signal;
    sigemptyset(&action.sa_mask);
    sigaddset(&action.sa_mask, SIGINT);
    sigaddset(&action.sa_mask, SIGTERM);
    sigaction(SIGINT, &action, &g_previous_int);
    sigaction(SIGTERM, &action, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
    sigaction(SIGINT, &g_previous_int, nullptr);
    sigaction(SIGTERM, &g_previous_term, nullptr);
}

int InterruptGuard::received() { return g_signal.load(); }

int InterruptGuard::exit_code() { return 128 + received(); }

std::string InterruptGuard::signal_name() {
    return received() == SIGTERM ? "SIGTERM" : "SIGINT";
}

}  // namespace dynrt::cli
