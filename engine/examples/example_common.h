#pragma once
// Small helpers shared by the example programs (cloth.cpp, lidar.cpp): nothing here is part of
// the library API; a program embedding dynrt would have its own.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace dynrt_example {

/// The median of `values` (taken by copy: it is reordered); 0 when empty.
inline double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    const std::size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(mid), values.end());
    if (values.size() % 2 == 1) return values[mid];
    const double upper = values[mid];
    return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + std::ptrdiff_t(mid)));
}

/// Milliseconds since `start`.
inline double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

/// "640x480" -> {640, 480}; throws std::invalid_argument otherwise.
inline std::pair<int, int> parse_resolution(const std::string& text) {
    int width = 0, height = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &extra) != 3 || x != 'x' ||
        width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        throw std::invalid_argument("--res wants WxH (e.g. 640x480), got '" + text + "'");
    }
    return {width, height};
}

/// `pattern` with its one printf-style integer field ("%d", "%04d") replaced by `number`, e.g.
/// frame_path("cloth/%04d.png", 7) = "cloth/0007.png". Parsed here rather than handed to printf,
/// so a pattern from the command line cannot name other conversions. Throws
/// std::invalid_argument for a pattern without exactly one such field ("%%" is a literal %).
inline std::string frame_path(const std::string& pattern, int number) {
    std::string out;
    int fields = 0;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') {
            out += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            out += '%';
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        const bool zero = j < pattern.size() && pattern[j] == '0';
        if (zero) ++j;
        int width = 0;
        while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && width < 100) {
            width = width * 10 + (pattern[j++] - '0');
        }
        if (j >= pattern.size() || pattern[j] != 'd') {
            throw std::invalid_argument("output pattern '" + pattern +
                                        "': only %d, %Nd or %0Nd may follow a %");
        }
        std::string digits = std::to_string(number);
        if (digits.size() < std::size_t(width)) {
            digits.insert(0, std::size_t(width) - digits.size(), zero ? '0' : ' ');
        }
        out += digits;
        ++fields;
        i = j;
    }
    if (fields != 1) {
        throw std::invalid_argument("output pattern '" + pattern +
                                    "' needs exactly one frame number field such as %04d");
    }
    return out;
}

/// The examples' command line: `--name value` options, each with a help line and a check, and
/// `--help`. Written here in a few lines rather than taken from an option library: the examples
/// show the engine's API, and a header-only parser cost each of them 35-45 s of compile time.
class CommandLine {
public:
    explicit CommandLine(std::string description) : description_(std::move(description)) {}

    /// An integer option taking values in [low, high].
    void add(const std::string& name, int& value, const std::string& help, int low, int high) {
        auto set = [&value, name, low, high](const std::string& s) {
            int parsed = 0;
            const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), parsed);
            if (error != std::errc() || end != s.data() + s.size() || parsed < low ||
                parsed > high) {
                throw std::invalid_argument(name + " wants an integer in [" + std::to_string(low) +
                                            ", " + std::to_string(high) + "], got '" + s + "'");
            }
            value = parsed;
        };
        add_option(name, std::to_string(value), help, std::move(set));
    }
    /// A positive finite number.
    void add(const std::string& name, float& value, const std::string& help) {
        char shortest[32];
        const auto written = std::to_chars(shortest, shortest + sizeof shortest, value);
        add_option(name, std::string(shortest, written.ptr), help, [&value, name](const std::string& text) {
            std::size_t used = 0;
            float parsed = 0.0f;
            try {
                parsed = std::stof(text, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used == 0 || used != text.size() || !(parsed > 0.0f) || !std::isfinite(parsed)) {
                throw std::invalid_argument(name + " wants a positive number, got '" + text + "'");
            }
            value = parsed;
        });
    }
    /// A text option; with `choices`, it must be one of them.
    void add(const std::string& name, std::string& value, const std::string& help,
             std::vector<std::string> choices = {}) {
        add_option(name, value, help, [&value, name, choices](const std::string& text) {
            if (!choices.empty() &&
                std::find(choices.begin(), choices.end(), text) == choices.end()) {
                std::string list;
                for (const std::string& choice : choices) {
                    list += (list.empty() ? "" : ", ") + choice;
                }
                throw std::invalid_argument(name + " wants one of " + list + ", got '" + text +
                                            "'");
            }
            value = text;
        });
    }

    /// Parses argv. Returns -1 to go on, or the exit code to return from main: 0 after --help,
    /// 2 after an unknown option, a missing value or a value failing its check (the message is
    /// printed).
    int parse(int argc, char** argv) const {
        for (int i = 1; i < argc; ++i) {
            const std::string name = argv[i];
            if (name == "--help" || name == "-h") {
                print_help();
                return 0;
            }
            const auto option = std::find_if(options_.begin(), options_.end(),
                                             [&](const Option& o) { return o.name == name; });
            try {
                if (option == options_.end()) {
                    throw std::invalid_argument("unknown option '" + name + "'");
                }
                if (i + 1 >= argc) throw std::invalid_argument(name + " needs a value");
                option->set(argv[++i]);
            } catch (const std::invalid_argument& e) {
                std::fprintf(stderr, "%s\nRun with --help for the options.\n", e.what());
                return 2;
            }
        }
        return -1;
    }

private:
    struct Option {
        std::string name, default_text, help;
        std::function<void(const std::string&)> set;
    };
    void add_option(const std::string& name, std::string default_text, const std::string& help,
                    std::function<void(const std::string&)> set) {
        options_.push_back({name, std::move(default_text), help, std::move(set)});
    }
    void print_help() const {
        std::printf("%s\nOptions:\n", description_.c_str());
        for (const Option& o : options_) {
            const std::string default_note =
                o.default_text.empty() ? "" : " (default: " + o.default_text + ")";
            std::printf("  %-14s %s%s\n", o.name.c_str(), o.help.c_str(), default_note.c_str());
        }
    }
    std::string description_;
    std::vector<Option> options_;
};

/// Creates the folder `path` will be written into, if it has one.
inline void make_parent_folder(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
}

}  // namespace dynrt_example
