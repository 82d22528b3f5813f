#include "dynrt/engine/sequence.h"

#include <charconv>
#include <limits>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace dynrt {

namespace {

/// The one integer conversion of a pattern: where it starts and ends, and its spec ("%04d").
struct Conversion {
    std::size_t begin = std::string_view::npos;
    std::size_t end = 0;
};

Conversion find_conversion(std::string_view pattern) {
    Conversion found;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') continue;
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            ++i;
            continue;
        }
        // Flags and width only: anything else (precision, length, another letter) is refused,
        // so the frame number is the only thing a pattern can format.
        std::size_t j = i + 1;
        while (j < pattern.size() && std::string_view("0-+ ").find(pattern[j]) != std::string_view::npos) ++j;
        while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9') ++j;
        if (j >= pattern.size() || pattern[j] != 'd') {
            throw std::invalid_argument("--out '" + std::string(pattern) +
                                        "': only %d (with flags and width, e.g. %04d) may "
                                        "format the frame number; write %% for a percent sign");
        }
        if (found.begin != std::string_view::npos) {
            throw std::invalid_argument("--out '" + std::string(pattern) +
                                        "': more than one %d for the frame number");
        }
        found.begin = i;
        found.end = j + 1;
        i = j;
    }
    return found;
}

/// `text` with "%%" turned into "%".
std::string unescape(std::string_view text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        out += text[i];
        if (text[i] == '%' && i + 1 < text.size() && text[i + 1] == '%') ++i;
    }
    return out;
}

}  // namespace

FrameRange parse_frame_range(std::string_view text) {
    const std::string message = "--frames '" + std::string(text) +
                                "': expected N (frame N alone) or A-B (frames A to B, "
                                "0 <= A <= B)";
    // A whole number, however long: values beyond long long read as its maximum, so that a
    // far frame gets the message about the bound rather than a syntax error.
    const auto number = [](std::string_view t, long long& v) {
        const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec == std::errc::result_out_of_range) v = std::numeric_limits<long long>::max();
        return !t.empty() && ptr == t.data() + t.size() &&
               (ec == std::errc() || ec == std::errc::result_out_of_range);
    };
    const auto check_bound = [&](long long last) {
        if (last > kFrameMax) {
            throw std::invalid_argument("--frames '" + std::string(text) +
                                        "': frame numbers above " + std::to_string(kFrameMax) +
                                        " are not supported");
        }
    };
    const std::size_t dash = text.find('-');
    long long first = 0, last = 0;
    if (dash == std::string_view::npos) {
        // One number is that frame, as Blender's -f and most renderers read it.
        if (!number(text, first) || first < 0) throw std::invalid_argument(message);
        check_bound(first);
        return FrameRange{int(first), int(first)};
    }
    if (!number(text.substr(0, dash), first) || !number(text.substr(dash + 1), last) ||
        last < first) {
        throw std::invalid_argument(message);
    }
    check_bound(last);
    return FrameRange{int(first), int(last)};
}

bool has_frame_number(std::string_view pattern) {
    return find_conversion(pattern).begin != std::string_view::npos;
}

std::string frame_path(std::string_view pattern, int frame) {
    const Conversion c = find_conversion(pattern);
    if (c.begin == std::string_view::npos) return unescape(pattern);
    const std::string spec(pattern.substr(c.begin, c.end - c.begin));
    // Sized by a first call: a wide field ('%233d') must not be cut short, which would give
    // every frame the same name.
    std::string number(std::size_t(std::snprintf(nullptr, 0, spec.c_str(), frame)), '\0');
    std::snprintf(number.data(), number.size() + 1, spec.c_str(), frame);
    return unescape(pattern.substr(0, c.begin)) + number + unescape(pattern.substr(c.end));
}

std::optional<int> frame_of_path(std::string_view pattern, std::string_view path) {
    const Conversion c = find_conversion(pattern);
    if (c.begin == std::string_view::npos) return std::nullopt;
    const std::string prefix = unescape(pattern.substr(0, c.begin));
    const std::string suffix = unescape(pattern.substr(c.end));
    if (path.size() < prefix.size() + suffix.size() || !path.starts_with(prefix) ||
        !path.ends_with(suffix)) {
        return std::nullopt;
    }
    std::string_view number = path.substr(prefix.size(), path.size() - prefix.size() - suffix.size());
    // What %d's flags may put before the digits: padding spaces and a plus sign.
    while (!number.empty() && (number.front() == ' ' || number.front() == '+')) number.remove_prefix(1);
    long long frame = -1;
    const auto [ptr, ec] = std::from_chars(number.data(), number.data() + number.size(), frame);
    if (ec != std::errc() || ptr != number.data() + number.size() || frame < 0 || frame > kFrameMax) {
        return std::nullopt;
    }
    if (frame_path(pattern, int(frame)) != path) return std::nullopt;
    return int(frame);
}

}  // namespace dynrt
