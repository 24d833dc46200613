// SPDX-License-Identifier: BSD-3-Clause
#include "rt/timer_baseline.hpp"

#include <stdexcept>
#include <string>
#include <thread>

namespace flexloop::rt {

TimerBaselineResult run_timer_baseline(const TimerBaselineOptions& options) {
  PeriodicClock clock(options.clock);  // validates period and margin
  if (options.duration_ns < options.clock.period_ns)
    throw std::invalid_argument("baseline duration " + std::to_string(options.duration_ns) +
                                " ns is shorter than one period");
  const std::int64_t periods = options.duration_ns / options.clock.period_ns;

  TimerBaselineResult r;
  r.wakeup_lateness = std::make_unique<LatencyHistogram>();
  LatencyHistogram& lateness = *r.wakeup_lateness;
  std::thread worker([&] {
    r.setup = apply_realtime_setup(options.realtime);
    clock.start();
    while (clock.schedule().periods_elapsed() < periods)
      lateness.record(clock.wait_next().lateness_ns);
  });
  worker.join();

  const DeadlineSchedule& s = clock.schedule();
  r.periods = s.periods_elapsed();
  r.cycles = s.cycles();
  r.overruns = s.overruns();
  r.skipped_periods = s.skipped_periods();
  return r;
}

void merge_into(TimerBaselineResult& total, const TimerBaselineResult& part) {
  total.wakeup_lateness->merge(*part.wakeup_lateness);
  total.periods += part.periods;
  total.cycles += part.cycles;
  total.overruns += part.overruns;
  total.skipped_periods += part.skipped_periods;
}

}  // namespace flexloop::rt
