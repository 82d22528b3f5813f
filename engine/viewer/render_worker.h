#pragma once
// The viewer's frames, rendered on a thread of their own (`dynrt view`): the window never
// waits for a frame. It posts changes (camera moves, time, settings, script commands) and
// shows the newest finished frame; the worker applies the changes posted since its last frame,
// moves the clock by the wall time that passed, renders, and publishes the frame with what the
// panels show of the session then. It renders while something changed or the animation plays,
// and refines a still view: with --spp N > 1, a view that moves is rendered at one sample per
// pixel, and once it holds still at 2, 4, ... up to N, so the image converges to `dynrt render
// --spp N`'s, bit for bit; then the worker sleeps until something changes.
//
// The session is touched by the worker's thread alone once the worker runs: the window reads
// the published Shown copies.

#include "viewer_session.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace dynrt::viewer {

class RenderWorker {
public:
    /// A frame and what the panels show of the session as it was rendered.
    struct Shown {
        std::uint64_t number = 0;   ///< frames published so far (0: none yet)
        std::uint64_t applied = 0;  ///< changes applied before it was rendered
        int width = 0, height = 0;
        std::vector<unsigned char> bytes;  ///< ViewerSession::display_bytes
        std::string legend;                ///< ViewerSession::legend: the cost view's colours
        double render_ms = 0.0;            ///< the worker's time for it: render and bytes
        std::deque<FrameStats> history;
        std::vector<std::pair<std::string, std::string>> settings;
        std::vector<std::string> cameras;
        bool playing = false, loop = true;
        int frame = 0, last_frame = 0;
        double speed = 1.0;
        int samples = 1, target_samples = 1;  ///< this frame's samples per pixel, and --spp
        /// The last change that failed since the previous frame (its message), or "".
        std::string error;

        bool converged() const { return samples >= target_samples; }
    };

    /// A change to make on the session; true when it changes the view (the camera, the
    /// time, a setting), false when it does not (a screenshot): then nothing is rendered again.
    using Change = std::function<bool(ViewerSession&)>;

    /// Starts rendering `session` (borrowed; only this worker's thread touches it until
    /// destruction). `published`, if given, is called on the worker's thread after each frame
    /// is published (the window wakes its event loop with it).
    explicit RenderWorker(ViewerSession& session, std::function<void()> published = {});
    /// Stops the frame at hand (ViewerSession::cancel_render) and the thread.
    ~RenderWorker();
    RenderWorker(const RenderWorker&) = delete;
    RenderWorker& operator=(const RenderWorker&) = delete;

    /// Queues `change` for the worker's thread, before its next frame; returns how many changes
    /// have been posted in all (a frame whose `applied` reaches it shows this one). A
    /// refinement step being rendered (more than one sample per pixel) is stopped
    /// (ViewerSession::cancel_render) so that the change is shown sooner; a frame at one
    /// sample per pixel is finished, so that a stream of changes (a drag) cannot stop every
    /// frame and leave none to show.
    std::uint64_t post(Change change);
    /// Copies the newest frame into `out` when it is newer than out.number; true then.
    bool take(Shown& out) const;
    /// How far the frame being rendered now has come (Renderer::progress). Any thread.
    RenderProgress progress() const { return session_.renderer().progress(); }

private:
    void run();
    /// Publishes the session's last frame as frame `applied` changes in; `rendered`: it was
    /// rendered for this publication (else the last one again, e.g. after a screenshot).
    void publish(std::uint64_t applied, double render_ms, int samples, const std::string& error);

    ViewerSession& session_;
    std::function<void()> published_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<Change> queue_;
    std::uint64_t posted_ = 0;
    bool stop_ = false;
    /// Whether the frame being rendered is a refinement step, which a change may stop.
    std::atomic<bool> refining_{false};
    Shown shown_;  ///< the newest frame, under mutex_
    std::thread thread_;
};

}  // namespace dynrt::viewer
