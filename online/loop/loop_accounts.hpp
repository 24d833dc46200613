// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The plant loop's latency accounting (doc/design.md §7) and its once-a-second loop_stats_t.
//
// LoopAccounts: four fixed-bin histograms (rt/latency_histogram.hpp), allocated once at set-up.
// StatsPublisher::poll() is called once per cycle, in the cycle's slack (after the answer came):
// when a publication is due it summarises one histogram per call (a summary walks ~9000 bins,
// a few us) and publishes on the fifth call, so no single cycle pays for all four. The counts
// are taken at publication, and copied to a watcher's LoopStatus (online/loop/loop_status.hpp)
// when there is one. poll() is noexcept and allocation-free; publishing is one sendmsg (LCM) or one
// chunk (iceoryx).
#include <cstdint>
#include <flexloop_msgs/loop_stats_t.hpp>
#include <memory>

#include "online/loop/loop_status.hpp"
#include "rt/latency_histogram.hpp"
#include "rt/loop_transport.hpp"

namespace flexloop::loop {

struct LoopAccounts {
  std::unique_ptr<rt::LatencyHistogram> round_trip = std::make_unique<rt::LatencyHistogram>();
  std::unique_ptr<rt::LatencyHistogram> wakeup_lateness = std::make_unique<rt::LatencyHistogram>();
  std::unique_ptr<rt::LatencyHistogram> plant_compute = std::make_unique<rt::LatencyHistogram>();
  std::unique_ptr<rt::LatencyHistogram> controller_compute =
      std::make_unique<rt::LatencyHistogram>();
  /// The round trips of the current segment only (LoopOptions::segments).
  std::unique_ptr<rt::LatencyHistogram> segment_round_trip =
      std::make_unique<rt::LatencyHistogram>();
};

/// The counts of loop_stats_t at one instant.
struct LoopCounts {
  std::int64_t cycles = 0, deadline_misses = 0, overruns = 0, dropped_messages = 0,
               safe_command_cycles = 0;
};

class StatsPublisher {
 public:
  /// status: where a watching process reads the same figures (nullptr: nobody watches).
  StatsPublisher(rt::LoopTransport& transport, const std::string& channel, double rate_hz,
                 LoopStatus* status = nullptr, std::int64_t interval_ns = 1'000'000'000)
      : publisher_(transport, channel), status_(status), interval_ns_(interval_ns) {
    msg_.rate_hz = rate_hz;
  }

  /// Starts the first interval at now_ns.
  void start(std::int64_t now_ns) noexcept { next_ns_ = now_ns + interval_ns_; }

  /// One stage of a due publication (see the header comment).
  void poll(std::int64_t now_ns, const LoopAccounts& a, const LoopCounts& c) noexcept {
    if (now_ns < next_ns_) return;
    switch (stage_++) {
      case 0:
        copy(a.round_trip->summary(), msg_.round_trip_ns);
        return;
      case 1:
        copy(a.wakeup_lateness->summary(), msg_.wakeup_lateness_ns);
        return;
      case 2:
        copy(a.plant_compute->summary(), msg_.plant_compute_ns);
        return;
      case 3:
        copy(a.controller_compute->summary(), msg_.controller_compute_ns);
        return;
      default:
        break;
    }
    msg_.t_ns = now_ns;
    msg_.cycles = c.cycles;
    msg_.deadline_misses = c.deadline_misses;
    msg_.overruns = c.overruns;
    msg_.dropped_messages = c.dropped_messages;
    msg_.safe_command_cycles = c.safe_command_cycles;
    publisher_.publish(msg_);
    if (status_ != nullptr) {
      status_->cycles.store(c.cycles, std::memory_order_relaxed);
      status_->deadline_misses.store(c.deadline_misses, std::memory_order_relaxed);
      status_->safe_command_cycles.store(c.safe_command_cycles, std::memory_order_relaxed);
      status_->round_trip_p99_ns.store(msg_.round_trip_ns[2], std::memory_order_relaxed);
      status_->updates.fetch_add(1, std::memory_order_release);
    }
    stage_ = 0;
    next_ns_ += interval_ns_;
    if (next_ns_ <= now_ns) next_ns_ = now_ns + interval_ns_;
  }

  std::int64_t published() const noexcept { return publisher_.published(); }

 private:
  static void copy(const rt::LatencySummary& s, std::int64_t (&out)[5]) noexcept {
    out[0] = s.min;
    out[1] = s.p50;
    out[2] = s.p99;
    out[3] = s.p999;
    out[4] = s.max;
  }

  rt::LoopPublisher<flexloop_msgs::loop_stats_t> publisher_;
  LoopStatus* status_;
  flexloop_msgs::loop_stats_t msg_{};
  std::int64_t interval_ns_;
  std::int64_t next_ns_ = 0;
  int stage_ = 0;
};

}  // namespace flexloop::loop
