// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The iceoryx carrier (issue 48): the same encoded messages as over LCM (msgs/), the same
// MessageInbox (rt/message_inbox.hpp: counts checked before decoding, stale, duplicate and
// out-of-order dropped), only the carrier changes -- a same-host shared-memory channel of Eclipse
// iceoryx 2.0 instead of a UDP multicast datagram. A channel is the iceoryx service
// {"flexloop", <LCM channel name>, "lcm"}; a chunk holds exactly one LCM-encoded message.
//
//   - IceoryxPublisher<Msg> loans a chunk of the message's encoded size from RouDi's mempool,
//     encodes into it (no copy after that) and publishes it; no allocation, no system call.
//   - IceoryxTransport::subscribe() makes an untyped subscriber per channel; handle_pending()
//     takes every chunk that is ready, offers its bytes to the inbox and releases it.
//     handle_until() waits as LcmTransport's does (rt/receive_wait.hpp): kPolling spins on
//     hasData, kBlocking sleeps in an iceoryx WaitSet (a futex-backed condition shared with the
//     publisher), kHybrid sleeps there until the spin time, then spins.
//
// The process registers with RouDi (rt/roudi_process.hpp) in the constructor: one
// IceoryxTransport per process, after fork, never in the process that owns RouDi (RouDi
// terminates every process still registered when it stops). Set-up may allocate and throws
// std::runtime_error; publish, handle_pending, poll_ready and handle_until are noexcept and
// allocation-free.
#include <cstdint>
#include <iceoryx_posh/popo/untyped_publisher.hpp>
#include <iceoryx_posh/popo/untyped_subscriber.hpp>
#include <iceoryx_posh/popo/wait_set.hpp>
#include <memory>
#include <string>
#include <vector>

#include "rt/event_log_recorder.hpp"
#include "rt/message_inbox.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/receive_wait.hpp"

namespace flexloop::rt {

/// The iceoryx service of an LCM channel name (at most 100 characters).
iox::capro::ServiceDescription iceoryx_service(const std::string& channel);

class IceoryxTransport {
 public:
  /// Registers this process with the running RouDi as `runtime_name` (unique on the host; made
  /// unique with the pid). RoudiError (rt/roudi_process.hpp) when no RouDi runs.
  explicit IceoryxTransport(const std::string& runtime_name);
  /// The name this process registered with: runtime_name + "_" + pid.
  static std::string registered_name(const std::string& runtime_name);
  /// The files iceoryx's runtime of that name keeps while registered (its socket and lock in
  /// /tmp), which it removes when it deregisters -- and which stay when the process is killed.
  static std::vector<std::string> runtime_files(const std::string& registered_name);
  ~IceoryxTransport();
  IceoryxTransport(const IceoryxTransport&) = delete;
  IceoryxTransport& operator=(const IceoryxTransport&) = delete;

  void record_to(EventLogRecorder* recorder) noexcept { recorder_ = recorder; }
  EventLogRecorder* recorder() const noexcept { return recorder_; }

  /// Delivers every message on `channel` to `inbox` (which must outlive the transport).
  /// queue_capacity: chunks kept for this subscriber before the oldest is dropped.
  template <class Msg>
  void subscribe(const std::string& channel, MessageInbox<Msg>& inbox, int queue_capacity = 30) {
    subscribe_bytes(channel, &IceoryxTransport::deliver<Msg>, &inbox, queue_capacity);
  }

  /// True when every subscription is connected to a publisher (RouDi's discovery connects them
  /// some ms after both exist).
  bool subscriptions_connected() const noexcept;

  /// 1 when a chunk is ready, 0 when none came within timeout_ns (0: just look).
  int poll_ready(std::int64_t timeout_ns) noexcept;
  /// Handles every chunk ready now; returns how many. A subscriber with nothing queued is only
  /// looked at (hasData reads the queue; take() on an empty queue writes its shared lines too,
  /// which a spinning receiver would pull away from the publisher's core on every turn).
  int handle_pending() noexcept;

  template <class Done>
  int handle_until(std::int64_t deadline_ns, ReceiveMode mode, Done&& done,
                   std::int64_t spin_from_ns = 0) noexcept {
    return handle_until_deadline(*this, deadline_ns, mode, done, spin_from_ns);
  }

 private:
  using Deliver = void (*)(void* inbox, const void* data, int size, std::int64_t now);
  struct Subscription {
    std::unique_ptr<iox::popo::UntypedSubscriber> subscriber;
    Deliver deliver;
    void* inbox;
    int recorder_channel;
  };
  template <class Msg>
  static void deliver(void* inbox, const void* data, int size, std::int64_t now) {
    static_cast<MessageInbox<Msg>*>(inbox)->offer(data, size, now);
  }
  void subscribe_bytes(const std::string& channel, Deliver deliver, void* inbox,
                       int queue_capacity);

  EventLogRecorder* recorder_ = nullptr;
  std::vector<Subscription> subscriptions_;
  std::unique_ptr<iox::popo::WaitSet<>> waitset_;
};

/// Publishes one message type on one channel through loaned chunks.
template <class Msg>
class IceoryxPublisher {
 public:
  IceoryxPublisher(IceoryxTransport& transport, const std::string& channel)
      : publisher_(iceoryx_service(channel), publisher_options()),
        recorder_(transport.recorder()),
        recorder_channel_(recorder_ ? recorder_->channel(channel) : -1) {}

  /// Loans a chunk, encodes into it and publishes; false (and counted) when no chunk could be
  /// loaned or the encoding failed.
  bool publish(const Msg& msg) noexcept {
    const int size = msg.getEncodedSize();
    void* chunk = nullptr;
    if (size > 0)
      publisher_.loan(static_cast<std::uint32_t>(size), alignof(std::max_align_t))
          .and_then([&](void* p) { chunk = p; });
    if (!chunk) return fail();
    if (msg.encode(chunk, 0, size) != size) {
      publisher_.release(chunk);
      return fail();
    }
    if (recorder_) recorder_->record(recorder_channel_, chunk, size, monotonic_now_ns());
    publisher_.publish(chunk);
    ++published_;
    return true;
  }

  /// True once a subscriber is connected (discovery runs in RouDi, some ms after both exist).
  bool has_subscribers() const noexcept { return publisher_.hasSubscribers(); }
  std::int64_t published() const noexcept { return published_; }
  std::int64_t failures() const noexcept { return failures_; }

 private:
  static iox::popo::PublisherOptions publisher_options() {
    iox::popo::PublisherOptions o;
    o.historyCapacity = 0;  // as LCM: a subscriber sees what is sent after it connected
    return o;
  }
  bool fail() noexcept {
    ++failures_;
    return false;
  }

  iox::popo::UntypedPublisher publisher_;
  EventLogRecorder* recorder_;
  int recorder_channel_;
  std::int64_t published_ = 0;
  std::int64_t failures_ = 0;
};

}  // namespace flexloop::rt
