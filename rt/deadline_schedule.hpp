// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The arithmetic of a periodic loop, without any waiting: a grid of absolute deadlines
// d_i = d_0 + i T (CLOCK_MONOTONIC ns), and what happens when a cycle starts late. Kept apart
// from rt/periodic_clock.hpp so that loop logic can be tested with synthetic times.
//
// A cycle waits for its deadline d and starts at s >= d; its wake-up lateness is s - d.
// It is an overrun when it starts a whole period or more late (s - d >= T): it began after the
// next period should have begun (loop_stats_t.overruns). Two ways to go on after an overrun:
//   kSkip      keep the grid: the cycle runs for the latest grid point d + n T <= s, the n
//              periods in between are skipped (counted), the next deadline is d + (n + 1) T.
//              Simulated time then lags behind wall time by n T, which the counts show.
//   kReanchor  move the grid: the cycle runs for s, the next deadline is s + T; nothing is
//              skipped, the phase shifts by s - d.
// Either way a cycle never runs twice in a burst to "catch up". Every call is O(1), noexcept,
// allocation-free.
#include <cstdint>
#include <string>

namespace flexloop::rt {

enum class OverrunPolicy { kSkip, kReanchor };

/// "skip" | "reanchor" -> policy; throws std::invalid_argument naming the choices.
OverrunPolicy parse_overrun_policy(const std::string& name);
const char* to_string(OverrunPolicy policy);

/// What one begun cycle is.
struct CycleStart {
  std::int64_t index = 0;        // grid index i of the deadline this cycle runs for
  std::int64_t due_ns = 0;       // that deadline (after kReanchor: the start time)
  std::int64_t start_ns = 0;     // when the cycle actually started
  std::int64_t lateness_ns = 0;  // start - the deadline waited for (before any skip / re-anchor)
  std::int64_t skipped = 0;      // grid periods skipped just before this cycle (kSkip)
  bool overrun = false;          // lateness_ns >= period
};

class DeadlineSchedule {
 public:
  /// period_ns > 0, else std::invalid_argument.
  DeadlineSchedule(std::int64_t period_ns, OverrunPolicy policy);

  /// Sets the first deadline d_0 (grid index 0) and clears the counts.
  void anchor(std::int64_t first_deadline_ns) noexcept;
  /// Moves the grid after a pause (the loop stood still on purpose): the next deadline is
  /// next_deadline_ns; the counts go on, and the pause counts as no periods.
  void resume_at(std::int64_t next_deadline_ns) noexcept { next_deadline_ns_ = next_deadline_ns; }

  /// The deadline the next cycle waits for.
  std::int64_t next_deadline_ns() const noexcept { return next_deadline_ns_; }
  std::int64_t period_ns() const noexcept { return period_ns_; }
  OverrunPolicy policy() const noexcept { return policy_; }

  /// The next cycle started at start_ns: account for it and advance the deadline.
  CycleStart begin_cycle(std::int64_t start_ns) noexcept;

  std::int64_t cycles() const noexcept { return cycles_; }            // cycles begun
  std::int64_t overruns() const noexcept { return overruns_; }        // cycles that overran
  std::int64_t skipped_periods() const noexcept { return skipped_; }  // grid periods skipped
  /// Periods elapsed on the grid: cycles() + skipped_periods().
  std::int64_t periods_elapsed() const noexcept { return cycles_ + skipped_; }

 private:
  std::int64_t period_ns_;
  OverrunPolicy policy_;
  std::int64_t next_deadline_ns_ = 0;
  std::int64_t next_index_ = 0;
  std::int64_t cycles_ = 0;
  std::int64_t overruns_ = 0;
  std::int64_t skipped_ = 0;
};

}  // namespace flexloop::rt
