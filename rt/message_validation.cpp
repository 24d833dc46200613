// SPDX-License-Identifier: BSD-3-Clause
#include "rt/message_validation.hpp"

#include <cmath>
#include <iterator>
#include <vector>

#include "rt/enum_names.hpp"

namespace flexloop::rt {

namespace {

bool finite(const std::vector<double>& v) noexcept {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// LCM encodes integers big-endian after the 8-byte fingerprint; the int16 count at `offset`.
bool count_at(const void* data, int size, int offset, int expected) noexcept {
  if (data == nullptr || size < offset + 2) return false;
  const auto* b = static_cast<const unsigned char*>(data) + offset;
  const int n = static_cast<std::int16_t>(static_cast<std::uint16_t>((b[0] << 8) | b[1]));
  return n >= 1 && n <= numeric::kMaxChannels && (expected == 0 || n == expected);
}

// Byte offsets of the counts: fingerprint, then the int64 fields before them
// (tests/msgs/test_message_codec.cpp checks them against the generated encoder).
constexpr int kSensorCountsOffset = 8 + 3 * 8;  // t_ns, seq, plant_epoch
constexpr int kCommandCountOffset = 8 + 5 * 8;  // t_ns, seq, answers_seq, plant_epoch, compute

}  // namespace

constexpr EnumName<DropReason> kDropReasonNames[] = {
    {DropReason::kDecodeFailure, "decode_failure"}, {DropReason::kChannelCount, "channel_count"},
    {DropReason::kNonFinite, "non_finite"},         {DropReason::kStale, "stale"},
    {DropReason::kDuplicate, "duplicate"},          {DropReason::kOutOfOrder, "out_of_order"}};
static_assert(std::size(kDropReasonNames) == kDropReasonCount);

const char* to_string(DropReason reason) noexcept {
  return enum_name(kDropReasonNames, reason);
}

std::int64_t DropCounts::total() const noexcept {
  std::int64_t n = 0;
  for (auto c : counts_) n += c;
  return n;
}

bool check_counts(const flexloop_msgs::sensor_sample_t*, const void* data, int size,
                  ChannelCounts expected) noexcept {
  return count_at(data, size, kSensorCountsOffset, expected.first) &&
         count_at(data, size, kSensorCountsOffset + 2, expected.second);
}

bool check_counts(const flexloop_msgs::actuator_command_t*, const void* data, int size,
                  ChannelCounts expected) noexcept {
  return count_at(data, size, kCommandCountOffset, expected.first);
}

bool check_counts(const flexloop_msgs::loop_stats_t*, const void*, int, ChannelCounts) noexcept {
  return true;
}

int max_encoded_size(const flexloop_msgs::sensor_sample_t*) {
  flexloop_msgs::sensor_sample_t m{};
  m.n_sensors = m.n_performance = numeric::kMaxChannels;
  m.sensors.assign(numeric::kMaxChannels, 0.0);
  m.performance.assign(numeric::kMaxChannels, 0.0);
  return m.getEncodedSize();
}

int max_encoded_size(const flexloop_msgs::actuator_command_t*) {
  flexloop_msgs::actuator_command_t m{};
  m.n_commands = numeric::kMaxChannels;
  m.commands.assign(numeric::kMaxChannels, 0.0);
  return m.getEncodedSize();
}

int max_encoded_size(const flexloop_msgs::loop_stats_t*) {
  return flexloop_msgs::loop_stats_t{}.getEncodedSize();
}

void reserve_channels(flexloop_msgs::sensor_sample_t& m) {
  m.sensors.reserve(numeric::kMaxChannels);
  m.performance.reserve(numeric::kMaxChannels);
}

void reserve_channels(flexloop_msgs::actuator_command_t& m) {
  m.commands.reserve(numeric::kMaxChannels);
}

bool all_finite(const flexloop_msgs::sensor_sample_t& m) noexcept {
  return finite(m.sensors) && finite(m.performance) && std::isfinite(m.applied_scale);
}

bool all_finite(const flexloop_msgs::actuator_command_t& m) noexcept {
  return finite(m.commands);
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
