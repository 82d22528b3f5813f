#pragma once
// The one writer of the benches' CSV and JSON rows. A row type comes with a function
// for_each(row, visit) that calls visit(key, value) for its columns in output order; this
// writes them:
//   Spread          three CSV columns key_median,key_min,key_max; a JSON {"median","min","max"}
//   infinite double "inf" in CSV; null in JSON, which has no infinity (a perfect PSNR)
//   anything else   as the stream or nlohmann::json writes it
// CSV numbers are written with 9 significant digits (the caller sets the stream's precision).

#include "dynrt/engine/spread.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <ostream>
#include <type_traits>

namespace dynrt::bench_columns {

/// The CSV header of `row`'s columns, each preceded by a comma unless it is the line's first.
template <typename Row, typename ForEach>
void csv_header(std::ostream& out, const Row& row, ForEach&& for_each, bool first = true) {
    for_each(row, [&](const char* key, const auto& value) {
        out << (first ? "" : ",");
        if constexpr (std::is_same_v<std::decay_t<decltype(value)>, Spread>) {
            out << key << "_median," << key << "_min," << key << "_max";
        } else {
            out << key;
        }
        first = false;
    });
}

/// The CSV values of `row`, as csv_header orders them.
template <typename Row, typename ForEach>
void csv_values(std::ostream& out, const Row& row, ForEach&& for_each, bool first = true) {
    for_each(row, [&](const char*, const auto& value) {
        out << (first ? "" : ",");
        first = false;
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, Spread>) {
            out << value.median << ',' << value.min << ',' << value.max;
        } else if constexpr (std::is_floating_point_v<T>) {
            if (std::isinf(value)) {
                out << "inf";
            } else {
                out << value;
            }
        } else {
            out << value;
        }
    });
}

/// `row`'s columns as fields of the JSON object `j`.
template <typename Row, typename ForEach>
void json_fields(nlohmann::ordered_json& j, const Row& row, ForEach&& for_each) {
    for_each(row, [&](const char* key, const auto& value) {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, Spread>) {
            j[key] = spread_json(value);
        } else if constexpr (std::is_floating_point_v<T>) {
            if (std::isinf(value)) {
                j[key] = nullptr;
            } else {
                j[key] = value;
            }
        } else {
            j[key] = value;
        }
    });
}

}  // namespace dynrt::bench_columns
