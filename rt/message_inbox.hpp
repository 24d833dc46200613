// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The receiving end of one channel: decodes each received buffer into a preallocated message,
// validates it (rt/message_validation.hpp) and keeps the newest accepted one -- "the real-time
// side never blocks: it takes the newest good value" (realtime_tools). Rejected messages are
// counted per DropReason and never become newest(). Messages accepted but replaced by a newer
// one before take() are counted as superseded (a burst, or a reader slower than the writer).
//
// offer() is what the LCM subscription calls (rt/lcm_transport.hpp), and what tests call with
// hand-made buffers. Everything after construction is noexcept and allocation-free: the channel
// counts are checked in the buffer before the generated decode sizes its vectors from them, and
// the vectors have room for numeric::kMaxChannels from the start; not thread-safe: one thread
// offers and takes.
#include <cstdint>
#include <optional>
#include <vector>

#include "rt/message_validation.hpp"

namespace flexloop::rt {

template <class Msg>
class MessageInbox {
 public:
  /// counts: what every accepted message must carry (message_validation.hpp; 0: any).
  explicit MessageInbox(OrderGate gate = OrderGate{}, ChannelCounts counts = {})
      : gate_(gate), counts_(counts), min_size_(Msg{}.getEncodedSize()) {
    reserve_channels(scratch_);
    reserve_channels(newest_);
    (void)Msg::getHash();  // the generated code computes it once, on the first call
  }

  /// Decodes `size` bytes received at `received_ns` (CLOCK_MONOTONIC); keeps the message as
  /// newest when it is valid. Returns the drop reason, or nullopt when accepted.
  std::optional<DropReason> offer(const void* data, int size, std::int64_t received_ns) noexcept {
    // A short (shorter than a message with no channels), foreign (fingerprint) or over-long
    // buffer is a decode failure. The type and length, then the counts (message_validation.hpp),
    // then the decode.
    if (!has_fingerprint<Msg>(data, size) || size < min_size_)
      return drop(DropReason::kDecodeFailure);
    if (!check_counts(&scratch_, data, size, counts_)) return drop(DropReason::kChannelCount);
    if (scratch_.decode(data, 0, size) != size) return drop(DropReason::kDecodeFailure);
    if (!all_finite(scratch_)) return drop(DropReason::kNonFinite);
    const OrderKey key = order_key(scratch_);
    if (const auto why = gate_.check(key, received_ns)) return drop(*why);
    gate_.accept(key);
    if (fresh_) ++superseded_;
    newest_ = scratch_;
    newest_received_ns_ = received_ns;
    fresh_ = true;
    ++accepted_;
    return std::nullopt;
  }

  /// True when a message was accepted since the last take().
  bool has_fresh() const noexcept { return fresh_; }
  /// The newest accepted message not taken yet (and marks it taken), or nullptr.
  const Msg* take() noexcept {
    if (!fresh_) return nullptr;
    fresh_ = false;
    return &newest_;
  }
  /// The newest accepted message, taken or not; meaningful when accepted() > 0.
  const Msg& newest() const noexcept { return newest_; }
  /// When newest() was received (CLOCK_MONOTONIC ns).
  std::int64_t newest_received_ns() const noexcept { return newest_received_ns_; }

  std::int64_t accepted() const noexcept { return accepted_; }
  std::int64_t superseded() const noexcept { return superseded_; }
  const DropCounts& drops() const noexcept { return drops_; }
  OrderGate& gate() noexcept { return gate_; }
  const OrderGate& gate() const noexcept { return gate_; }

 private:
  std::optional<DropReason> drop(DropReason why) noexcept {
    drops_.add(why);
    return why;
  }

  OrderGate gate_;
  ChannelCounts counts_;
  int min_size_;  // the encoded size of a message with no channels
  Msg scratch_{};
  Msg newest_{};
  std::int64_t newest_received_ns_ = 0;
  bool fresh_ = false;
  std::int64_t accepted_ = 0;
  std::int64_t superseded_ = 0;
  DropCounts drops_;
};

/// Encodes `m` into `buffer` and offers it to `inbox` as received at received_ns, as the LCM
/// subscription would hand it over: for a run replayed without sockets
/// (online/hil/run_replay.hpp) and for tests. Not for the loop: the buffer grows (allocates)
/// when the message needs it.
template <class Msg>
std::optional<DropReason> offer_encoded(MessageInbox<Msg>& inbox, const Msg& m,
                                        std::int64_t received_ns,
                                        std::vector<std::uint8_t>& buffer) {
  buffer.resize(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
  return inbox.offer(buffer.data(), static_cast<int>(buffer.size()), received_ns);
}

}  // namespace flexloop::rt
