#pragma once
// Building one-line error messages from pieces. A variadic join instead of chains of
// `"literal" + std::string(...)`: GCC 12 warns falsely (-Wrestrict, GCC bug 105329) on inlined
// operator+(const char*, std::string&&), and the join reads better anyway.

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

}  // namespace message_text_detail

/// Concatenates strings, string views, C strings and integers (in decimal) into one string.
template <class... Pieces>
std::string cat(const Pieces&... pieces) {
    std::string out;
    (message_text_detail::append(out, pieces), ...);
    return out;
}

}  // namespace dynrt
