// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A periodic clock on CLOCK_MONOTONIC with absolute deadlines: each wait targets d_0 + i T, so
// wake-up errors never accumulate into drift. Three ways to wait:
//   kSleep   clock_nanosleep(TIMER_ABSTIME) until the deadline. Costs no CPU; lateness is the
//            kernel's timer + scheduling latency (tens of us, and on a VM a rare ms tail).
//   kHybrid  sleep until `spin_margin_ns` before the deadline, then spin on the clock. Lateness
//            is the spin loop's granularity as long as the sleep's own lateness stays below the
//            margin; costs margin/T of a CPU (plus whatever else the cycle spins for, e.g.
//            polling for a message: keep the sum well below 95 % of T at SCHED_FIFO).
//   kSpin    spin on the clock the whole period: one full CPU. At SCHED_FIFO the kernel's RT
//            bandwidth limit (sched_rt_runtime_us, doc/design.md §11) throttles such a thread for
//            ~50 ms every second, which shows as a huge max lateness; prefer kHybrid.
// After the wait the cycle is accounted by rt/deadline_schedule.hpp: lateness, overruns
// (starting a whole period late) and the overrun policy (kSkip keeps the grid and counts the
// skipped periods, kReanchor restarts the grid at the late start).
//
// wait_next() makes no allocation, takes no lock and never throws; in kSleep and kHybrid it makes
// the clock_nanosleep system call (retried on EINTR). Honest caveat: nothing here guarantees a
// rate; it measures how well the machine keeps it.
#include <cstdint>
#include <string>

#include "rt/deadline_schedule.hpp"

namespace flexloop::rt {

enum class WaitMode { kSleep, kHybrid, kSpin };

/// "sleep" | "hybrid" | "spin" -> mode; throws std::invalid_argument naming the choices.
WaitMode parse_wait_mode(const std::string& name);
const char* to_string(WaitMode mode);

/// Default hybrid margin: above the typical timer wake-up latency of the 2-core VM this was
/// measured on (SCHED_FIFO sleep lateness p50 ~17 us, p99 30-60 us, like cyclictest there), so
/// the sleep rarely overshoots the spin window. The loop spins margin/T of its CPU.
inline constexpr std::int64_t kDefaultSpinMarginNs = 50'000;

struct PeriodicClockOptions;
/// The margin a loop actually spins: at most half the period. A margin near or above the period
/// (e.g. 50 us at 20 kHz) would make hybrid a pure spin, and a SCHED_FIFO thread that spins more
/// than sched_rt_runtime_us per second (95 %) is stopped by the kernel for the rest of it (50 ms).
std::int64_t effective_spin_margin_ns(const PeriodicClockOptions& options) noexcept;

/// Waits until CLOCK_MONOTONIC >= deadline_ns in the given mode; returns the time it returned
/// (never before the deadline). Allocation-free, noexcept.
std::int64_t wait_until(std::int64_t deadline_ns, WaitMode mode,
                        std::int64_t spin_margin_ns = kDefaultSpinMarginNs) noexcept;

/// Sleeps (clock_nanosleep TIMER_ABSTIME, retried on EINTR) until deadline_ns; no spinning.
void sleep_until(std::int64_t deadline_ns) noexcept;

/// Busy-waits until deadline_ns; returns the time it saw the deadline pass.
std::int64_t spin_until(std::int64_t deadline_ns) noexcept;

struct PeriodicClockOptions {
  std::int64_t period_ns = 1'000'000;
  WaitMode wait_mode = WaitMode::kSleep;
  std::int64_t spin_margin_ns = kDefaultSpinMarginNs;  // kHybrid only
  OverrunPolicy overrun_policy = OverrunPolicy::kSkip;
};

class PeriodicClock {
 public:
  /// period_ns > 0 and spin_margin_ns >= 0, else std::invalid_argument.
  explicit PeriodicClock(const PeriodicClockOptions& options);

  /// Anchors the grid: the first deadline is one period from now.
  void start() noexcept;
  /// Anchors the grid at an explicit first deadline (e.g. shared by two threads).
  void start_at(std::int64_t first_deadline_ns) noexcept;
  /// After a deliberate pause: the next deadline is one period from now, the counts go on.
  void resume() noexcept;

  /// Waits for the next deadline (returns at once when it has passed) and begins that cycle.
  CycleStart wait_next() noexcept;

  std::int64_t next_deadline_ns() const noexcept { return schedule_.next_deadline_ns(); }
  const DeadlineSchedule& schedule() const noexcept { return schedule_; }
  const PeriodicClockOptions& options() const noexcept { return options_; }

 private:
  PeriodicClockOptions options_;
  DeadlineSchedule schedule_;
};

}  // namespace flexloop::rt
