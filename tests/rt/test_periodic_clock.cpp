// SPDX-License-Identifier: BSD-3-Clause
// rt/deadline_schedule.hpp with synthetic times (deadline grid, lateness, overruns, skip and
// re-anchor), and rt/periodic_clock.hpp on the real clock: it never wakes before a deadline and
// its deadlines stay on the absolute grid whatever the wake-up error.
#include <catch2/catch.hpp>
#include <cstdint>
#include <stdexcept>

#include "rt/monotonic_time.hpp"
#include "rt/periodic_clock.hpp"

using namespace flexloop::rt;

TEST_CASE("on time, cycles follow the absolute grid d0 + i T with their lateness") {
  DeadlineSchedule s(1000, OverrunPolicy::kSkip);
  s.anchor(5000);
  for (std::int64_t i = 0; i < 10; ++i) {
    const std::int64_t late = (i * 37) % 999;  // anything below one period
    const CycleStart c = s.begin_cycle(5000 + i * 1000 + late);
    REQUIRE(c.index == i);
    REQUIRE(c.due_ns == 5000 + i * 1000);
    REQUIRE(c.lateness_ns == late);
    REQUIRE_FALSE(c.overrun);
    REQUIRE(c.skipped == 0);
    REQUIRE(s.next_deadline_ns() == 5000 + (i + 1) * 1000);
  }
  CHECK(s.cycles() == 10);
  CHECK(s.overruns() == 0);
  CHECK(s.periods_elapsed() == 10);
}

TEST_CASE("skip policy: a cycle a whole period late keeps the grid and counts skipped periods") {
  DeadlineSchedule s(1000, OverrunPolicy::kSkip);
  s.anchor(0);
  s.begin_cycle(10);                         // index 0
  const CycleStart c = s.begin_cycle(3250);  // waited for 1000, started 2250 late
  CHECK(c.overrun);
  CHECK(c.lateness_ns == 2250);
  CHECK(c.skipped == 2);  // grid points 1000 and 2000 passed unserved
  CHECK(c.index == 3);
  CHECK(c.due_ns == 3000);
  CHECK(s.next_deadline_ns() == 4000);
  CHECK(s.overruns() == 1);
  CHECK(s.skipped_periods() == 2);
  CHECK(s.cycles() == 2);
  CHECK(s.periods_elapsed() == 4);

  // Exactly one period late is an overrun; one nanosecond less is not.
  const CycleStart on_edge = s.begin_cycle(4000 + 999);
  CHECK_FALSE(on_edge.overrun);
  const CycleStart over = s.begin_cycle(5000 + 1000);
  CHECK(over.overrun);
  CHECK(over.skipped == 1);
  CHECK(over.due_ns == 6000);
}

TEST_CASE("re-anchor policy: a late cycle restarts the grid at its start, nothing skipped") {
  DeadlineSchedule s(1000, OverrunPolicy::kReanchor);
  s.anchor(0);
  const CycleStart c = s.begin_cycle(2600);
  CHECK(c.overrun);
  CHECK(c.lateness_ns == 2600);
  CHECK(c.skipped == 0);
  CHECK(c.index == 0);
  CHECK(c.due_ns == 2600);
  CHECK(s.next_deadline_ns() == 3600);
  const CycleStart next = s.begin_cycle(3610);
  CHECK(next.index == 1);
  CHECK(next.lateness_ns == 10);
  CHECK(s.skipped_periods() == 0);
  CHECK(s.periods_elapsed() == 2);
}

TEST_CASE("bad clock settings and names are refused with the choices") {
  CHECK_THROWS_AS(DeadlineSchedule(0, OverrunPolicy::kSkip), std::invalid_argument);
  CHECK_THROWS_AS(PeriodicClock({.period_ns = 1000, .spin_margin_ns = -1}), std::invalid_argument);
  CHECK(parse_wait_mode("hybrid") == WaitMode::kHybrid);
  CHECK(std::string(to_string(WaitMode::kSpin)) == "spin");
  CHECK_THROWS_WITH(parse_wait_mode("busy"), Catch::Contains("sleep | hybrid | spin"));
  CHECK(parse_overrun_policy("reanchor") == OverrunPolicy::kReanchor);
  CHECK_THROWS_AS(parse_overrun_policy("catch-up"), std::invalid_argument);
}

TEST_CASE("the real clock never wakes before a deadline and keeps the absolute grid") {
  for (const WaitMode mode : {WaitMode::kSleep, WaitMode::kHybrid, WaitMode::kSpin}) {
    INFO("wait mode " << to_string(mode));
    PeriodicClock clock({.period_ns = 500'000, .wait_mode = mode, .spin_margin_ns = 100'000});
    const std::int64_t t0 = monotonic_now_ns() + 1'000'000;
    clock.start_at(t0);
    for (int i = 0; i < 40; ++i) {
      const CycleStart c = clock.wait_next();
      REQUIRE(c.lateness_ns >= 0);
      REQUIRE(c.start_ns >= c.due_ns);
      // On the grid: a skipped period (a slow machine) moves by whole periods only.
      REQUIRE((c.due_ns - t0) % 500'000 == 0);
      REQUIRE(c.due_ns == t0 + c.index * 500'000);
    }
    CHECK(clock.schedule().cycles() == 40);
    CHECK(clock.schedule().periods_elapsed() == 40 + clock.schedule().skipped_periods());
  }
}

TEST_CASE("wait_until returns at or after its deadline, at once when it has passed") {
  const std::int64_t past = monotonic_now_ns() - 1'000'000;
  CHECK(wait_until(past, WaitMode::kSleep) >= past);
  const std::int64_t soon = monotonic_now_ns() + 200'000;
  CHECK(wait_until(soon, WaitMode::kHybrid, 50'000) >= soon);
  const std::int64_t later = monotonic_now_ns() + 200'000;
  CHECK(spin_until(later) >= later);
}
