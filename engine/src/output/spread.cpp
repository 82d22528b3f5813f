#include "dynrt/engine/spread.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace dynrt {

Spread spread_of(std::vector<double> values) {
    if (values.empty()) throw std::invalid_argument("spread_of: no values");
    std::sort(values.begin(), values.end());
    return Spread{values[(values.size() - 1) / 2], values.front(), values.back()};
}

std::string format_spread(const Spread& s, int precision) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(precision) << s.median << " (" << s.min << "-"
        << s.max << ")";
    return out.str();
}

std::string format_ratio(double num, double den) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(2);
    if (den > 0) {
        out << num / den;
    } else {
        out << "-";
    }
    return out.str();
}

nlohmann::ordered_json spread_json(const Spread& s) {
    return nlohmann::ordered_json{{"median", s.median}, {"min", s.min}, {"max", s.max}};
}

}  // namespace dynrt
