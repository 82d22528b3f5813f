// parse_script (viewer_script.h).

#include "viewer_script.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dynrt::viewer {

namespace {

struct CommandShape {
    const char* name;
    int min_args, max_args;
    const char* help;
};

constexpr CommandShape kCommands[] = {
    {"orbit", 2, 2, "YAW PITCH: turn the eye around the target, in degrees"},
    {"pan", 2, 2, "RIGHT UP: move across the view, in units of the distance to the target"},
    {"zoom", 1, 1, "FACTOR: divide the distance to the target (> 1 closer)"},
    {"fly", 3, 3, "FORWARD RIGHT UP: move along the view, in units of the distance"},
    {"reset-camera", 0, 0, "back to the first view"},
    {"camera", 1, 1, "INDEX: look through the scene file's camera INDEX (from 0)"},
    {"play", 0, 0, "play the animation at its frame rate (wall time)"},
    {"pause", 0, 0, "hold the animation at its frame"},
    {"step", 0, 1, "[N]: pause and go N frames on (default 1; negative: back)"},
    {"seek", 1, 1, "FRAME: pause at that frame"},
    {"speed", 1, 1, "X: play at X times the frame rate"},
    {"loop", 1, 1, "on|off: play again from the first frame past the last"},
    {"set", 2, 2, "NAME VALUE: a setting, as its flag takes it (tracer, depth, reuse, spp, ...)"},
    {"overlay", 1, 1, "on|off: the panels over the image"},
    {"resize", 2, 2, "WIDTH HEIGHT: resize the window (the image follows it) and wait for its frame"},
    {"screenshot", 1, 1, "FILE.png: the frame's image and FILE.json, its report and camera"},
    {"capture", 1, 1, "FILE.png: what the window shows, read back from it"},
    {"wait-frames", 1, 1, "N: hold the script until N more frames are drawn"},
    {"wait-still", 0, 0, "hold the script until the view has refined to its samples per pixel (--spp)"},
    {"quit", 0, 0, "close the window"},
};

const CommandShape* shape_of(const std::string& name) {
    for (const CommandShape& c : kCommands) {
        if (name == c.name) return &c;
    }
    return nullptr;
}

}  // namespace

std::string script_commands_help() {
    std::ostringstream out;
    for (const CommandShape& c : kCommands) out << "  " << c.name << ' ' << c.help << '\n';
    return out.str();
}

std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source) {
    std::vector<ScriptCommand> commands;
    std::istringstream lines(text);
    std::string line;
    int number = 0;
    double last = 0.0;
    while (std::getline(lines, line)) {
        ++number;
        const auto fail = [&](const std::string& why) {
            throw std::invalid_argument("script " + source + ", line " + std::to_string(number) + ": " + why);
        };
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream words(line);
        std::string first;
        if (!(words >> first)) continue;
        ScriptCommand command;
        command.line = number;
        std::size_t used = 0;
        try {
            command.at_seconds = std::stod(first, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != first.size() || !std::isfinite(command.at_seconds) || command.at_seconds < 0.0) {
            fail("'" + first + "' is not a time in seconds (a number >= 0) before the command");
        }
        if (command.at_seconds < last) fail("its time " + first + " is before the line above's");
        last = command.at_seconds;
        if (!(words >> command.name)) fail("a time with no command");
        const CommandShape* shape = shape_of(command.name);
        if (shape == nullptr) fail("unknown command '" + command.name + "'; the commands are:\n" + script_commands_help());
        for (std::string arg; words >> arg;) command.args.push_back(arg);
        const int n = int(command.args.size());
        if (n < shape->min_args || n > shape->max_args) {
            fail("'" + command.name + "' takes " +
                 (shape->min_args == shape->max_args ? std::to_string(shape->min_args)
                                                     : std::to_string(shape->min_args) + " to " + std::to_string(shape->max_args)) +
                 " argument(s), not " + std::to_string(n) + " (" + shape->help + ")");
        }
        commands.push_back(std::move(command));
    }
    return commands;
}

std::vector<ScriptCommand> read_script(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("script " + path + ": cannot be read");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_script(text.str(), path);
}

}  // namespace dynrt::viewer
