// SPDX-License-Identifier: BSD-3-Clause
#include "rt/periodic_clock.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>

#include "rt/enum_names.hpp"
#include "rt/monotonic_time.hpp"

namespace flexloop::rt {

namespace {

inline void cpu_relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

}  // namespace

constexpr EnumName<WaitMode> kWaitModeNames[] = {
    {WaitMode::kSleep, "sleep"}, {WaitMode::kHybrid, "hybrid"}, {WaitMode::kSpin, "spin"}};

WaitMode parse_wait_mode(const std::string& name) {
  return parse_enum(kWaitModeNames, name, "wait mode");
}

const char* to_string(WaitMode mode) {
  return enum_name(kWaitModeNames, mode);
}

void sleep_until(std::int64_t deadline_ns) noexcept {
  const timespec ts = to_timespec(deadline_ns);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

std::int64_t spin_until(std::int64_t deadline_ns) noexcept {
  std::int64_t now = monotonic_now_ns();
  while (now < deadline_ns) {
    cpu_relax();
    now = monotonic_now_ns();
  }
  return now;
}

std::int64_t wait_until(std::int64_t deadline_ns, WaitMode mode,
                        std::int64_t spin_margin_ns) noexcept {
  switch (mode) {
    case WaitMode::kSleep:
      sleep_until(deadline_ns);
      return monotonic_now_ns();
    case WaitMode::kHybrid:
      if (monotonic_now_ns() < deadline_ns - spin_margin_ns)
        sleep_until(deadline_ns - spin_margin_ns);
      return spin_until(deadline_ns);
    case WaitMode::kSpin:
      return spin_until(deadline_ns);
  }
  return monotonic_now_ns();
}

PeriodicClock::PeriodicClock(const PeriodicClockOptions& options)
    : options_(options), schedule_(options.period_ns, options.overrun_policy) {
  if (options.spin_margin_ns < 0)
    throw std::invalid_argument("spin margin must not be negative, got " +
                                std::to_string(options.spin_margin_ns) + " ns");
}

void PeriodicClock::start() noexcept {
  start_at(monotonic_now_ns() + options_.period_ns);
}

void PeriodicClock::resume() noexcept {
  schedule_.resume_at(monotonic_now_ns() + options_.period_ns);
}

void PeriodicClock::start_at(std::int64_t first_deadline_ns) noexcept {
  schedule_.anchor(first_deadline_ns);
}

std::int64_t effective_spin_margin_ns(const PeriodicClockOptions& o) noexcept {
  return std::min(o.spin_margin_ns, o.period_ns / 2);
}

CycleStart PeriodicClock::wait_next() noexcept {
  const std::int64_t woke = wait_until(schedule_.next_deadline_ns(), options_.wait_mode,
                                       effective_spin_margin_ns(options_));
  return schedule_.begin_cycle(woke);
}

}  // namespace flexloop::rt
