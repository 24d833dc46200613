// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Which received messages may be applied (doc/design.md §7, §9): a message that fails to decode,
// carries other channel counts than the loop's, carries NaN or Inf in any floating-point field,
// is stale, or repeats or reorders the sequence, is dropped and counted per reason, never
// applied. Every function here is noexcept and allocation-free, for use inside the loop.
//
// Channel counts are read from the buffer before it is decoded (check_counts): the generated
// decode would size its vectors from them, so a count outside 1 .. numeric::kMaxChannels (or other
// than the loop's) never reaches it, and vectors reserved for numeric::kMaxChannels
// (reserve_channels) are never reallocated.
//
// Ordering uses an OrderKey (epoch, seq, t_ns) per message type:
//   sensor_sample_t     (plant_epoch, seq, t_ns)
//   actuator_command_t  (plant_epoch, answers_seq, t_ns) -- ordered by the sample it answers, so
//                       a restarted controller (whose own seq starts again) is accepted at once
//   loop_stats_t        (0, cycles, t_ns)
// OrderGate decides, against the newest key it accepted, in this order:
//   older than max_age_ns before "now" (only when max_age_ns > 0)                      kStale
//   other epoch   kFollow (a receiver of plant samples): a plant restart -- accepted and tracked
//                 from there (a resync) when its t_ns is not older than the newest seen, else
//                 kStale (a straggler of the old epoch). kFixed (the plant receiving commands):
//                 an answer to another plant run -- kStale.
//   seq == newest kDuplicate;   seq < newest  kOutOfOrder
//   t_ns < newest t_ns (seq went forward, time backward: older than the newest seen)    kStale
#include <array>
#include <cstdint>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/loop_stats_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <optional>

#include "numeric/channel_limits.hpp"

namespace flexloop::rt {

enum class DropReason {
  kDecodeFailure,
  kChannelCount,
  kNonFinite,
  kStale,
  kDuplicate,
  kOutOfOrder
};
inline constexpr int kDropReasonCount = 6;

/// "decode_failure", "channel_count", "non_finite", "stale", "duplicate", "out_of_order" (JSON
/// keys).
const char* to_string(DropReason reason) noexcept;

/// Dropped-message counts per reason.
class DropCounts {
 public:
  void add(DropReason r) noexcept { ++counts_[static_cast<std::size_t>(r)]; }
  std::int64_t operator[](DropReason r) const noexcept {
    return counts_[static_cast<std::size_t>(r)];
  }
  std::int64_t total() const noexcept;
  void reset() noexcept { counts_.fill(0); }
  void merge(const DropCounts& other) noexcept {
    for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
  }

 private:
  std::array<std::int64_t, kDropReasonCount> counts_{};
};

/// The channel counts a receiver expects: sensor_sample_t (sensors, performance),
/// actuator_command_t (commands, unused); 0 takes any count 1 .. numeric::kMaxChannels.
struct ChannelCounts {
  int first = 0, second = 0;
};

/// True when the counts in an encoded buffer (read without decoding it) are the expected ones;
/// false for a buffer too short to hold them.
bool check_counts(const flexloop_msgs::sensor_sample_t*, const void* data, int size,
                  ChannelCounts expected) noexcept;
bool check_counts(const flexloop_msgs::actuator_command_t*, const void* data, int size,
                  ChannelCounts expected) noexcept;
bool check_counts(const flexloop_msgs::loop_stats_t*, const void* data, int size,
                  ChannelCounts expected) noexcept;

/// True when `data` starts with Msg's 8-byte fingerprint (LCM's type check, read without decoding).
template <class Msg>
bool has_fingerprint(const void* data, int size) noexcept {
  if (data == nullptr || size < 8) return false;
  const auto* b = static_cast<const unsigned char*>(data);
  std::uint64_t h = 0;
  for (int i = 0; i < 8; ++i) h = (h << 8) | b[i];
  return static_cast<std::int64_t>(h) == Msg::getHash();
}

/// The encoded size of the largest message of this type (numeric::kMaxChannels in every channel
/// vector): what a publisher's buffer must hold.
int max_encoded_size(const flexloop_msgs::sensor_sample_t*);
int max_encoded_size(const flexloop_msgs::actuator_command_t*);
int max_encoded_size(const flexloop_msgs::loop_stats_t*);
template <class Msg>
int max_encoded_size() {
  return max_encoded_size(static_cast<const Msg*>(nullptr));
}

/// Start-up: room for numeric::kMaxChannels in every channel vector, so that decoding and copying
/// never allocate.
void reserve_channels(flexloop_msgs::sensor_sample_t& m);
void reserve_channels(flexloop_msgs::actuator_command_t& m);
inline void reserve_channels(flexloop_msgs::loop_stats_t&) {}

/// True when every floating-point field is finite.
bool all_finite(const flexloop_msgs::sensor_sample_t& m) noexcept;
bool all_finite(const flexloop_msgs::actuator_command_t& m) noexcept;
bool all_finite(const flexloop_msgs::loop_stats_t& m) noexcept;

struct OrderKey {
  std::int64_t epoch = 0;
  std::int64_t seq = 0;
  std::int64_t t_ns = 0;
};

OrderKey order_key(const flexloop_msgs::sensor_sample_t& m) noexcept;
OrderKey order_key(const flexloop_msgs::actuator_command_t& m) noexcept;
OrderKey order_key(const flexloop_msgs::loop_stats_t& m) noexcept;

enum class EpochPolicy { kFollow, kFixed };

class OrderGate {
 public:
  /// kFixed accepts only `epoch`; kFollow starts with whatever epoch arrives first.
  /// max_age_ns > 0 also drops messages older than that before the `now_ns` given to check().
  explicit OrderGate(EpochPolicy policy = EpochPolicy::kFollow, std::int64_t epoch = 0,
                     std::int64_t max_age_ns = 0) noexcept
      : policy_(policy), epoch_(epoch), max_age_ns_(max_age_ns) {}

  /// Why `key` must be dropped, or nullopt when it may be applied. Changes nothing.
  std::optional<DropReason> check(const OrderKey& key, std::int64_t now_ns) const noexcept;
  /// Records `key` (which check() passed) as the newest.
  void accept(const OrderKey& key) noexcept;

  /// Forgets the newest key (the next message in the epoch is accepted whatever its seq).
  void reset() noexcept { have_newest_ = false; }
  /// kFixed: the epoch to accept from now on (e.g. the plant's own, after a restart); resets.
  void set_epoch(std::int64_t epoch) noexcept {
    epoch_ = epoch;
    reset();
  }

  bool has_newest() const noexcept { return have_newest_; }
  const OrderKey& newest() const noexcept { return newest_; }
  std::int64_t epoch() const noexcept { return epoch_; }
  /// Epoch changes followed (kFollow): plant restarts seen.
  std::int64_t resyncs() const noexcept { return resyncs_; }

 private:
  EpochPolicy policy_;
  std::int64_t epoch_;
  std::int64_t max_age_ns_;
  bool have_newest_ = false;
  OrderKey newest_;
  std::int64_t resyncs_ = 0;
};

}  // namespace flexloop::rt
