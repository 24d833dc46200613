// SPDX-License-Identifier: BSD-3-Clause
#include "rt/deadline_schedule.hpp"

#include <stdexcept>

#include "rt/enum_names.hpp"

namespace flexloop::rt {

constexpr EnumName<OverrunPolicy> kOverrunPolicyNames[] = {{OverrunPolicy::kSkip, "skip"},
                                                           {OverrunPolicy::kReanchor, "reanchor"}};

OverrunPolicy parse_overrun_policy(const std::string& name) {
  return parse_enum(kOverrunPolicyNames, name, "overrun policy");
}

const char* to_string(OverrunPolicy policy) {
  return enum_name(kOverrunPolicyNames, policy);
}

DeadlineSchedule::DeadlineSchedule(std::int64_t period_ns, OverrunPolicy policy)
    : period_ns_(period_ns), policy_(policy) {
  if (period_ns <= 0)
    throw std::invalid_argument("period must be positive, got " + std::to_string(period_ns) +
                                " ns");
}

void DeadlineSchedule::anchor(std::int64_t first_deadline_ns) noexcept {
  next_deadline_ns_ = first_deadline_ns;
  next_index_ = 0;
  cycles_ = overruns_ = skipped_ = 0;
}

CycleStart DeadlineSchedule::begin_cycle(std::int64_t start_ns) noexcept {
  CycleStart c;
  c.start_ns = start_ns;
  c.lateness_ns = start_ns - next_deadline_ns_;
  c.overrun = c.lateness_ns >= period_ns_;
  c.index = next_index_;
  c.due_ns = next_deadline_ns_;
  if (c.overrun) {
    ++overruns_;
    if (policy_ == OverrunPolicy::kSkip) {
      c.skipped = c.lateness_ns / period_ns_;
      c.index += c.skipped;
      c.due_ns += c.skipped * period_ns_;
      skipped_ += c.skipped;
    } else {
      c.due_ns = start_ns;
    }
  }
  ++cycles_;
  next_index_ = c.index + 1;
  next_deadline_ns_ = c.due_ns + period_ns_;
  return c;
}

}  // namespace flexloop::rt
