#pragma once
// The accuracy-vs-time study's outputs (offline/study/tradeoff.hpp): the console table, CSV and
// JSON files (one row per configuration, skipped ones with their reason), the Pareto front as a
// PNG (error against ns per step, log-log, the front highlighted and each point of it named),
// and the answer to an error budget.
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "offline/study/tradeoff.hpp"

namespace flexloop::study {

/// The measured rows, sorted by ns per step, front rows marked '*'; the skipped ones counted.
void print_table(std::ostream& out, const TradeoffResult& r);

/// Column names of the CSV file, as written.
std::string csv_header();
void write_csv(const std::string& path, const TradeoffResult& r);
nlohmann::json to_json(const TradeoffResult& r);
void write_front_png(const std::string& path, const TradeoffResult& r, const std::string& title);

/// "cheapest within 1e-3: <config>, 41.2 ns/step, error 3.1e-4; the default (<config>) takes
/// 55.0 ns/step at error 2.0e-6: 25 % less time", or why there is no answer.
std::string budget_answer(const TradeoffResult& r, double budget);

}  // namespace flexloop::study
