#pragma once
// The same-run baselines' figures as JSON (rt/timer_baseline.hpp, rt/pingpong_baseline.hpp), as
// `flexloop baseline` writes them and the hil report embeds them under "baseline". Reporting only.
#include <nlohmann/json.hpp>

#include "rt/pingpong_baseline.hpp"
#include "rt/timer_baseline.hpp"

namespace flexloop::hil {

/// wakeup_lateness_ns {min..max, count}, periods, cycles, overruns, skipped_periods, fifo.
nlohmann::json timer_baseline_json(const rt::TimerBaselineResult& r);
/// round_trip_ns, wakeup_lateness_ns, sent, answered, unanswered, late_answers, overruns,
/// dropped {reason: n}, ping_setup, pong_setup, pong_summary.
nlohmann::json pingpong_baseline_json(const rt::PingPongResult& r);

}  // namespace flexloop::hil
