#include "rt/message_validation.hpp"

#include <cmath>
#include <iterator>

#include "rt/enum_names.hpp"

namespace flexloop::rt {

namespace {

template <std::size_t N>
bool finite(const double (&v)[N]) noexcept {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

constexpr EnumName<DropReason> kDropReasonNames[] = {{DropReason::kDecodeFailure, "decode_failure"},
                                                     {DropReason::kNonFinite, "non_finite"},
                                                     {DropReason::kStale, "stale"},
                                                     {DropReason::kDuplicate, "duplicate"},
                                                     {DropReason::kOutOfOrder, "out_of_order"}};
static_assert(std::size(kDropReasonNames) == kDropReasonCount);

const char* to_string(DropReason reason) noexcept {
  return enum_name(kDropReasonNames, reason);
}

std::int64_t DropCounts::total() const noexcept {
  std::int64_t n = 0;
  for (auto c : counts_) n += c;
  return n;
}

bool all_finite(const flexloop_msgs::sensor_sample_t& m) noexcept {
  return finite(m.force_n) && finite(m.accel_mps2);
}

bool all_finite(const flexloop_msgs::actuator_command_t& m) noexcept {
  return finite(m.force_n);
}

bool all_finite(const flexloop_msgs::loop_stats_t& m) noexcept {
  return std::isfinite(m.rate_hz);
}

OrderKey order_key(const flexloop_msgs::sensor_sample_t& m) noexcept {
  return {m.plant_epoch, m.seq, m.t_ns};
}

OrderKey order_key(const flexloop_msgs::actuator_command_t& m) noexcept {
  return {m.plant_epoch, m.answers_seq, m.t_ns};
}

OrderKey order_key(const flexloop_msgs::loop_stats_t& m) noexcept {
  return {0, m.cycles, m.t_ns};
}

std::optional<DropReason> OrderGate::check(const OrderKey& key,
                                           std::int64_t now_ns) const noexcept {
  if (max_age_ns_ > 0 && now_ns - key.t_ns > max_age_ns_) return DropReason::kStale;
  if (policy_ == EpochPolicy::kFixed && key.epoch != epoch_) return DropReason::kStale;
  if (!have_newest_) return std::nullopt;
  if (key.epoch != newest_.epoch)  // kFollow: a restart, unless it is older than what we have
    return key.t_ns < newest_.t_ns ? std::optional(DropReason::kStale) : std::nullopt;
  if (key.seq == newest_.seq) return DropReason::kDuplicate;
  if (key.seq < newest_.seq) return DropReason::kOutOfOrder;
  if (key.t_ns < newest_.t_ns) return DropReason::kStale;
  return std::nullopt;
}

void OrderGate::accept(const OrderKey& key) noexcept {
  if (have_newest_ && key.epoch != newest_.epoch) ++resyncs_;
  if (policy_ == EpochPolicy::kFollow) epoch_ = key.epoch;
  newest_ = key;
  have_newest_ = true;
}

}  // namespace flexloop::rt
