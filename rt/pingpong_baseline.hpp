// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Same-run baseline (b): the bare LCM round trip between two processes, with the loop's rate,
// CPUs, priorities, wait and receive modes but no plant or controller behind it. A loop's
// sensor -> actuator round trip is judged against it (doc/design.md §7).
//
// run_pingpong_baseline() forks. The child ("pong", pinned to pong_realtime.cpu) answers every
// ping (a sensor_sample_t) with an actuator_command_t whose answers_seq is the ping's seq. The
// parent ("ping", pinned to ping_realtime.cpu) runs a PeriodicClock; each cycle it publishes a
// ping stamped just before publishing and receives until the answer arrives or the next ping is
// due; round trip = answer handled - ping stamped (CLOCK_MONOTONIC, one clock for both).
// Receive modes (rt/lcm_transport.hpp) apply to both sides; with kHybrid the ping side polls
// from the moment it sent, the pong side sleeps until the spin margin (effective_spin_margin_ns:
// at most half the period) before the next ping
// is due (a spinning SCHED_FIFO pong would otherwise be throttled ~50 ms every second).
// Set-up per process: LCM first, then rt/realtime_setup.hpp's order; when SCHED_FIFO is granted
// LCM's receive thread gets the same CPU and one priority level above the process's loop, so a
// polling loop cannot starve it. The pong's set-up and counts come back over a pipe.
//
// It sends multicast, so it refuses (std::runtime_error, from require_private_loopback_namespace)
// outside the private loopback-only namespace: run the caller through tools/netns-run.
#include <cstdint>
#include <memory>
#include <string>

#include "rt/latency_histogram.hpp"
#include "rt/lcm_transport.hpp"
#include "rt/loopback_guard.hpp"
#include "rt/periodic_clock.hpp"
#include "rt/realtime_setup.hpp"

namespace flexloop::rt {

struct PingPongOptions {
  PeriodicClockOptions clock;                         // the ping side's period and wait mode
  ReceiveMode receive_mode = ReceiveMode::kBlocking;  // both sides
  ReceivePath receive_path = ReceivePath::kDirect;    // both sides
  std::int64_t duration_ns = kNsPerSecond;
  RealtimeOptions ping_realtime{.cpu = 0};
  RealtimeOptions pong_realtime{.cpu = 1};
  std::string url = kPrivateLoopbackLcmUrl;
  std::string channel_prefix = "FLEXLOOP_BASELINE";  // _PING, _PONG, _STOP
  /// Give up when the pong has not answered a first ping within this time.
  std::int64_t connect_timeout_ns = 3 * kNsPerSecond;
};

struct PingPongResult {
  std::unique_ptr<LatencyHistogram> round_trip;       // ns, one sample per answered ping
  std::unique_ptr<LatencyHistogram> wakeup_lateness;  // ns, the ping side's clock
  std::int64_t sent = 0;                              // pings sent in the measured period
  std::int64_t answered = 0;                          // answered before the next ping was due
  std::int64_t unanswered = 0;                        // sent - answered
  std::int64_t late_answers = 0;  // answers that came after their ping's period ended
  std::int64_t overruns = 0;      // ping cycles that started a whole period late
  DropCounts ping_drops;          // answers rejected by the ping side
  std::string ping_setup;         // set-up report of each side, one line per step
  std::string pong_setup;
  std::string pong_summary;  // the pong's own counts
};

/// Runs the baseline (forks once, waits for the child). std::runtime_error when not in the
/// private namespace, when LCM cannot be opened, or when the pong never answers.
PingPongResult run_pingpong_baseline(const PingPongOptions& options);

/// Adds a later run's pings, counts and histograms to `total` (a baseline measured in segments);
/// the set-up texts stay the first run's.
void merge_into(PingPongResult& total, const PingPongResult& part);

}  // namespace flexloop::rt
