// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Same-host baseline: the physical floor of a round trip between two processes -- no transport,
// no clock, no message: two processes pinned to the two cores, spinning on one cache line of
// shared memory (issue 48). An iceoryx or LCM round trip is read against it, same run.
//
// run_shm_pingpong_baseline() maps one anonymous shared page (MAP_SHARED | MAP_ANONYMOUS before
// the fork: it has no name, so no /dev/shm entry exists on any path, and the kernel frees it
// when both processes are gone) and forks. The child ("pong", pong_realtime) copies every new
// value of the ping word into the pong word; the parent ("ping", ping_realtime) stores i into
// the ping word and spins until the pong word reads i: round trip = the two monotonic stamps
// around that. warm_up round trips go first and are not recorded; then round_trips recorded
// back to back (no period: this is the floor, not a loop).
//
// Both sides spin. With SCHED_FIFO a spinning thread owns its CPU, so pin them to two different
// CPUs (a FIFO pong spinning on the ping's CPU would starve it until the kernel's RT throttling
// steps in; the give-up time then ends the run with an error, not a hang).
#include <cstdint>
#include <memory>
#include <string>

#include "rt/latency_histogram.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/realtime_setup.hpp"

namespace flexloop::rt {

struct ShmPingPongOptions {
  std::int64_t round_trips = 200'000;  // recorded
  std::int64_t warm_up = 1'000;        // before, not recorded
  RealtimeOptions ping_realtime{.cpu = 0};
  RealtimeOptions pong_realtime{.cpu = 1};
  /// Either side gives up when the other has not moved for this long (a dead or starved peer).
  std::int64_t give_up_ns = 3 * kNsPerSecond;
};

struct ShmPingPongResult {
  std::unique_ptr<LatencyHistogram> round_trip;  // ns, one sample per recorded round trip
  std::int64_t round_trips = 0;                  // recorded
  std::string ping_setup;                        // set-up report of each side, one line per step
  std::string pong_setup;
};

/// Runs the baseline (forks once, waits for the child). std::invalid_argument for a count below
/// one; std::runtime_error when the mapping or the fork fails, or when the pong does not answer
/// within give_up_ns (the pong is then killed by its pid).
ShmPingPongResult run_shm_pingpong_baseline(const ShmPingPongOptions& options);

}  // namespace flexloop::rt
