// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The same-run baselines' figures as JSON (rt/timer_baseline.hpp, rt/pingpong_baseline.hpp), as
// `flexloop baseline` writes them and the hil report embeds them under "baseline". Reporting only.
#include <nlohmann/json.hpp>

#include "rt/pingpong_baseline.hpp"
#include "rt/shm_pingpong_baseline.hpp"
#include "rt/timer_baseline.hpp"

namespace flexloop::hil {

/// A baseline of fewer samples (timer cycles, pings sent) than this is flagged "too_short": its
/// p99.9 rests on a single sample and its unanswered share moves by 0.1 % per ping, so a loop
/// compared with it is compared with noise.
inline constexpr long kMinBaselineSamples = 1000;

/// wakeup_lateness_ns {min..max, count}, periods, cycles, overruns, skipped_periods, fifo,
/// too_short.
nlohmann::json timer_baseline_json(const rt::TimerBaselineResult& r);
/// round_trip_ns, wakeup_lateness_ns, sent, answered, unanswered, late_answers, overruns,
/// dropped {reason: n}, ping_setup, pong_setup, pong_summary, too_short, min_samples.
nlohmann::json pingpong_baseline_json(const rt::PingPongResult& r);
/// round_trip_ns, round_trips, ping_setup, pong_setup, too_short, min_samples.
nlohmann::json shm_pingpong_baseline_json(const rt::ShmPingPongResult& r);

}  // namespace flexloop::hil
