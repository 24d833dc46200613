// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Receiving LCM messages in the loop thread itself, without LCM's receive thread.
//
// Why: LCM 1.3.1's udpm provider reads its socket in an internal thread that hands each message
// to the user through a pipe, so every message costs one more thread wake-up before the loop
// sees it -- on this 2-core VM a cross-CPU wake-up costs 15-30 us, so a round trip pays it twice
// on top of the loops' own wake-ups, and a polling loop cannot avoid it.
//
// What: a UDP socket of our own on the URL's multicast group and port (SO_REUSEADDR: every
// socket bound there gets its own copy of each datagram, so LCM's own subscribers, lcm-logger and
// lcm-spy see everything as before), read non-blocking by the thread that wants the messages.
// Each datagram is parsed as LCM's small-message packet (LCM UDP multicast protocol, "LC02"):
//   uint32 magic 0x4c433032 (big-endian) | uint32 sequence | channel, NUL-terminated | payload
// and the payload goes to the handler of its channel. Fragmented messages ("LC03", more than
// one datagram: > 64 kB) are not ours -- the loop's messages are ~100 bytes -- and are skipped
// and counted, as are datagrams that are not LCM at all. Publishing stays with LCM
// (lcm_publish), so what goes on the wire is LCM's, byte for byte.
//
// URL: "udpm://GROUP:PORT?opt=value&..." as LCM reads it; recv_buf_size sets SO_RCVBUF, other
// options are LCM's (ttl is for sending). Set-up (constructor, subscribe) may allocate and throws
// std::runtime_error / std::invalid_argument; receive() and wait_readable() do not allocate or
// throw (recv, ppoll: system calls).
#include <cstdint>
#include <string>
#include <vector>

namespace flexloop::rt {

/// Group, port and receive buffer of an LCM udpm URL.
struct UdpmAddress {
  std::string group = "239.255.76.67";
  int port = 7667;
  int recv_buf_size = 0;  ///< bytes; 0: the system default
};

/// @throws std::invalid_argument for a URL that is not udpm://GROUP[:PORT][?options] with an
/// IPv4 multicast group and a port 1..65535.
UdpmAddress parse_udpm_url(const std::string& url);

class LcmDirectSocket {
 public:
  using Handler = void (*)(const std::uint8_t* payload, int size, void* user);

  /// Binds to the URL's port and joins its group. @throws std::invalid_argument for a URL that is
  /// not udpm (parse_udpm_url), std::runtime_error naming the socket step that failed.
  explicit LcmDirectSocket(const std::string& url);
  ~LcmDirectSocket();
  LcmDirectSocket(const LcmDirectSocket&) = delete;
  LcmDirectSocket& operator=(const LcmDirectSocket&) = delete;

  /// Payloads on `channel` go to handler(payload, size, user). Start-up only (allocates).
  void subscribe(const std::string& channel, Handler handler, void* user);

  /// Reads the datagrams waiting now (at most kMaxDatagramsPerCall) and dispatches them; returns
  /// how many went to a handler.
  int receive() noexcept;
  int fd() const noexcept { return fd_; }
  std::int64_t foreign() const noexcept { return foreign_; }  ///< not small LCM messages (LC03 too)
  std::int64_t unsubscribed() const noexcept { return unsubscribed_; }  ///< other channels

  static constexpr int kMaxDatagramsPerCall = 64;

 private:
  struct Subscription {
    std::string channel;
    Handler handler;
    void* user;
  };
  int fd_ = -1;
  std::vector<Subscription> subscriptions_;
  std::vector<std::uint8_t> buffer_;  // one datagram, 64 kB
  std::int64_t foreign_ = 0, unsubscribed_ = 0;
};

}  // namespace flexloop::rt
