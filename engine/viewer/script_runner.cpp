// run_command (script_runner.h).

#include "script_runner.h"

#include <cmath>
#include <stdexcept>

namespace dynrt::viewer {

WindowStep run_command(ViewerSession& session, const ScriptCommand& command, const std::string& source) {
    const auto where = [&] { return "script " + source + ", line " + std::to_string(command.line) + ": "; };
    const auto number = [&](std::size_t i) {
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
    };
    const auto on_off = [&](std::size_t i) {
        if (command.args.at(i) != "on" && command.args[i] != "off") {
            throw std::invalid_argument(where() + "'" + command.args[i] + "': on or off");
        }
        return command.args[i] == "on";
    };
    const std::string& name = command.name;
    WindowStep step;
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
            session.set_loop(on_off(0));
        } else if (name == "set") {
            session.set(command.args[0], command.args[1]);
        } else if (name == "screenshot") {
            session.screenshot(command.args[0]);
        } else if (name == "overlay") {
            step = {WindowStep::Action::overlay, on_off(0), {}, 0};
        } else if (name == "capture") {
            step = {WindowStep::Action::capture, true, command.args[0], 0};
        } else if (name == "wait-still") {
            step.action = WindowStep::Action::wait_still;
        } else if (name == "wait-frames") {
            step = {WindowStep::Action::wait_frames, true, {}, int(number(0))};
        } else if (name == "quit") {
            step.action = WindowStep::Action::quit;
        }
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        if (what.rfind("script ", 0) == 0) throw;
        throw std::invalid_argument(where() + what);
    }
    return step;
}

}  // namespace dynrt::viewer
