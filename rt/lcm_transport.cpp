// SPDX-License-Identifier: BSD-3-Clause
#include "rt/lcm_transport.hpp"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <iterator>
#include <stdexcept>

#include "rt/enum_names.hpp"

namespace flexloop::rt {

constexpr EnumName<ReceiveMode> kReceiveModeNames[] = {{ReceiveMode::kBlocking, "block"},
                                                       {ReceiveMode::kPolling, "poll"},
                                                       {ReceiveMode::kHybrid, "hybrid"}};

ReceiveMode parse_receive_mode(const std::string& name) {
  return parse_enum(kReceiveModeNames, name, "receive mode");
}

const char* to_string(ReceiveMode mode) {
  return enum_name(kReceiveModeNames, mode);
}

constexpr EnumName<ReceivePath> kReceivePathNames[] = {{ReceivePath::kLcmThread, "lcm-thread"},
                                                       {ReceivePath::kDirect, "direct"}};

ReceivePath parse_receive_path(const std::string& name) {
  return parse_enum(kReceivePathNames, name, "receive path");
}

const char* to_string(ReceivePath path) {
  return enum_name(kReceivePathNames, path);
}

LcmTransport::LcmTransport(const std::string& url, ReceivePath path) {
  if (path == ReceivePath::kDirect) direct_ = std::make_unique<LcmDirectSocket>(url);
  const std::vector<pid_t> before = process_thread_ids();
  lcm_ = lcm_create(url.c_str());
  if (lcm_ == nullptr) throw std::runtime_error("cannot open LCM on '" + url + "'");
  if (direct_) {  // LCM publishes only: no subscription, no fileno, so no receive thread
    fileno_ = direct_->fd();
    return;
  }
  // Asking for the fileno makes the udpm provider set up its receive socket and thread now,
  // before the loop, so the thread can be found and configured.
  fileno_ = lcm_get_fileno(lcm_);
  if (fileno_ < 0) {
    lcm_destroy(lcm_);
    throw std::runtime_error("LCM on '" + url + "' has no file descriptor to poll");
  }
  const std::vector<pid_t> after = process_thread_ids();
  std::set_difference(after.begin(), after.end(), before.begin(), before.end(),
                      std::back_inserter(receive_threads_));
}

LcmTransport::~LcmTransport() {
  if (lcm_) lcm_destroy(lcm_);
}

void LcmTransport::subscribe_lcm(const std::string& channel, lcm_msg_handler_t handler, void* user,
                                 int queue_capacity) {
  lcm_subscription_t* sub = lcm_subscribe(lcm_, channel.c_str(), handler, user);
  if (sub == nullptr) throw std::runtime_error("cannot subscribe to LCM channel " + channel);
  if (lcm_subscription_set_queue_capacity(sub, queue_capacity) != 0)
    throw std::runtime_error("cannot set the queue capacity of LCM channel " + channel);
}

int LcmTransport::poll_ready(std::int64_t timeout_ns) noexcept {
  pollfd fd{fileno_, POLLIN, 0};
  const timespec ts = to_timespec(timeout_ns > 0 ? timeout_ns : 0);
  const int n = ppoll(&fd, 1, &ts, nullptr);
  if (n < 0) return errno == EINTR ? 0 : -1;
  return n > 0 && (fd.revents & POLLIN) ? 1 : (n > 0 ? -1 : 0);
}

int LcmTransport::handle_pending() noexcept {
  if (direct_) return direct_->receive();
  int handled = 0;
  while (poll_ready(0) == 1 && lcm_handle(lcm_) == 0) ++handled;
  return handled;
}

std::vector<SetupStatus> LcmTransport::configure_receive_thread(int cpu, int fifo_priority) {
  std::vector<SetupStatus> out;
  for (pid_t tid : receive_threads_) {
    if (cpu >= 0) out.push_back(pin_thread_to_cpu(tid, cpu));
    if (fifo_priority > 0) out.push_back(try_set_thread_fifo_priority(tid, fifo_priority));
  }
  if (direct_)
    out.push_back({true, "none: the loop thread reads the multicast socket itself (direct)"});
  else if (receive_threads_.empty())
    out.push_back({false, "LCM started no receive thread that could be configured"});
  return out;
}

}  // namespace flexloop::rt
