// `dynrt view`: the scene in a window (engine/viewer/). The scene is loaded, and the script
// read, before the window opens, so a scene that cannot be read or a bad script fails as
// `dynrt render` would, with no window. Built without GLFW and Dear ImGui, it says so.

#include "view_command.h"

#include "../viewer/viewer_script.h"
#include "../viewer/viewer_session.h"
#if DYNRT_HAVE_VIEWER
#include "../viewer/viewer_window.h"
#endif

#include "dynrt/engine/sequence_output.h"

#include <iostream>
#include <stdexcept>

namespace dynrt::cli {

int run_view(const viewer::ViewArgs& args) {
#if !DYNRT_HAVE_VIEWER
    (void)args;
    throw std::runtime_error("view: this dynrt was built without its window (GLFW and Dear ImGui were not "
                             "found when it was built: bash scripts/install-deps.sh, then build again)");
#else
    const std::string problem = viewer::display_problem();
    if (!problem.empty()) throw std::runtime_error("view: " + problem);
    if (!args.record.empty()) {
        if (!dynrt::is_sequence_file(args.record)) {
            throw std::invalid_argument("--record '" + args.record + "': a .gif or a video (.mp4, .mov, .mkv, .webm, .avi)");
        }
        dynrt::check_sequence_file(args.record);
    }
    const std::vector<viewer::ScriptCommand> script =
        args.script.empty() ? std::vector<viewer::ScriptCommand>{} : viewer::read_script(args.script);
    viewer::ViewerSession session(args);
    return viewer::run_window(session, script, args.script, "dynrt view: " + scene_source(args), args.record);
#endif
}

}  // namespace dynrt::cli
