#pragma once
// A viewer script (`dynrt view --script FILE`): timed inputs that drive the viewer as a user
// would, for tests under Xvfb and for demos. One command per line, after the wall-clock
// second (from the window's first frame) it runs at, in order:
//
//     0.5 orbit 30 -10        # yaw, pitch in degrees
//     1.0 set tracer single   # any setting the panel changes (ViewerSession::set)
//     1.5 play
//     2.0 screenshot out.png  # the frame's image and, beside it, its report
//     2.1 quit
//
// '#' starts a comment; blank lines are skipped. A command is run at the first frame at or
// after its time, never before the frame before it has been drawn; `wait-frames N` holds the
// script until N more frames have been drawn (a still view's frames are all the same).

#include <string>
#include <vector>

namespace dynrt::viewer {

struct ScriptCommand {
    double at_seconds = 0.0;
    std::string name;                ///< orbit, pan, zoom, fly, play, pause, step, seek, ...
    std::vector<std::string> args;  ///< as written
    int line = 0;                    ///< 1-based, for errors
};

/// The commands of a script's text, in order of their times (which must not decrease). Throws
/// std::invalid_argument naming `source`, the line and the problem: an unknown command, a
/// wrong number of arguments, a time that is not a finite number >= 0 or goes backwards.
std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source);

/// parse_script of a file's text; throws std::runtime_error when it cannot be read.
std::vector<ScriptCommand> read_script(const std::string& path);

/// Each command's name, how many arguments it takes and what it does: `dynrt view --help`
/// and the errors list them.
std::string script_commands_help();

}  // namespace dynrt::viewer
