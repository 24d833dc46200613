// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// LCM glue for the loop (doc/design.md §7, §11), on LCM 1.3.1's C API so that nothing in the loop
// allocates:
//   - LcmPublisher<Msg> encodes into a buffer sized once at construction and publishes the
//     bytes (the C++ typed publish allocates a buffer on every call, and the C++ std::string
//     channel arguments allocate for names longer than 15 characters);
//   - subscribe() registers a static C callback (no lambdas in 1.3.1) that hands each message
//     to a MessageInbox<Msg> (decode into a preallocated struct, validate, keep the newest);
//   - receiving never blocks longer than asked: handle_pending() handles what is ready (zero-
//     timeout ppoll on LCM's fileno, then lcm_handle), handle_until() waits for messages up to
//     an absolute deadline and stops early when a predicate holds (e.g. "the answer to sample k
//     came"). ReceiveMode: kBlocking sleeps in ppoll; kPolling spins on zero-timeout polls (a
//     full CPU; at SCHED_FIFO throttled by sched_rt_runtime_us like any spinner, see
//     rt/periodic_clock.hpp); kHybrid sleeps in ppoll until a given time (shortly before the
//     message is expected) and polls from then on.
//
// How LCM 1.3.1's udpm provider receives (what the timing depends on): an internal thread,
// started by the first subscribe or fileno call (here: in the constructor), reads the UDP socket
// and queues the message; lcm_get_fileno() is the read end of a pipe that this thread writes one
// byte to; lcm_handle() takes one message from the queue and calls the handlers. So a message
// costs a thread wake-up in between -- that thread's scheduling and CPU matter:
// configure_receive_thread() pins it and gives it SCHED_FIFO (one above the loop, so a spinning
// loop on the same CPU cannot starve it). Measured on the 2-core VM (flexloop baseline pingpong):
// that wake-up costs about what a timer wake-up does (15-20 us), so a round trip is ~2 of them
// when both loops poll (p50 60-75 us) and ~4 when both block (p50 60-130 us); polling saves the
// loop thread's wake-up, not the receive thread's. LCM keeps at most `queue_capacity` unhandled
// messages per subscription (30 by default) and drops newer ones when full; for bursts also raise
// the socket buffer with the URL option recv_buf_size (e.g. "...?ttl=0&recv_buf_size=2097152").
//
// ReceivePath::kDirect takes LCM's receive thread out of the path: the loop thread reads the
// multicast socket itself (rt/lcm_direct_socket.hpp) and LCM only publishes (no LCM subscription,
// so LCM never starts its thread). Same subscribe/handle API; the set-up report says which path.
//
// In-loop calls (publish, handle_pending, handle_until) are allocation-free once each channel
// has delivered one message (LCM caches its channel -> handlers lookup on first use), throw
// nothing, and make system calls (sendmsg, ppoll, read); lcm_handle takes LCM's internal mutex,
// shared with the receive thread only. Set-up calls (constructor, subscribe) may allocate and
// throw std::runtime_error. Callers that send multicast must first check they run in the private
// loopback namespace (rt/loopback_guard.hpp).
#include <lcm/lcm.h>
#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rt/event_log_recorder.hpp"
#include "rt/lcm_direct_socket.hpp"
#include "rt/message_inbox.hpp"
#include "rt/monotonic_time.hpp"
#include "rt/realtime_setup.hpp"
#include "rt/receive_wait.hpp"

namespace flexloop::rt {

/// Who reads the socket: LCM's internal thread (handing over through a pipe), or the loop thread
/// itself (rt/lcm_direct_socket.hpp).
enum class ReceivePath { kLcmThread, kDirect };

/// "block" | "poll" | "hybrid" -> mode; throws std::invalid_argument naming the choices.
ReceiveMode parse_receive_mode(const std::string& name);
const char* to_string(ReceiveMode mode);
/// "lcm-thread" | "direct" -> path; throws std::invalid_argument naming the choices.
ReceivePath parse_receive_path(const std::string& name);
const char* to_string(ReceivePath path);

class LcmTransport {
 public:
  /// Opens LCM on `url`; with kLcmThread starts its receive thread, with kDirect opens the
  /// loop's own socket instead. std::runtime_error when LCM or the socket cannot be opened,
  /// std::invalid_argument when kDirect is asked for a URL that is not udpm://.
  explicit LcmTransport(const std::string& url, ReceivePath path = ReceivePath::kLcmThread);
  ~LcmTransport();
  LcmTransport(const LcmTransport&) = delete;
  LcmTransport& operator=(const LcmTransport&) = delete;

  /// Start-up, before subscribe() and the publishers: every message subscribed to and every
  /// message published from then on is also given to `recorder` (which must outlive the
  /// transport and its publishers), as it arrives or leaves.
  void record_to(EventLogRecorder* recorder) noexcept { recorder_ = recorder; }
  EventLogRecorder* recorder() const noexcept { return recorder_; }

