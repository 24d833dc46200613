// SPDX-License-Identifier: BSD-3-Clause
#include "online/hil/baseline_json.hpp"

#include "online/loop/latency_json.hpp"

namespace flexloop::hil {

nlohmann::json timer_baseline_json(const rt::TimerBaselineResult& r) {
  return {{"wakeup_lateness_ns", loop::summary_json(*r.wakeup_lateness)},
          {"periods", r.periods},
          {"cycles", r.cycles},
          {"overruns", r.overruns},
          {"skipped_periods", r.skipped_periods},
          {"fifo", r.setup.fifo},
          {"too_short", r.cycles < kMinBaselineSamples}};
}

nlohmann::json pingpong_baseline_json(const rt::PingPongResult& r) {
  return {{"round_trip_ns", loop::summary_json(*r.round_trip)},
          {"wakeup_lateness_ns", loop::summary_json(*r.wakeup_lateness)},
          {"sent", r.sent},
          {"answered", r.answered},
          {"unanswered", r.unanswered},
          {"late_answers", r.late_answers},
          {"overruns", r.overruns},
          {"dropped", loop::drops_json(r.ping_drops)},
          {"ping_setup", r.ping_setup},
          {"pong_setup", r.pong_setup},
          {"pong_summary", r.pong_summary},
          {"too_short", r.sent < kMinBaselineSamples},
          {"min_samples", kMinBaselineSamples}};
}

nlohmann::json shm_pingpong_baseline_json(const rt::ShmPingPongResult& r) {
  return {{"round_trip_ns", loop::summary_json(*r.round_trip)},
          {"round_trips", r.round_trips},
          {"ping_setup", r.ping_setup},
          {"pong_setup", r.pong_setup},
          {"too_short", r.round_trips < kMinBaselineSamples},
          {"min_samples", kMinBaselineSamples}};
}

}  // namespace flexloop::hil
