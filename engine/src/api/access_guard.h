#pragma once
// Detects calls that break the library API's thread-safety contract (dynrt/api/engine.h)
// instead of letting them race: any number of readers (queries, renders) may hold the engine
// at once, or one writer (a change or an update), never both. A call that finds the other kind
// inside throws Error::Code::invalid_state; nobody waits.

#include "dynrt/api/error.h"

#include <atomic>

namespace dynrt::api_detail {

class AccessGuard {
public:
    /// Held for the duration of one reading call.
    class Read {
    public:
        explicit Read(const AccessGuard& guard) : count_(guard.count_) {
            int now = count_.load(std::memory_order_relaxed);
            do {
                if (now < 0) {
                    throw Error(Error::Code::invalid_state,
                                "dynrt::Engine: a query or render started while another thread "
                                "was changing or updating the engine");
                }
            } while (!count_.compare_exchange_weak(now, now + 1, std::memory_order_acquire));
        }
        ~Read() { count_.fetch_sub(1, std::memory_order_release); }
        Read(const Read&) = delete;
        Read& operator=(const Read&) = delete;

    private:
        std::atomic<int>& count_;
    };

    /// Held for the duration of one changing call.
    class Write {
    public:
        explicit Write(AccessGuard& guard) : count_(guard.count_) {
            int idle = 0;
            if (!count_.compare_exchange_strong(idle, -1, std::memory_order_acquire)) {
                throw Error(Error::Code::invalid_state,
                            "dynrt::Engine: a change or update while another thread was " +
                                std::string(idle > 0 ? "tracing or rendering" : "changing") +
                                " the engine (see the thread-safety contract in "
                                "dynrt/api/engine.h)");
            }
        }
        ~Write() { count_.store(0, std::memory_order_release); }
        Write(const Write&) = delete;
        Write& operator=(const Write&) = delete;

    private:
        std::atomic<int>& count_;
    };

private:
    /// Readers inside (> 0), a writer inside (-1) or nobody (0).
    mutable std::atomic<int> count_{0};
};

}  // namespace dynrt::api_detail
