// SPDX-License-Identifier: BSD-3-Clause
// rt/shm_pingpong_baseline.hpp, without timing judgement (it runs beside other tests): every
// recorded round trip is counted once, the figures are ordered and add up to no more than the
// wall time the run took, the pong is reaped, and the anonymous page leaves no /dev/shm entry.
#include <sys/wait.h>
#include <catch2/catch.hpp>

#include <cerrno>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

#include "rt/monotonic_time.hpp"
#include "rt/shm_pingpong_baseline.hpp"
#include "tests/support/dev_shm.hpp"

using namespace flexloop::rt;
using flexloop::test::dev_shm_entries;

namespace {

// Unprivileged and unlocked: the two processes share the CPUs with whatever else runs.
ShmPingPongOptions gentle(std::int64_t round_trips) {
  ShmPingPongOptions o;
  o.round_trips = round_trips;
  o.warm_up = 100;
  o.ping_realtime = {.cpu = 0, .lock_memory = false, .fifo_priority = 0};
  o.pong_realtime = {.cpu = 1, .lock_memory = false, .fifo_priority = 0};
  return o;
}

}  // namespace

TEST_CASE("shm floor: every round trip recorded once, within the run's wall time, nothing left") {
  const auto before = dev_shm_entries();
  const std::int64_t start = monotonic_now_ns();
  const ShmPingPongResult r = run_shm_pingpong_baseline(gentle(2000));
  const std::int64_t wall = monotonic_now_ns() - start;

  CHECK(r.round_trips == 2000);
  const LatencySummary s = r.round_trip->summary();
  CHECK(s.count == 2000);
  CHECK(s.min > 0);  // a store, the other core's load and store, our load: never free
  CHECK(s.min <= s.p50);
  CHECK(s.p50 <= s.p99);
  CHECK(s.p99 <= s.max);
  // The recorded intervals are disjoint parts of the call: their sum cannot exceed its length.
  CHECK(r.round_trip->mean() * static_cast<double>(s.count) <= static_cast<double>(wall));
  CHECK_THAT(r.pong_setup, Catch::Contains("CPU 1"));
  CHECK_THAT(r.ping_setup, Catch::Contains("CPU 0"));

  int status = 0;
  CHECK(waitpid(-1, &status, WNOHANG) == -1);  // no child left, reaped or running
  CHECK(errno == ECHILD);
  CHECK(dev_shm_entries() == before);
}

TEST_CASE("shm floor: a count below one or a non-positive give-up time is refused before forking") {
  CHECK_THROWS_AS(run_shm_pingpong_baseline(gentle(0)), std::invalid_argument);
  ShmPingPongOptions o = gentle(10);
  o.give_up_ns = 0;
  CHECK_THROWS_AS(run_shm_pingpong_baseline(o), std::invalid_argument);
}
