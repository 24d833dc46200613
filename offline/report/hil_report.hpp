// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The hil report: JSON, histogram PNGs and the printed summary (flexloop hil).
//
// Keys (all latencies in ns, each {min, p50, p99, p999, max, count}):
//   rate_hz, period_ns, wait_mode, duration_s, cycles, periods, deadline_misses, late_answers,
//   overruns, skipped_periods, safe_command_cycles, safe_after, dropped_messages {reason: n},
//   round_trip_ns, wakeup_lateness_ns, plant_compute_ns, controller_compute_ns,
//   controller {answered, resyncs, resumes, dropped_messages, compute_ns, response_ns, ...},
//   baseline {timer {wakeup_lateness_ns, ...}, pingpong {round_trip_ns, unanswered, ...}},
//   scene, lcm_url, cpu, controller_cpu, fifo, set-up texts, lcm_log (when recorded),
//   open_loop (true: no controller process and no answer came: the plant ran alone),
//   verdict {result, reasons, ..., judged (a loop without a controller process: what was)}.
// periods = cycles + skipped_periods: the grid periods the run covered, at least rate x duration,
// more when a stall in the last cycle skipped past the end.
// PNGs beside the report: <stem>_round_trip.png and <stem>_wakeup_lateness.png (log-spaced bins,
// log counts), with the baseline's p50/p99 in the title. Reporting only (allocates, throws).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexloop::report {

/// Writes the report (without its "histograms" bins) atomically to `path` and draws the PNGs;
/// returns the paths written.
std::vector<std::string> write_hil_report(const nlohmann::json& report, const std::string& path);

/// Prints the run's verdict (report "verdict": pass / fail / interrupted, and why).
void print_verdict(const nlohmann::json& report);

/// Prints the run's figures beside its baselines, and its verdict.
void print_hil_summary(const nlohmann::json& report);

/// The run's physical figures (report "physical"): RMS of each performance output beside what
/// `flexloop sim` predicts with the controller off and on, the RMS command and the share of
/// periods in saturation. Nothing when the report has none.
void print_physical(const nlohmann::json& report);

/// One table row per report (rate, misses, round trip, baselines), for `--sweep`.
void print_sweep_table(const std::vector<nlohmann::json>& reports);

}  // namespace flexloop::report
