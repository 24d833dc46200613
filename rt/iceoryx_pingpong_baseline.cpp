// SPDX-License-Identifier: BSD-3-Clause
#include "rt/iceoryx_pingpong_baseline.hpp"

#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>

#include "rt/iceoryx_transport.hpp"
#include "rt/pingpong_sides.hpp"
#include "rt/reap_child.hpp"

namespace flexloop::rt {

namespace {

// The runtime's files of this process, removed by the handler of a stopping signal (SIGINT from
// a terminal reaches the whole process group; SIGTERM from RouDi when its owner died): the
// runtime cannot deregister then, and would leave them in /tmp.
char g_runtime_files[2][256];

extern "C" void remove_runtime_files_and_end(int signal) {
  for (const char* path : g_runtime_files) unlink(path);  // async-signal-safe
  _exit(128 + signal);
}

void remove_runtime_files_on_signal(const std::string& registered_name) {
  const std::vector<std::string> files = IceoryxTransport::runtime_files(registered_name);
  for (std::size_t i = 0; i < 2; ++i)
    std::snprintf(g_runtime_files[i], sizeof g_runtime_files[i], "%s", files[i].c_str());
  struct sigaction action {};
  action.sa_handler = remove_runtime_files_and_end;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// iceoryx as the ping-pong's carrier (rt/pingpong_sides.hpp).
struct IceoryxCarrier {
  static constexpr const char* kName = "iceoryx";
  template <class Msg>
  using Publisher = IceoryxPublisher<Msg>;
  static std::unique_ptr<IceoryxTransport> open(const PingPongOptions&, const char* role) {
    const std::string name = std::string("flexloop_") + role;
    remove_runtime_files_on_signal(IceoryxTransport::registered_name(name));
    return std::make_unique<IceoryxTransport>(name);
  }
  static std::string set_up(IceoryxTransport&, const RealtimeOptions& realtime) {
    return apply_realtime_setup(realtime).describe();
  }
};

// What the ping process hands back: its figures, its set-up text, or why it failed.
struct PingPage {
  LatencyHistogram round_trip;
  LatencyHistogram wakeup_lateness;
  std::int64_t sent = 0, answered = 0, unanswered = 0, late_answers = 0, overruns = 0;
  DropCounts ping_drops;
  char ping_setup[2048]{};
  char error[1024]{};
};

// The counts of a ping side, from a result to the page and back (the same names on both).
template <class From, class To>
void copy_counts(const From& from, To& to) {
  to.sent = from.sent;
  to.answered = from.answered;
  to.unanswered = from.unanswered;
  to.late_answers = from.late_answers;
  to.overruns = from.overruns;
  to.ping_drops = from.ping_drops;
}

void copy_text(char* to, std::size_t size, const std::string& text) {
  std::snprintf(to, size, "%s", text.c_str());
}

// The ping process: run the ping side, leave the figures on the page. exit(), not _exit():
// iceoryx's runtime deregisters from RouDi in its static destructor.
[[noreturn]] void ping_process(const PingPongOptions& o, PingPage& page) {
  try {
    PingPongResult r;
    r.round_trip = std::make_unique<LatencyHistogram>();
    r.wakeup_lateness = std::make_unique<LatencyHistogram>();
    pingpong::run_ping<IceoryxCarrier>(o, r);
    page.round_trip = *r.round_trip;
    page.wakeup_lateness = *r.wakeup_lateness;
    copy_counts(r, page);
    copy_text(page.ping_setup, sizeof page.ping_setup, r.ping_setup);
  } catch (const std::exception& e) {
    copy_text(page.error, sizeof page.error, e.what());
  }
  std::exit(0);
}

[[noreturn]] void pong_process(const PingPongOptions& o, int report_fd) {
  int code = 1;
  try {
    code = pingpong::run_pong<IceoryxCarrier>(o, report_fd);
  } catch (const std::exception& e) {
    pingpong::send_block(report_fd, std::string("iceoryx ping-pong: the pong failed: ") + e.what());
  }
  std::exit(code);
}

pid_t fork_or_throw() {
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("iceoryx ping-pong: fork failed");
  return child;
}

PingPongResult result_from(const PingPage& page) {
  PingPongResult r;
  r.round_trip = std::make_unique<LatencyHistogram>(page.round_trip);
  r.wakeup_lateness = std::make_unique<LatencyHistogram>(page.wakeup_lateness);
  copy_counts(page, r);
  r.ping_setup = page.ping_setup;
  return r;
}

}  // namespace

PingPongResult run_iceoryx_pingpong_baseline(const PingPongOptions& options, RoudiProcess& roudi) {
  pingpong::check_options(options);
  void* map =
      mmap(nullptr, sizeof(PingPage), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED)
    throw std::runtime_error(std::string("iceoryx ping-pong: mmap: ") + std::strerror(errno));
  PingPage& page = *new (map) PingPage;
  int pipe_fd[2];
  if (pipe(pipe_fd) != 0) throw std::runtime_error("iceoryx ping-pong: cannot create a pipe");
  std::fflush(nullptr);  // nothing buffered may be written twice
  const pid_t pong = fork_or_throw();
  if (pong == 0) {
    close(pipe_fd[0]);
    pong_process(options, pipe_fd[1]);
  }
  close(pipe_fd[1]);
  const pid_t ping = fork_or_throw();
  if (ping == 0) ping_process(options, page);
  // The ping ends by itself (its clock, its connect time-out); the pong on the stop message.
  const std::int64_t run_ns = options.connect_timeout_ns + options.duration_ns;
  reap_child(ping, run_ns + 10 * kNsPerSecond, 10'000'000);
  reap_child(pong, 3 * kNsPerSecond, 10'000'000);
  const std::string pong_setup = pingpong::receive_block(pipe_fd[0]);
  const std::string pong_summary = pingpong::receive_block(pipe_fd[0]);
  close(pipe_fd[0]);
  PingPongResult r = result_from(page);
  const std::string error = page.error;
  munmap(map, sizeof(PingPage));
  if (!roudi.alive())
    throw RoudiError(roudi.describe() + " during the iceoryx ping-pong: no figures reported");
  if (!error.empty()) throw std::runtime_error(error);
  if (pong_setup.rfind("iceoryx ping-pong: the pong failed", 0) == 0)
    throw std::runtime_error(pong_setup);
  r.pong_setup = pong_setup;
  r.pong_summary = pong_summary;
  return r;
}

}  // namespace flexloop::rt
