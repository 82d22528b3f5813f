// RenderWorker (render_worker.h).

#include "render_worker.h"

#include <algorithm>
#include <chrono>
#include <exception>

namespace dynrt::viewer {

RenderWorker::RenderWorker(ViewerSession& session, std::function<void()> published)
    : session_(session), published_(std::move(published)), thread_([this] { run(); }) {}

RenderWorker::~RenderWorker() {
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    // Closing the window does not wait for a long frame (many samples, a huge scene) to end.
    session_.cancel_render();
    wake_.notify_one();
    thread_.join();
}

std::uint64_t RenderWorker::post(Change change) {
    std::uint64_t number;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        queue_.push_back(std::move(change));
        number = ++posted_;
    }
    if (refining_) session_.cancel_render();
    wake_.notify_one();
    return number;
}

bool RenderWorker::take(Shown& out) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (shown_.number <= out.number) return false;
    out = shown_;
    return true;
}

void RenderWorker::run() {
    using Clock = std::chrono::steady_clock;
    Clock::time_point last = Clock::now();
    int samples = 0;  // of the last frame; 0: none yet
    double render_ms = 0.0;
    while (true) {
        std::vector<Change> changes;
        std::uint64_t applied = 0;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            const bool busy = samples == 0 || !session_.complete() || session_.playing() ||
                              samples < session_.target_samples();
            if (!busy) wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            changes.swap(queue_);
            applied = posted_;
        }
        std::string error;
        bool view_changed = false;
        for (Change& change : changes) {
            try {
                view_changed = change(session_) || view_changed;
            } catch (const std::exception& e) {
                error = e.what();
            }
        }
        const Clock::time_point now = Clock::now();
        if (samples == 0) last = now;  // the clock starts at the first frame
        session_.advance(std::chrono::duration<double>(now - last).count());
        last = now;
        // A view that moves is rendered at one sample per pixel; a still one refined, up to
        // the settings' samples; a converged one not rendered again.
        const bool moving = samples == 0 || view_changed || session_.playing() || !session_.complete();
        const int next = moving ? 1 : std::min(2 * samples, session_.target_samples());
        if (moving || next != samples) {
            samples = next;
            try {
                refining_ = samples > 1;
                session_.render(samples);
            } catch (const std::exception& e) {
                error = e.what();
            }
            refining_ = false;
            render_ms = std::chrono::duration<double, std::milli>(Clock::now() - now).count();
        }
        // A frame stopped for a newer change is not shown: the next turn renders that one.
        if (!session_.complete() && error.empty()) continue;
        publish(applied, render_ms, samples, error);
    }
}

void RenderWorker::publish(std::uint64_t applied, double render_ms, int samples, const std::string& error) {
    // Built outside the lock (the bytes are the frame's size), then swapped in.
    Shown next;
    next.applied = applied;
    next.bytes = session_.display_bytes();
    next.legend = session_.legend();
    next.width = session_.image().width;
    next.height = session_.image().height;
    next.render_ms = render_ms;
    next.history = session_.history();
    next.settings = session_.settings();
    next.cameras = session_.camera_names();
    next.playing = session_.playing();
    next.loop = session_.loop();
    next.frame = session_.frame();
    next.last_frame = session_.last_frame();
    next.speed = session_.speed();
    next.samples = samples;
    next.target_samples = session_.target_samples();
    next.error = error;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        next.number = shown_.number + 1;
        shown_ = std::move(next);
    }
    if (published_) published_();
}

}  // namespace dynrt::viewer
