// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Same-run baseline (a): a bare periodic thread with the loop's period and settings that does
// nothing but wake up, as cyclictest does. Its wake-up lateness is what the machine gives any
// loop; a loop's own figures are judged against it (doc/design.md §7).
//
// run_timer_baseline() starts one thread, sets it up in the order of rt/realtime_setup.hpp
// (pin, mlockall + prefault, then SCHED_FIFO when asked and permitted), runs a PeriodicClock
// until `duration_ns` worth of periods have elapsed on its grid, and returns the lateness
// histogram and counts. Only the thread's set-up and the final result allocate.
#include <cstdint>
#include <memory>

#include "rt/latency_histogram.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/periodic_clock.hpp"
#include "rt/realtime_setup.hpp"

namespace flexloop::rt {

struct TimerBaselineOptions {
  PeriodicClockOptions clock;
  std::int64_t duration_ns = kNsPerSecond;
  RealtimeOptions realtime;  // cpu, memory locking, SCHED_FIFO priority of the thread
};

struct TimerBaselineResult {
  std::unique_ptr<LatencyHistogram> wakeup_lateness;  // one sample per cycle, ns
  std::int64_t periods = 0;   // grid periods covered: cycles + skipped_periods
  std::int64_t cycles = 0;    // cycles that ran
  std::int64_t overruns = 0;  // cycles that started a whole period late
  std::int64_t skipped_periods = 0;
  RealtimeReport setup;
};

/// Runs the baseline on a new thread and waits for it. std::invalid_argument for a bad period,
/// margin or duration (duration_ns < period_ns).
TimerBaselineResult run_timer_baseline(const TimerBaselineOptions& options);

/// Adds a later run's cycles, counts and histogram to `total` (a baseline measured in segments).
void merge_into(TimerBaselineResult& total, const TimerBaselineResult& part);

}  // namespace flexloop::rt
