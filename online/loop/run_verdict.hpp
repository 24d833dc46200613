// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The verdict of a real-time run, as Simulink Real-Time judges overloads: a limit on the share of
// cycles whose answer missed its deadline, and an overrun policy (go on, or stop the run at the
// Nth miss). How the run ended is part of it: a run cut short by SIGINT/SIGTERM is "interrupted"
// (its figures cover what ran), one stopped by the overrun policy or over the miss limit "fail".
// Set-up and reporting only (the loop itself only compares a count with limits.stop_after_misses).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexloop::loop {

struct RunLimits {
  double max_miss_share = 0.01;        ///< fail when misses / cycles is above this
  std::int64_t stop_after_misses = 0;  ///< 0: go on whatever misses; N: stop the run at the Nth
  bool judge_misses =
      true;  ///< false: a loop with no controller (it misses every answer by design)
};

/// Why the loop ended.
enum class RunEnd { kDuration, kInterrupted, kMissLimit, kDivergence };

/// "duration", "interrupted", "overrun policy", "divergence".
std::string to_string(RunEnd end);

struct RunVerdict {
  enum class Result { kPass, kFail, kInterrupted } result = Result::kPass;
  std::vector<std::string> reasons;  ///< each limit that was hit, in words
};

/// The verdict of a run of `cycles` with `misses` deadline misses that ended by `end`.
RunVerdict judge_run(RunEnd end, std::int64_t cycles, std::int64_t misses, const RunLimits& limits);

/// "pass", "fail", "interrupted".
std::string to_string(RunVerdict::Result result);

/// Adds a failure found outside the loop (a helper process that failed): the result becomes
/// "fail" unless the run was interrupted.
void add_failure(RunVerdict& v, const std::string& reason);

/// {"result": "pass"|"fail"|"interrupted", "reasons": [...], "ended": ..., "max_miss_share",
///  "stop_after_misses" (null: go on)}.
nlohmann::json verdict_json(const RunVerdict& v, RunEnd end, const RunLimits& limits);

/// The process exit code of a verdict: 0 pass, 3 fail, 130 interrupted (as a shell reports
/// SIGINT).
int exit_code(const RunVerdict& v);

/// Thrown by a loop command whose report was written but whose verdict is not a pass: carries the
/// exit code (main returns it) and the message printed as "error: ...".
struct VerdictFailure {
  int code;
  std::string message;
};

/// The verdict of verdict_json's text (its result and reasons).
RunVerdict verdict_from_json(const nlohmann::json& j);

/// The message for a verdict that is not a pass: "interrupted: ..." or "verdict fail: ...".
std::string verdict_message(const RunVerdict& v);

/// Throws VerdictFailure for a verdict that is not a pass (the report is written first).
void throw_unless_pass(const RunVerdict& v);

}  // namespace flexloop::loop
