// SPDX-License-Identifier: BSD-3-Clause
// Timing sanity of the bare timer baseline (rt/timer_baseline.hpp), measured in this run only:
// its counts add up, it never reports a wake-up before the deadline, and the hybrid wait is not
// worse than the plain sleep at p99 by more than kHybridVsSleepFactor. Sleep and hybrid run
// interleaved in short rounds, so that load from other processes hits both alike. No absolute
// time is asserted (doc/design.md §7): absolute figures go to `flexloop baseline` and
// doc/performance.md.
#include <catch2/catch.hpp>
#include <cstdint>
#include <memory>

#include "rt/timer_baseline.hpp"

using namespace flexloop::rt;

namespace {

constexpr std::int64_t kPeriodNs = 100'000;  // 10 kHz
constexpr std::int64_t kRoundNs = 200'000'000;
constexpr int kRounds = 6;
// Hybrid spins the last 50 us, so its typical lateness is far below the sleep's. Its tail is
// not always: a vCPU that spins half of each period is more exposed to being preempted by the
// hypervisor than one that sleeps, and on the 2-core VM under load (load average 5) hybrid's
// p99 was measured up to 2.6 times sleep's. The factor leaves room for that and still catches a
// grossly worse tail; the p50 check catches a hybrid wait that does not spin up to the deadline.
constexpr double kHybridVsSleepFactor = 4.0;

TimerBaselineOptions options(WaitMode mode) {
  TimerBaselineOptions o;
  o.clock = {.period_ns = kPeriodNs, .wait_mode = mode, .spin_margin_ns = 50'000};
  o.duration_ns = kRoundNs;
  // CPU 1, SCHED_FIFO when permitted (the baseline reports it if not); memory is not locked
  // to keep the test binary light.
  o.realtime = {.cpu = 1, .lock_memory = false, .fifo_priority = 80};
  return o;
}

void check_counts(const TimerBaselineResult& r) {
  INFO(r.setup.describe());
  CHECK(r.periods == r.cycles + r.skipped_periods);
  CHECK(r.periods >= kRoundNs / kPeriodNs);
  CHECK(r.wakeup_lateness->count() == r.cycles);
  CHECK(r.overruns <= r.cycles);
  CHECK(r.skipped_periods >= r.overruns);  // every overrun under kSkip skips >= 1 period
  CHECK(r.wakeup_lateness->min() >= 0);
}

}  // namespace

TEST_CASE("timer baseline: counts add up and hybrid p99 is within a factor of sleep's") {
  auto sleep = std::make_unique<LatencyHistogram>();
  auto hybrid = std::make_unique<LatencyHistogram>();
  for (int round = 0; round < kRounds; ++round) {
    const auto s = run_timer_baseline(options(WaitMode::kSleep));
    const auto h = run_timer_baseline(options(WaitMode::kHybrid));
    check_counts(s);
    check_counts(h);
    sleep->merge(*s.wakeup_lateness);
    hybrid->merge(*h.wakeup_lateness);
  }
  const auto ss = sleep->summary(), hs = hybrid->summary();
  // Printed for the record (ns): not asserted.
  WARN("sleep  lateness min/p50/p99/p99.9/max " << ss.min << " " << ss.p50 << " " << ss.p99 << " "
                                                << ss.p999 << " " << ss.max);
  WARN("hybrid lateness min/p50/p99/p99.9/max " << hs.min << " " << hs.p50 << " " << hs.p99 << " "
                                                << hs.p999 << " " << hs.max);
  CHECK(static_cast<double>(hs.p99) <= kHybridVsSleepFactor * static_cast<double>(ss.p99));
  CHECK(hs.p50 <= ss.p50);  // spinning the last 50 us cannot make the typical wake-up later
}
