#pragma once
// Summaries of repeated measurements, the one summariser of the reports and benches: median,
// min and max, and how each is written (a table cell "median (min-max)", a ratio of medians,
// a JSON object {"median", "min", "max"}).

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace dynrt {

/// Median (the lower one for an even count, so that integer figures stay values that
/// occurred), min and max of repeated measurements.
struct Spread {
    double median = 0;
    double min = 0;
    double max = 0;
};

/// Summarises `values`. Throws std::invalid_argument when it is empty.
Spread spread_of(std::vector<double> values);

/// "median (min-max)" with `precision` decimals.
std::string format_spread(const Spread& s, int precision = 2);

/// num / den with two decimals, or "-" when den is not positive (a figure not measured).
std::string format_ratio(double num, double den);

/// {"median": ..., "min": ..., "max": ...}.
nlohmann::ordered_json spread_json(const Spread& s);

}  // namespace dynrt
