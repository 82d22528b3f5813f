#pragma once
// A viewer script's commands carried out (viewer_script.h): those on the session (camera,
// time, settings, screenshots) here, the window's own (overlay, capture, quit, waiting for
// frames) handed back to the window.

#include "viewer_script.h"
#include "viewer_session.h"

#include <string>

namespace dynrt::viewer {

/// What the window must do for a command the session does not carry out.
struct WindowStep {
    enum class Action { none, overlay, capture, wait_frames, wait_still, resize, quit };
    Action action = Action::none;
    bool on = true;         ///< overlay on or off
    std::string file;       ///< capture's
    int frames = 0;         ///< wait_frames'
    int width = 0, height = 0;  ///< resize's
};

/// What the window must do for `command` when it is one of the window's own (overlay,
/// capture, wait-frames, wait-still, resize, quit); Action::none for a command on the session. Throws
/// std::invalid_argument naming the script line for a bad argument.
WindowStep window_step(const ScriptCommand& command, const std::string& source);

/// Carries out `command` on `session`, or says what the window must (window_step). Throws
/// std::invalid_argument naming the script line for a bad argument (a setting the session
/// refuses, a number that is not one).
WindowStep run_command(ViewerSession& session, const ScriptCommand& command, const std::string& source);

}  // namespace dynrt::viewer
