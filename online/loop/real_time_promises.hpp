// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Which of flexloop's real-time promises a controller kept while the controller process watched
// it, for its report and hil's. The promises of a step (controller/runtime/loop_controller.hpp):
//
//   no allocation      counted around each answer (rt/thread_allocations.hpp); unknown where
//                      the program does not count (a sanitizer build)
//   step time          the answer's compute time, p99 within kStepBudgetShare of the period (the
//                      rest of the period is the plant's step, the transport both ways and the
//                      wake-up); the maximum is shown, not judged (this VM's timer has rare
//                      millisecond tails)
//   no failed call     a controller FMU's calls all returned fmi2OK or fmi2Warning
//   no lock, no system call   not watched (it would take a tracer in the loop): said so
//
// flexloop's own controllers keep them by construction (tests/alloc checks the allocations); a
// controller FMU is foreign code: watched here, not trusted.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "rt/latency_histogram.hpp"

namespace flexloop::loop {

/// The controller's share of a period that its p99 answer time may take.
inline constexpr double kStepBudgetShare = 0.1;

struct AnswerWatch {
  bool allocations_counted = false;
  std::int64_t allocations = 0;         ///< made while answering, in all answers
  std::int64_t answers_allocating = 0;  ///< answers that allocated at least once
  std::int64_t answered = 0;
  rt::LatencySummary compute;  ///< the answers' compute time, ns
  std::int64_t period_ns = 0;
  std::string controller_failure;  ///< empty: no failed call
};

/// {"no_allocation": {...}, "step_time": {...}, "no_failed_call": {...},
///  "no_lock_or_system_call": {...}, "summary": real_time_promises_text}, each promise with
///  "kept": true, false or null (not watched).
nlohmann::json real_time_promises_json(const AnswerWatch& w);

/// One line: "real-time promises: no allocation kept (0 in 30000 answers), step time kept
/// (p99 0.4 us = 0.4 % of the period), no failed call kept; locks and system calls not watched".
std::string real_time_promises_text(const nlohmann::json& promises);

}  // namespace flexloop::loop
