#pragma once
// Building one-line error messages from pieces. A variadic join instead of chains of
// `"literal" + std::string(...)`: GCC 12 warns falsely (-Wrestrict, GCC bug 105329) on inlined
// operator+(const char*, std::string&&), and the join reads better anyway.

#include <charconv>
#include <concepts>
#include <string>
#include <string_view>

namespace dynrt {

namespace message_text_detail {

inline void append(std::string& out, std::string_view piece) { out += piece; }

template <std::integral Integer>
void append(std::string& out, Integer value) {
    out += std::to_string(value);
}

/// Floating point in its shortest form that reads back exactly ("0.1", "1e+20").
template <std::floating_point Real>
void append(std::string& out, Real value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, result.ptr);
}

}  // namespace message_text_detail

/// Concatenates strings, string views, C strings, integers (in decimal) and floating-point
/// numbers (shortest exact form) into one string.
template <class... Pieces>
std::string cat(const Pieces&... pieces) {
    std::string out;
    (message_text_detail::append(out, pieces), ...);
    return out;
}

}  // namespace dynrt
