#pragma once
// Small helpers shared by the example programs (cloth.cpp, lidar.cpp): nothing here is part of
// the library API; a program embedding dynrt would have its own.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
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

/// Creates the folder `path` will be written into, if it has one.
inline void make_parent_folder(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
}

}  // namespace dynrt_example
