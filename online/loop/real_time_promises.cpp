// SPDX-License-Identifier: BSD-3-Clause
#include "online/loop/real_time_promises.hpp"

#include <cstdio>

namespace flexloop::loop {

namespace {

std::string verdict(const nlohmann::json& kept) {
  return kept.is_boolean() ? (kept.get<bool>() ? "kept" : "BROKEN") : "not counted";
}

}  // namespace

std::string real_time_promises_text(const nlohmann::json& p) {
  const auto& a = p.at("no_allocation");
  const auto& s = p.at("step_time");
  const auto& f = p.at("no_failed_call");
  char text[400];
  std::snprintf(
      text, sizeof text,
      "real-time promises: no allocation %s (%lld allocations in %lld of %lld answers), step "
      "time %s (p99 %.2f us = %.2f %% of the period, budget %.0f %%; max %.2f us), no failed "
      "call %s; locks and system calls not watched",
      verdict(a.at("kept")).c_str(), a.value("allocations", 0LL),
      a.value("answers_allocating", 0LL), a.value("answered", 0LL), verdict(s.at("kept")).c_str(),
      s.value("p99_ns", 0.0) / 1e3, 100 * s.value("p99_share_of_period", 0.0),
      100 * s.value("budget_share", 0.0), s.value("max_ns", 0.0) / 1e3,
      verdict(f.at("kept")).c_str());
  return text;
}

nlohmann::json real_time_promises_json(const AnswerWatch& w) {
  const double p99_share =
      w.period_ns > 0 ? static_cast<double>(w.compute.p99) / static_cast<double>(w.period_ns) : 0.0;
  nlohmann::json p = {
      {"no_allocation",
       {{"kept", w.allocations_counted ? nlohmann::json(w.allocations == 0) : nlohmann::json()},
        {"counted", w.allocations_counted},
        {"allocations", w.allocations},
        {"answers_allocating", w.answers_allocating},
        {"answered", w.answered}}},
      {"step_time",
       {{"kept", w.answered == 0 || p99_share <= kStepBudgetShare},
        {"p99_ns", w.compute.p99},
        {"max_ns", w.compute.max},
        {"period_ns", w.period_ns},
        {"p99_share_of_period", p99_share},
        {"budget_share", kStepBudgetShare}}},
      {"no_failed_call",
       {{"kept", w.controller_failure.empty()},
        {"failure",
         w.controller_failure.empty() ? nlohmann::json() : nlohmann::json(w.controller_failure)}}},
      {"no_lock_or_system_call", {{"kept", nullptr}, {"watched", false}}}};
  p["summary"] = real_time_promises_text(p);
  return p;
}

}  // namespace flexloop::loop
