// SPDX-License-Identifier: BSD-3-Clause
#include "rt/pingpong_baseline.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <stdexcept>

#include "rt/loop_process_setup.hpp"
#include "rt/pingpong_sides.hpp"
#include "rt/reap_child.hpp"

namespace flexloop::rt {

namespace {

constexpr const char* kPongFailed = "LCM ping-pong: the pong process failed: ";

// LCM as the ping-pong's carrier (rt/pingpong_sides.hpp).
struct LcmCarrier {
  static constexpr const char* kName = "LCM";
  template <class Msg>
  using Publisher = LcmPublisher<Msg>;
  static std::unique_ptr<LcmTransport> open(const PingPongOptions& o, const char*) {
    return std::make_unique<LcmTransport>(o.url, o.receive_path);
  }
  static std::string set_up(LcmTransport& lcm, const RealtimeOptions& realtime) {
    return set_up_loop_process(lcm, realtime).text;
  }
};

}  // namespace

PingPongResult run_pingpong_baseline(const PingPongOptions& options) {
  require_private_loopback_namespace("LCM ping-pong baseline");
  pingpong::check_options(options);  // before forking

  PingPongResult r;
  r.round_trip = std::make_unique<LatencyHistogram>();
  r.wakeup_lateness = std::make_unique<LatencyHistogram>();

  int pipe_fd[2];
  if (pipe(pipe_fd) != 0) throw std::runtime_error("ping-pong: cannot create a pipe");
  std::fflush(nullptr);  // nothing buffered may be written twice
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("ping-pong: fork failed");
  if (child == 0) {
    close(pipe_fd[0]);
    int code = 1;
    try {
      code = pingpong::run_pong<LcmCarrier>(options, pipe_fd[1]);
    } catch (const std::exception& e) {
      pingpong::send_block(pipe_fd[1], std::string(kPongFailed) + e.what());
    }
    _exit(code);  // the parent's atexit handlers and buffers are not the child's to run
  }
  close(pipe_fd[1]);
  r.pong_setup = pingpong::receive_block(pipe_fd[0]);  // also: the pong has subscribed
  try {
    if (r.pong_setup.rfind(kPongFailed, 0) == 0) throw std::runtime_error(r.pong_setup);
    pingpong::run_ping<LcmCarrier>(options, r);
  } catch (...) {
    reap_child(child, 2 * kNsPerSecond, 10'000'000);
    close(pipe_fd[0]);
    throw;
  }
  r.pong_summary = pingpong::receive_block(pipe_fd[0]);
  close(pipe_fd[0]);
  reap_child(child, 2 * kNsPerSecond, 10'000'000);
  return r;
}

void merge_into(PingPongResult& total, const PingPongResult& part) {
  total.round_trip->merge(*part.round_trip);
  total.wakeup_lateness->merge(*part.wakeup_lateness);
  total.sent += part.sent;
  total.answered += part.answered;
  total.unanswered += part.unanswered;
  total.late_answers += part.late_answers;
  total.overruns += part.overruns;
  total.ping_drops.merge(part.ping_drops);
}

}  // namespace flexloop::rt
