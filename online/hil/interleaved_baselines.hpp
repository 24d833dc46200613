// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Baselines interleaved with the loop (doc/design.md §7): A1 B1 A2 B2 ... AK BK, where Ak is the
// bare timer and the bare LCM ping-pong (rt/timer_baseline.hpp, rt/pingpong_baseline.hpp) on the
// loop's CPUs with its rate, wait mode and priority, and Bk is segment k of the loop (the plant
// pauses between segments, LoopOptions::segments; hil stops the controller process meanwhile).
// This VM's phases change within a minute, so a baseline taken once before a long loop need not
// describe the machine the loop saw; each loop segment is compared with the baseline measured
// just before it, and the report gives each ratio with its spread over the segments.
// The ping-pong runs on the loop's transport: over LCM on the loop's URL with the port one higher,
// so that the paused loop's sockets do not queue its traffic; over iceoryx on the run's RouDi
// (services of their own), with the LCM ping-pong beside it for reference. The first segment also
// measures the shared-memory floor (rt/shm_pingpong_baseline.hpp), which no transport beats.
// Orchestration: allocates, throws std::runtime_error.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rt/periodic_clock.hpp"
#include "rt/pingpong_baseline.hpp"
#include "rt/roudi_process.hpp"
#include "rt/shm_pingpong_baseline.hpp"
#include "rt/timer_baseline.hpp"
#include "rt/transport_kind.hpp"

namespace flexloop::hil {

/// The loop's LCM URL with its port one higher ("udpm://239.255.76.67:7667?ttl=0" -> ...:7668;
/// no port: LCM's default 7667 -> 7668).
std::string neighbour_port_url(const std::string& url);

/// How each baseline segment runs: the loop's clock, receive path, URL and CPUs.
struct BaselineSettings {
  rt::PeriodicClockOptions clock;
  rt::ReceivePath receive_path = rt::ReceivePath::kDirect;
  rt::RealtimeOptions realtime;  ///< the timer's and the ping side's (the plant's CPU)
  int pong_cpu = 1;              ///< the controller's CPU
  std::string url;               ///< the ping-pong's LCM URL
  double segment_s = 1;          ///< each of timer and ping-pong runs this long per segment
  /// The loop's transport: the ping-pong on it is the one each loop segment is compared with.
  rt::TransportKind transport = rt::TransportKind::kLcm;
  rt::RoudiProcess* roudi = nullptr;  ///< iceoryx: the run's RouDi (this process never registers)
  std::int64_t floor_round_trips = 100'000;  ///< the shared-memory floor, once (0: not measured)
};

/// The margins the timing tests hold a loop segment to (doc/testing.md): misses within twice the
/// bare ping-pong's unanswered share + 1 % of the cycles, round-trip p99 within 1.5 x the
/// ping-pong's p99 + one timer p99 (the loop has a plant step, a controller step and a publish
/// more than the bare exchange).
struct BaselineMargins {
  double miss_share_factor = 2.0, miss_share_margin = 0.01;
  double round_trip_factor = 1.5;
};

/// One baseline segment's figures, as compared with the loop segment after it.
struct BaselineSegment {
  std::int64_t pings = 0, unanswered = 0, timer_cycles = 0;
  std::int64_t pingpong_p99_ns = 0, timer_p99_ns = 0;
};

/// Segment k of the baselines beside segment k of the loop (the plant's "segments", keys of
/// online/loop/plant_loop.hpp): {"segments": [{baseline, loop, round_trip_p99_ratio, miss_share,
/// unanswered_share, margin_use, within_margins}], "round_trip_p99_ratio",
/// "miss_share_minus_unanswered" and "margin_use": {median, min, max}, "segments_within_margins",
/// "median_segment_within_margins", "margins"}. margin_use is the larger of the two margins' uses
/// (1 = at the margin). Pairs only the segments both have.
nlohmann::json compare_segments(const std::vector<BaselineSegment>& baseline,
                                const nlohmann::json& loop_segments,
                                const BaselineMargins& margins = {});

class InterleavedBaselines {
 public:
  explicit InterleavedBaselines(BaselineSettings settings) : settings_(std::move(settings)) {}

  /// Measures the next baseline segment (timer, then ping-pong).
  void measure_segment();
  int segments() const { return static_cast<int>(segments_.size()); }

  /// All segments merged: {"timer", "pingpong" (on the loop's transport, which it names),
  /// "pingpong_lcm" (iceoryx runs: the LCM one beside it), "shm_floor", "segments"}, as
  /// baseline_json.hpp writes them.
  nlohmann::json totals_json() const;

  /// compare_segments() of the segments measured so far.
  nlohmann::json comparison_json(const nlohmann::json& loop_segments,
                                 const BaselineMargins& margins = {}) const {
    return compare_segments(segments_, loop_segments, margins);
  }

 private:
  rt::PingPongOptions pingpong_options(std::int64_t duration_ns) const;

  BaselineSettings settings_;
  std::vector<BaselineSegment> segments_;
  rt::TimerBaselineResult timer_;
  rt::PingPongResult pingpong_;
  rt::PingPongResult pingpong_lcm_;  // iceoryx runs: the LCM ping-pong beside
  std::optional<rt::ShmPingPongResult> floor_;
};

}  // namespace flexloop::hil
