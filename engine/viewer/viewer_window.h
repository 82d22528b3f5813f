#pragma once
// `dynrt view`'s window: GLFW for the window and input, Dear ImGui for the panels, the frame
// drawn 1:1 from the session's display bytes (the same bytes `dynrt render` writes to a PNG).

#include "viewer_script.h"
#include "viewer_session.h"

#include <string>
#include <vector>

namespace dynrt::viewer {

/// Why no window can be opened here, or "" when one may be: no X11 or Wayland display named
/// in the environment.
std::string display_problem();

/// Opens the window on `session` and runs until it is closed, or the script (read from
/// `script_source`) quits; with `record_path`, every frame drawn is written to that sequence
/// file (sequence_output.h). Returns the process exit status: 0, or 1 after printing why the
/// window could not be opened or a script command failed.
int run_window(ViewerSession& session, const std::vector<ScriptCommand>& script, const std::string& script_source,
               const std::string& title, const std::string& record_path = {});

}  // namespace dynrt::viewer
