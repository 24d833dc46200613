// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The accuracy-vs-time study's outputs (offline/study/tradeoff.hpp): the console table, CSV and
// JSON files (one row per configuration, skipped ones with their reason), the Pareto front as a
// PNG (error, log, against the cost on an axis fitted to the data: cost_axis; the front
// highlighted and each point of it named),
// and the answer to an error budget.
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "offline/study/tradeoff.hpp"

namespace flexloop::study {

/// The measured rows, sorted by ns per step, front rows marked '*'; the skipped ones counted.
void print_table(std::ostream& out, const TradeoffResult& r);

/// Column names of the CSV file, as written.
std::string csv_header();
void write_csv(const std::string& path, const TradeoffResult& r);
nlohmann::json to_json(const TradeoffResult& r);
void write_front_png(const std::string& path, const TradeoffResult& r, const std::string& title);

/// The cost axis of the front's picture, chosen from the costs it shows (the measured rows' ns
/// per step, or % of the period): logarithmic when they span more than a decade, else linear,
/// and in both cases the data's span with kCostAxisMargin of it added at each end (in decades on
/// a log axis), so that the points spread over the picture -- a step cost of 50 to 90 ns on
/// gnuplot's own log axis of 10 to 100 ns drew the front as a vertical line. Equal costs get
/// +-10 % around them; a linear axis never starts below 0.
struct AxisRange {
  double min = 0, max = 0;
  bool log = false;
};
inline constexpr double kCostAxisMargin = 0.08;
AxisRange cost_axis(const std::vector<double>& costs);
/// cost_axis of the costs of r's measured rows (r.cost).
AxisRange front_cost_axis(const TradeoffResult& r);

/// "cheapest within 1e-3: <config>, 41.2 ns/step, error 3.1e-4; the default (<config>) takes
/// 55.0 ns/step at error 2.0e-6: 25 % less time", or why there is no answer.
std::string budget_answer(const TradeoffResult& r, double budget);

}  // namespace flexloop::study
