// SPDX-License-Identifier: BSD-3-Clause
#include "rt/lcm_direct_socket.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "rt/monotonic_time.hpp"

namespace flexloop::rt {

namespace {

constexpr std::uint32_t kSmallMagic = 0x4c433032;  // "LC02"
constexpr std::size_t kHeaderBytes = 8;            // magic, sequence
constexpr std::size_t kMaxDatagram = 65536;

std::uint32_t read_be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

int to_int(const std::string& text, const std::string& what, const std::string& url) {
  std::size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty())
    throw std::invalid_argument("LCM URL '" + url + "': " + what + " '" + text +
                                "' is not a whole number");
  return v;
}

}  // namespace

UdpmAddress parse_udpm_url(const std::string& url) {
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0)
    throw std::invalid_argument("LCM URL '" + url +
                                "': direct receive needs a udpm:// URL (UDP multicast); for other "
                                "providers use --receive-path lcm-thread");
  UdpmAddress a;
  std::string rest = url.substr(scheme.size());
  std::string options;
  if (const auto q = rest.find('?'); q != std::string::npos) {
    options = rest.substr(q + 1);
    rest = rest.substr(0, q);
  }
  if (const auto c = rest.find(':'); c != std::string::npos) {
    a.port = to_int(rest.substr(c + 1), "port", url);
    rest = rest.substr(0, c);
  }
  if (!rest.empty()) a.group = rest;
  in_addr group{};
  if (inet_pton(AF_INET, a.group.c_str(), &group) != 1 || !IN_MULTICAST(ntohl(group.s_addr)))
    throw std::invalid_argument("LCM URL '" + url + "': '" + a.group +
                                "' is not an IPv4 multicast group (224.0.0.0/4)");
  if (a.port < 1 || a.port > 65535)
    throw std::invalid_argument("LCM URL '" + url + "': port must be 1..65535");
  while (!options.empty()) {
    const auto amp = options.find('&');
    const std::string kv = options.substr(0, amp);
    options = amp == std::string::npos ? "" : options.substr(amp + 1);
    const auto eq = kv.find('=');
    if (eq != std::string::npos && kv.substr(0, eq) == "recv_buf_size") {
      a.recv_buf_size = to_int(kv.substr(eq + 1), "recv_buf_size", url);
      if (a.recv_buf_size < 1)
        throw std::invalid_argument("LCM URL '" + url + "': recv_buf_size must be >= 1 byte");
    }
  }
  return a;
}

LcmDirectSocket::LcmDirectSocket(const std::string& url) : buffer_(kMaxDatagram) {
  const UdpmAddress a = parse_udpm_url(url);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0)
    throw std::runtime_error("LCM direct receive: socket: " + std::string(strerror(errno)));
  const auto fail = [&](const std::string& step) {
    const int err = errno;
    close(fd_);
    fd_ = -1;
    throw std::runtime_error("LCM direct receive on " + a.group + ":" + std::to_string(a.port) +
                             ": " + step + ": " + strerror(err));
  };
  const int one = 1;
  if (setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0) fail("SO_REUSEADDR");
  if (a.recv_buf_size > 0 &&  // 0: not given, the kernel's default
      setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &a.recv_buf_size, sizeof a.recv_buf_size) != 0)
    fail("SO_RCVBUF");
  sockaddr_in bind_to{};
  bind_to.sin_family = AF_INET;
  bind_to.sin_addr.s_addr = htonl(INADDR_ANY);
  bind_to.sin_port = htons(static_cast<std::uint16_t>(a.port));
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&bind_to), sizeof bind_to) != 0) fail("bind");
  ip_mreq join{};
  inet_pton(AF_INET, a.group.c_str(), &join.imr_multiaddr);
  join.imr_interface.s_addr = htonl(INADDR_ANY);
  if (setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &join, sizeof join) != 0)
    fail("joining the multicast group");
  // Only this group's datagrams (Linux delivers every joined group on the port otherwise).
  const int zero = 0;
  if (setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_ALL, &zero, sizeof zero) != 0)
    fail("IP_MULTICAST_ALL");
}

LcmDirectSocket::~LcmDirectSocket() {
  if (fd_ >= 0) close(fd_);
}

void LcmDirectSocket::subscribe(const std::string& channel, Handler handler, void* user) {
  subscriptions_.push_back({channel, handler, user});
}

int LcmDirectSocket::receive() noexcept {
  int handled = 0;
  // At most kMaxDatagramsPerCall per call, so that a flood cannot hold the loop past its
  // deadline; what is left is read by the next call.
  for (int read = 0; read < kMaxDatagramsPerCall; ++read) {
    const ssize_t n = recv(fd_, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      return handled;  // EAGAIN: nothing more now (other errors: nothing to read either)
    }
    const auto size = static_cast<std::size_t>(n);
    if (size < kHeaderBytes + 1) {
      ++foreign_;
      continue;
    }
    const std::uint32_t magic = read_be32(buffer_.data());
    const auto* channel = reinterpret_cast<const char*>(buffer_.data() + kHeaderBytes);
    const std::size_t room = size - kHeaderBytes;
    const std::size_t length = strnlen(channel, room);
    // Not a small LCM message (fragments of large ones included), or no NUL in the datagram.
    if (magic != kSmallMagic || length == room) {
      ++foreign_;
      continue;
    }
    const std::uint8_t* payload = buffer_.data() + kHeaderBytes + length + 1;
    const int payload_size = static_cast<int>(room - length - 1);
    bool delivered = false;
    for (const Subscription& s : subscriptions_)
      if (s.channel.size() == length && std::memcmp(s.channel.data(), channel, length) == 0) {
        s.handler(payload, payload_size, s.user);
        delivered = true;
      }
    if (delivered)
      ++handled;
    else
      ++unsubscribed_;
  }
  return handled;
}

}  // namespace flexloop::rt
