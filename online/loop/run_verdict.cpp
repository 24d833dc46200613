// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/run_verdict.hpp"

#include <cstdio>

namespace flexloop::loop {

std::string to_string(RunEnd end) {
  switch (end) {
    case RunEnd::kDuration:
      return "duration";
    case RunEnd::kInterrupted:
      return "interrupted";
    case RunEnd::kMissLimit:
      return "overrun policy";
    case RunEnd::kDivergence:
      return "divergence";
  }
  return "unknown";
}

RunVerdict judge_run(RunEnd end, std::int64_t cycles, std::int64_t misses,
                     const RunLimits& limits) {
  RunVerdict v;
  char text[200];
  if (end == RunEnd::kMissLimit) {
    std::snprintf(text, sizeof text,
                  "overrun policy: stopped at the %lld-th deadline miss, after %lld cycles",
                  static_cast<long long>(limits.stop_after_misses), static_cast<long long>(cycles));
    v.reasons.emplace_back(text);
  }
  const double share = cycles > 0 ? static_cast<double>(misses) / static_cast<double>(cycles) : 0;
  if (limits.judge_misses && share > limits.max_miss_share) {
    std::snprintf(text, sizeof text,
                  "deadline misses %.3g %% of %lld cycles (%lld), above the limit of %.3g %%",
                  100 * share, static_cast<long long>(cycles), static_cast<long long>(misses),
                  100 * limits.max_miss_share);
    v.reasons.emplace_back(text);
  }
  if (end == RunEnd::kDivergence) v.reasons.emplace_back("the plant diverged");
  if (end == RunEnd::kInterrupted)
    v.result = RunVerdict::Result::kInterrupted;
  else if (!v.reasons.empty())
    v.result = RunVerdict::Result::kFail;
  return v;
}

std::string to_string(RunVerdict::Result result) {
  switch (result) {
    case RunVerdict::Result::kPass:
      return "pass";
    case RunVerdict::Result::kFail:
      return "fail";
    case RunVerdict::Result::kInterrupted:
      return "interrupted";
  }
  return "fail";
}

void add_failure(RunVerdict& v, const std::string& reason) {
  v.reasons.push_back(reason);
  if (v.result == RunVerdict::Result::kPass) v.result = RunVerdict::Result::kFail;
}

RunVerdict verdict_from_json(const nlohmann::json& j) {
  RunVerdict v;
  const std::string result = j.value("result", "fail");
  v.result = result == "pass"          ? RunVerdict::Result::kPass
             : result == "interrupted" ? RunVerdict::Result::kInterrupted
                                       : RunVerdict::Result::kFail;
  if (j.contains("reasons")) v.reasons = j["reasons"].get<std::vector<std::string>>();
  return v;
}

nlohmann::json verdict_json(const RunVerdict& v, RunEnd end, const RunLimits& limits) {
  return {
      {"result", to_string(v.result)},
      {"reasons", v.reasons},
      {"ended", to_string(end)},
      {"max_miss_share", limits.judge_misses ? nlohmann::json(limits.max_miss_share)
                                             : nlohmann::json("not judged (no controller)")},
      {"stop_after_misses", limits.stop_after_misses > 0 ? nlohmann::json(limits.stop_after_misses)
                                                         : nlohmann::json(nullptr)}};
}

int exit_code(const RunVerdict& v) {
  switch (v.result) {
    case RunVerdict::Result::kPass:
      return 0;
    case RunVerdict::Result::kFail:
      return 3;
    case RunVerdict::Result::kInterrupted:
      return 130;
  }
  return 1;
}

std::string verdict_message(const RunVerdict& v) {
  std::string m = v.result == RunVerdict::Result::kInterrupted
                      ? "interrupted (SIGINT/SIGTERM): the figures cover the part that ran"
                      : "verdict fail";
  for (const auto& r : v.reasons) m += "; " + r;
  return m;
}

}  // namespace flexloop::loop

namespace flexloop::loop {

void throw_unless_pass(const RunVerdict& v) {
  if (v.result != RunVerdict::Result::kPass) throw VerdictFailure{exit_code(v), verdict_message(v)};
}

}  // namespace flexloop::loop
