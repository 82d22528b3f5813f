#pragma once
// How many fields an aggregate has, found at compile time: the most initialisers that a
// braced list of it takes (each a value that converts to any type). The technique Boost.PFR
// uses. A base class counts as one field. For the checks that a list written by hand names
// every field of a struct (job_settings.cpp).

#include <cstddef>
#include <utility>

namespace dynrt::cli {

namespace field_count_detail {

/// Converts to anything; declared only, for unevaluated use.
struct AnyField {
    template <class T>
    operator T() const;
};

template <class T, std::size_t... I>
constexpr bool braces_take(std::index_sequence<I...>) {
    return requires { T{(void(I), AnyField{})...}; };
}

}  // namespace field_count_detail

/// The number of fields of the aggregate `T` (its direct base, if any, counting as one).
template <class T, std::size_t N = 0>
constexpr std::size_t field_count() {
    if constexpr (!field_count_detail::braces_take<T>(std::make_index_sequence<N + 1>{})) {
        return N;
    } else {
        return field_count<T, N + 1>();
    }
}

}  // namespace dynrt::cli
