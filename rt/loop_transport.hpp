// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A loop's carrier, chosen at start-up (rt/transport_kind.hpp): LCM (rt/lcm_transport.hpp) or
// iceoryx (rt/iceoryx_transport.hpp). The plant and controller processes and the stations are
// written once against this class: the same encoded messages, the same MessageInbox validation,
// the same wait loop (rt/receive_wait.hpp); only the carrier differs. Dispatch is one predictable
// branch per call (no virtual call, no allocation); set-up may allocate and throws
// std::runtime_error / std::invalid_argument as the carriers do.
//
// With iceoryx, a RouDi must run (rt/roudi_process.hpp; `flexloop roudi` or `flexloop hil
// --transport iceoryx` start one), and the process registers with it in the constructor: one
// LoopTransport per process, never in the process that owns RouDi. Publishers and subscribers are
// connected by RouDi's discovery some ms after both exist: peers_connected() says when.
#include <unistd.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "rt/iceoryx_transport.hpp"
#include "rt/lcm_transport.hpp"
#include "rt/loop_process_setup.hpp"
#include "rt/roudi_process.hpp"
#include "rt/transport_kind.hpp"

namespace flexloop::rt {

struct LoopTransportOptions {
  TransportKind kind = TransportKind::kLcm;
  std::string url;                                  ///< LCM: the URL
  ReceivePath receive_path = ReceivePath::kDirect;  ///< LCM: who reads the socket
  std::string runtime_name = "flexloop";            ///< iceoryx: registered as <name>_<pid>
};

class LoopTransport {
 public:
  explicit LoopTransport(const LoopTransportOptions& options);

  TransportKind kind() const noexcept {
    return lcm_ ? TransportKind::kLcm : TransportKind::kIceoryx;
  }
  /// "LCM <url>" or "iceoryx (shared memory)": what the start-up banner says.
  std::string describe() const;

  void record_to(EventLogRecorder* recorder) noexcept {
    if (lcm_)
      lcm_->record_to(recorder);
    else
      iceoryx_->record_to(recorder);
  }
  EventLogRecorder* recorder() const noexcept {
    return lcm_ ? lcm_->recorder() : iceoryx_->recorder();
  }

  template <class Msg>
  void subscribe(const std::string& channel, MessageInbox<Msg>& inbox, int queue_capacity = 30) {
    if (lcm_)
      lcm_->subscribe(channel, inbox, queue_capacity);
    else
      iceoryx_->subscribe(channel, inbox, queue_capacity);
  }

  int poll_ready(std::int64_t timeout_ns) noexcept {
    return lcm_ ? lcm_->poll_ready(timeout_ns) : iceoryx_->poll_ready(timeout_ns);
  }
  int handle_pending() noexcept {
    return lcm_ ? lcm_->handle_pending() : iceoryx_->handle_pending();
  }

  /// As LcmTransport::handle_until (rt/receive_wait.hpp).
  template <class Done>
  int handle_until(std::int64_t deadline_ns, ReceiveMode mode, Done&& done,
                   std::int64_t spin_from_ns = 0) noexcept {
    return handle_until_deadline(*this, deadline_ns, mode, done, spin_from_ns);
  }

  /// iceoryx: every subscription connected to a publisher; LCM (no connections): true.
  bool subscriptions_connected() const noexcept {
    return lcm_ ? true : iceoryx_->subscriptions_connected();
  }

  LcmTransport* lcm() noexcept { return lcm_.get(); }
  IceoryxTransport* iceoryx() noexcept { return iceoryx_.get(); }

 private:
  std::unique_ptr<LcmTransport> lcm_;
  std::unique_ptr<IceoryxTransport> iceoryx_;
  std::string url_;
};

/// Publishes one message type on one channel of the loop's carrier.
template <class Msg>
class LoopPublisher {
 public:
  LoopPublisher(LoopTransport& transport, const std::string& channel) {
    if (transport.lcm())
      lcm_.emplace(*transport.lcm(), channel);
    else
      iceoryx_.emplace(*transport.iceoryx(), channel);
  }

  bool publish(const Msg& msg) noexcept {
    return lcm_ ? lcm_->publish(msg) : iceoryx_->publish(msg);
  }
  /// iceoryx: a subscriber is connected; LCM (no connections): true.
  bool has_subscribers() const noexcept { return lcm_ ? true : iceoryx_->has_subscribers(); }
  std::int64_t published() const noexcept {
    return lcm_ ? lcm_->published() : iceoryx_->published();
  }
  std::int64_t failures() const noexcept { return lcm_ ? lcm_->failures() : iceoryx_->failures(); }

 private:
  std::optional<LcmPublisher<Msg>> lcm_;
  std::optional<IceoryxPublisher<Msg>> iceoryx_;
};

/// The loop process's set-up (rt/loop_process_setup.hpp) on either carrier: with LCM also its
/// receive thread; iceoryx has no thread in the message path.
LoopProcessSetup set_up_loop_process(LoopTransport& transport, const RealtimeOptions& options);

/// A RouDi for flexloop's loops and baselines: one mempool whose chunks hold the largest of the
/// loop's messages at numeric::kMaxChannels channels (256 chunks: every subscriber queue full,
/// 30 each, with room to spare), its keep-alive watch off (RoudiOptions::monitoring).
RoudiOptions loop_roudi_options();

/// Waits (sleeping 1 ms at a time, set-up only) until `connected()` holds or timeout_ns passed;
/// the time it took, or -1 when it timed out.
template <class Connected>
std::int64_t wait_until_connected(Connected&& connected, std::int64_t timeout_ns) {
  const std::int64_t start = monotonic_now_ns();
  while (!connected()) {
    if (monotonic_now_ns() - start >= timeout_ns) return -1;
    usleep(1000);
  }
  return monotonic_now_ns() - start;
}

}  // namespace flexloop::rt
