// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant process (`flexloop plant`, doc/design.md §7): owns the clock and plays the hardware.
// Set-up: the scene sampled at the loop's rate, LCM (command subscription, sensor and stats
// publishers), /dev/cpu_dma_latency held at 0, then rt/loop_process_setup.hpp (pin, mlockall,
// prefaulted stack, SCHED_FIFO when permitted -- the report says when not). Each period:
//   wait for the deadline (rt/periodic_clock.hpp, the chosen wait mode)    -> wake-up lateness
//   settle the last period and take the sample (online/loop/plant_station.hpp)  -> plant TET
//   publish the sensor message, then receive until the answer to it came or the next sample is
//   due (block / hybrid / poll as the wait mode)         -> round trip, controller compute time
//   in the slack, one stage of the once-a-second loop_stats_t (online/loop/loop_accounts.hpp)
// A cycle allocates nothing, takes no lock (but LCM's handle mutex, shared with its receive
// thread only), throws nothing; its system calls are the wait, sendmsg, ppoll and read.
// SIGINT / SIGTERM end the run early (the report covers what ran, "ended": "interrupted"); so
// does the overrun policy of options.limits ("ended": "overrun policy").
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artefact/loop_artefact.hpp"
#include "online/loop/loop_accounts.hpp"
#include "online/loop/loop_options.hpp"
#include "online/loop/sample_ranges.hpp"
#include "plant/runtime/divergence.hpp"
#include "rt/message_validation.hpp"

namespace flexloop::loop {

/// What the run did physically (beside its timing): judged by the same figures `flexloop sim`
/// prints.
struct PhysicalResults {
  std::vector<artefact::Channel> performance, actuators;  ///< names and units, channel-map order
  Eigen::VectorXd rms_performance;  ///< RMS of each true performance output over the run
  Eigen::VectorXd rms_command;      ///< RMS of each command held over the run
  double saturated_share = 0;       ///< periods with a command at the actuator's force limit
  double command_limit = 0;         ///< that limit (infinity: the actuator has none)
};

/// One segment of a run in segments (LoopOptions::segments): its own counts and round trip.
struct SegmentFigures {
  std::int64_t periods = 0, cycles = 0, deadline_misses = 0;
  std::int64_t answers = 0;            ///< answers applied (round trips measured)
  std::int64_t round_trip_p99_ns = 0;  ///< 0 when nothing was answered
};

struct PlantLoopResult {
  LoopAccounts accounts;
  double rate_hz = 0;
  std::int64_t spin_margin_ns = 0;  ///< hybrid: as spun (rt::effective_spin_margin_ns)
  std::int64_t periods = 0;         ///< grid periods elapsed (cycles + skipped)
  std::int64_t cycles = 0;
  std::int64_t samples = 0;  ///< samples taken (seq of the last)
  std::int64_t deadline_misses = 0;
  std::int64_t late_answers = 0;
  std::int64_t overruns = 0;
  std::int64_t skipped_periods = 0;
  std::int64_t safe_command_cycles = 0;
  std::int64_t stats_published = 0;
  std::int64_t publish_failures = 0;
  rt::DropCounts drops;
  std::string setup;  ///< set-up report, one line per step
  bool fifo = false;
  /// The loop stops at a sample whose outputs and command leave the stated range
  /// (plant/runtime/divergence.hpp); `divergence_message` then says when and where.
  plant::runtime::Divergence divergence;
  std::string divergence_message;
  RunEnd end = RunEnd::kDuration;  ///< why the loop ended (online/loop/run_verdict.hpp)
  PhysicalResults physical;
  std::vector<SegmentFigures> segments;  ///< in order; one when the run was not segmented
  /// The samples whose answers the plant did not apply (it held or went safe), by seq.
  SampleRanges unapplied;
  /// LoopOptions::lcm_log: messages written, dropped (the ring full), and what went wrong.
  struct LogFigures {
    std::int64_t recorded = 0, dropped = 0;
    std::string error;
  } lcm_log;
};

/// The physical figures as JSON: {"performance": [{"name", "unit", "rms"}], "command": [...],
/// "saturated_share", "command_limit" (null: none)}.
nlohmann::json physical_json(const PhysicalResults& p);

/// Runs the plant loop of the artefact (options.loop_path and rate_hz unused).
/// std::runtime_error / flexloop::InputError before the loop starts (not in a private network,
/// LCM unavailable, hardware the artefact's sizes refuse).
PlantLoopResult run_plant_loop(const LoopOptions& options, const artefact::LoopArtefact& loop);

/// The run's verdict against o.limits.
RunVerdict plant_verdict(const PlantLoopResult& r, const LoopOptions& o);

/// The figures as JSON (keys of the hil report, "partial" and "verdict" included); with_bins adds
/// the non-empty histogram bins of round trip and wake-up lateness under "histograms" (for drawing
/// them in another process).
nlohmann::json plant_result_json(const PlantLoopResult& r, const LoopOptions& o, bool with_bins);

}  // namespace flexloop::loop