  /// Delivers every message on `channel` to `inbox` (which must outlive the transport).
  /// queue_capacity: unhandled messages LCM keeps for this subscription before dropping.
  template <class Msg>
  void subscribe(const std::string& channel, MessageInbox<Msg>& inbox, int queue_capacity = 30) {
    auto& s = *subscriptions_.emplace_back(std::make_unique<Subscription>(
        Subscription{&inbox, recorder_, recorder_ ? recorder_->channel(channel) : -1}));
    if (direct_)
      direct_->subscribe(channel, &LcmTransport::deliver_direct<Msg>, &s);
    else
      subscribe_lcm(channel, &LcmTransport::deliver<Msg>, &s, queue_capacity);
  }

  /// 1 when a message is ready, 0 when none came within timeout_ns (0: just look), -1 on error.
  int poll_ready(std::int64_t timeout_ns) noexcept;

  /// Handles every message ready now; returns how many.
  int handle_pending() noexcept;

  /// Handles messages until `done()` is true (checked after each batch) or CLOCK_MONOTONIC
  /// reaches deadline_ns; returns how many were handled. Between messages kBlocking sleeps in
  /// ppoll, kPolling spins on zero-timeout polls, kHybrid sleeps until spin_from_ns and spins
  /// after it (spin_from_ns is ignored by the other modes).
  template <class Done>
  int handle_until(std::int64_t deadline_ns, ReceiveMode mode, Done&& done,
                   std::int64_t spin_from_ns = 0) noexcept {
    return handle_until_deadline(*this, deadline_ns, mode, done, spin_from_ns);
  }
  int handle_until(std::int64_t deadline_ns, ReceiveMode mode) noexcept {
    return handle_until(deadline_ns, mode, [] { return false; });
  }

  /// Kernel thread ids of LCM's internal threads (those the constructor saw appear; none with
  /// kDirect).
  const std::vector<pid_t>& receive_thread_ids() const { return receive_threads_; }
  /// Pins LCM's receive thread(s) to `cpu` (when >= 0) and sets SCHED_FIFO `fifo_priority`
  /// (when > 0). One status per step and thread.
  std::vector<SetupStatus> configure_receive_thread(int cpu, int fifo_priority);

  /// The direct socket (kDirect), or nullptr.
  const LcmDirectSocket* direct_socket() const noexcept { return direct_.get(); }
  lcm_t* lcm() noexcept { return lcm_; }
  /// What poll_ready() waits on: LCM's pipe, or the direct socket.
  int fileno() const noexcept { return fileno_; }

 private:
  struct Subscription {
    void* inbox;  // MessageInbox<Msg>*
    EventLogRecorder* recorder;
    int recorder_channel;
  };
  template <class Msg>
  static void deliver(const lcm_recv_buf_t* rbuf, const char*, void* subscription) {
    deliver_direct<Msg>(static_cast<const std::uint8_t*>(rbuf->data),
                        static_cast<int>(rbuf->data_size), subscription);
  }
  template <class Msg>
  static void deliver_direct(const std::uint8_t* data, int size, void* subscription) {
    const auto& s = *static_cast<const Subscription*>(subscription);
    const std::int64_t now = monotonic_now_ns();
    if (s.recorder) s.recorder->record(s.recorder_channel, data, size, now);
    static_cast<MessageInbox<Msg>*>(s.inbox)->offer(data, size, now);
  }
  void subscribe_lcm(const std::string& channel, lcm_msg_handler_t handler, void* user,
                     int queue_capacity);

  std::unique_ptr<LcmDirectSocket> direct_;
  EventLogRecorder* recorder_ = nullptr;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;  // stable addresses for the callbacks
  lcm_t* lcm_ = nullptr;
  int fileno_ = -1;
  std::vector<pid_t> receive_threads_;
};

/// Publishes one message type on one channel from a preallocated buffer.
template <class Msg>
class LcmPublisher {
 public:
  LcmPublisher(LcmTransport& transport, std::string channel)
      : lcm_(transport.lcm()),
        channel_(std::move(channel)),
        buffer_(static_cast<std::size_t>(max_encoded_size<Msg>())),
        recorder_(transport.recorder()),
        recorder_channel_(recorder_ ? recorder_->channel(channel_) : -1) {}

  /// Encodes and sends; false (and counted) when encoding or sending failed. What was sent is
  /// also recorded when the transport records (LcmTransport::record_to).
  bool publish(const Msg& msg) noexcept {
    const int n = msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    if (n < 0 ||
        lcm_publish(lcm_, channel_.c_str(), buffer_.data(), static_cast<unsigned>(n)) != 0) {
      ++failures_;
      return false;
    }
    if (recorder_) recorder_->record(recorder_channel_, buffer_.data(), n, monotonic_now_ns());
    ++published_;
    return true;
  }

  const std::string& channel() const noexcept { return channel_; }
  std::int64_t published() const noexcept { return published_; }
  std::int64_t failures() const noexcept { return failures_; }

 private:
  lcm_t* lcm_;
  std::string channel_;
  std::vector<std::uint8_t> buffer_;
  EventLogRecorder* recorder_;
  int recorder_channel_;
  std::int64_t published_ = 0;
  std::int64_t failures_ = 0;
};

}  // namespace flexloop::rt
