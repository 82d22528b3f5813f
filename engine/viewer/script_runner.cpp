// run_command (script_runner.h).

#include "script_runner.h"

#include <cmath>
#include <stdexcept>

namespace dynrt::viewer {

namespace {

/// A command's arguments read as numbers or on/off, errors naming the script and the line.
struct Arguments {
    const ScriptCommand& command;
    const std::string& source;

    std::string where() const { return "script " + source + ", line " + std::to_string(command.line) + ": "; }
    double number(std::size_t i) const {
        std::size_t used = 0;
        double value = 0.0;
        try {
            value = std::stod(command.args.at(i), &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != command.args[i].size() || !std::isfinite(value)) {
            throw std::invalid_argument(where() + "'" + command.args[i] + "' is not a number");
        }
        return value;
    }
    bool on_off(std::size_t i) const {
        if (command.args.at(i) != "on" && command.args[i] != "off") {
            throw std::invalid_argument(where() + "'" + command.args[i] + "': on or off");
        }
        return command.args[i] == "on";
    }
};

}  // namespace

WindowStep window_step(const ScriptCommand& command, const std::string& source) {
    const Arguments args{command, source};
    const std::string& name = command.name;
    if (name == "overlay") return {WindowStep::Action::overlay, args.on_off(0), {}, 0};
    if (name == "capture") return {WindowStep::Action::capture, true, command.args[0], 0};
    if (name == "wait-still") return {WindowStep::Action::wait_still, true, {}, 0};
    if (name == "quit") return {WindowStep::Action::quit, true, {}, 0};
    if (name == "wait-frames") {
        const double frames = args.number(0);
        if (frames < 0.0 || frames != std::floor(frames)) {
            throw std::invalid_argument(args.where() + "'" + command.args[0] + "' is not a count of frames");
        }
        return {WindowStep::Action::wait_frames, true, {}, int(frames)};
    }
    if (name == "resize") {
        WindowStep step;
        step.action = WindowStep::Action::resize;
        for (int i = 0; i < 2; ++i) {
            const double size = args.number(std::size_t(i));
            if (size < 1.0 || size > double(ViewerSession::kMaxSize) || size != std::floor(size)) {
                throw std::invalid_argument(args.where() + "'" + command.args[std::size_t(i)] + "': a size in pixels, 1 to " +
                                            std::to_string(ViewerSession::kMaxSize));
            }
            (i == 0 ? step.width : step.height) = int(size);
        }
        return step;
    }
    return {};
}

WindowStep run_command(ViewerSession& session, const ScriptCommand& command, const std::string& source) {
    if (const WindowStep step = window_step(command, source); step.action != WindowStep::Action::none) return step;
    const Arguments args{command, source};
    const auto number = [&](std::size_t i) { return args.number(i); };
    const std::string& name = command.name;
    try {
        if (name == "orbit") {
            session.camera().orbit(float(number(0)), float(number(1)));
        } else if (name == "pan") {
            session.camera().pan(float(number(0)), float(number(1)));
        } else if (name == "zoom") {
            session.camera().zoom(float(number(0)));
        } else if (name == "fly") {
            session.camera().fly(float(number(0)), float(number(1)), float(number(2)));
        } else if (name == "reset-camera") {
            session.reset_camera();
        } else if (name == "camera") {
            const double index = number(0);
            if (index < 0.0 || index != std::floor(index)) throw std::invalid_argument("camera '" + command.args[0] + "': not an index");
            try {
                session.use_scene_camera(std::size_t(index));
            } catch (const std::out_of_range& e) {
                throw std::invalid_argument(e.what());
            }
        } else if (name == "play") {
            session.play();
        } else if (name == "pause") {
            session.pause();
        } else if (name == "step") {
            session.step(command.args.empty() ? 1 : int(number(0)));
        } else if (name == "seek") {
            session.seek(int(number(0)));
        } else if (name == "speed") {
            session.set_speed(number(0));
        } else if (name == "loop") {
            session.set_loop(args.on_off(0));
        } else if (name == "set") {
            session.set(command.args[0], command.args[1]);
        } else if (name == "screenshot") {
            session.screenshot(command.args[0]);
        }
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        if (what.rfind("script ", 0) == 0) throw;
        throw std::invalid_argument(args.where() + what);
    }
    return {};
}

}  // namespace dynrt::viewer
