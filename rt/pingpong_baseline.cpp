#include "rt/pingpong_baseline.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <stdexcept>

#include "rt/loop_process_setup.hpp"
#include "rt/reap_child.hpp"

namespace flexloop::rt {

namespace {

using flexloop_msgs::actuator_command_t;
using flexloop_msgs::sensor_sample_t;

// Channels of each kind in the ping-pong's messages: the size of the metrology frame's loop.
constexpr int kBaselineChannels = 6;

constexpr const char* kPongFailed = "LCM ping-pong: the pong process failed: ";

struct Channels {
  std::string ping, pong, stop;
  explicit Channels(const std::string& prefix)
      : ping(prefix + "_PING"), pong(prefix + "_PONG"), stop(prefix + "_STOP") {}
};

// A text block over the pipe, '\0'-terminated (the first one also says "ready").
void send_block(int fd, const std::string& text) {
  const std::string block = text + '\0';
  std::size_t done = 0;
  while (done < block.size()) {
    const ssize_t n = write(fd, block.data() + done, block.size() - done);
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

std::string receive_block(int fd) {
  std::string text;
  char c = 0;
  while (read(fd, &c, 1) == 1 && c != '\0') text += c;
  return text;
}

// The child: answer every ping until told to stop (or a generous time limit passes).
int run_pong(const PingPongOptions& o, int report_fd) {
  const Channels ch(o.channel_prefix);
  LcmTransport lcm(o.url, o.receive_path);
  MessageInbox<sensor_sample_t> pings;  // kFollow: a ping side's epoch is taken as it comes
  MessageInbox<sensor_sample_t> stop;
  lcm.subscribe(ch.ping, pings);
  lcm.subscribe(ch.stop, stop);
  LcmPublisher<actuator_command_t> answer(lcm, ch.pong);
  send_block(report_fd, set_up_loop_process(lcm, o.pong_realtime).text);

  actuator_command_t cmd{};
  // The loop's message sizes (the metrology frame's 6 channels of each kind).
  cmd.n_commands = kBaselineChannels;
  cmd.commands.assign(kBaselineChannels, 0.0);
  const std::int64_t give_up =
      monotonic_now_ns() + o.connect_timeout_ns + o.duration_ns + 5 * kNsPerSecond;
  const auto wake = [&] { return pings.has_fresh() || stop.has_fresh(); };
  std::int64_t spin_from = 0;  // kHybrid: poll from shortly before the next ping is due
  while (!stop.has_fresh() && monotonic_now_ns() < give_up) {
    lcm.handle_until(give_up, o.receive_mode, wake, spin_from);
    if (const sensor_sample_t* p = pings.take()) {
      spin_from = p->t_ns + o.clock.period_ns - effective_spin_margin_ns(o.clock);
      cmd.seq += 1;
      cmd.answers_seq = p->seq;
      cmd.plant_epoch = p->plant_epoch;
      cmd.t_ns = monotonic_now_ns();
      answer.publish(cmd);
    }
  }
  char summary[256];
  std::snprintf(
      summary, sizeof summary,
      "answered %lld pings, %lld superseded before answered, %lld dropped, "
      "%lld publish failures",
      static_cast<long long>(answer.published()), static_cast<long long>(pings.superseded()),
      static_cast<long long>(pings.drops().total()), static_cast<long long>(answer.failures()));
  send_block(report_fd, summary);
  return 0;
}

// The parent: ping every period, account the answers.
void run_ping(const PingPongOptions& o, PingPongResult& r) {
  const Channels ch(o.channel_prefix);
  LcmTransport lcm(o.url, o.receive_path);
  const std::int64_t epoch = monotonic_now_ns() ^ (static_cast<std::int64_t>(getpid()) << 40);
  MessageInbox<actuator_command_t> answers(OrderGate(EpochPolicy::kFixed, epoch));
  lcm.subscribe(ch.pong, answers);
  LcmPublisher<sensor_sample_t> ping(lcm, ch.ping);
  LcmPublisher<sensor_sample_t> stop(lcm, ch.stop);
  r.ping_setup = set_up_loop_process(lcm, o.ping_realtime).text;

  sensor_sample_t msg{};
  msg.n_sensors = msg.n_performance = kBaselineChannels;
  msg.sensors.assign(kBaselineChannels, 0.0);
  msg.performance.assign(kBaselineChannels, 0.0);
  msg.plant_epoch = epoch;
  const auto send = [&] {
    msg.seq += 1;
    msg.t_ns = monotonic_now_ns();
    ping.publish(msg);
  };
  const auto answered = [&] {
    return answers.has_fresh() && answers.newest().answers_seq == msg.seq;
  };

  // Connect: ping every 5 ms until the pong's subscription answers (it may start later).
  const std::int64_t give_up = monotonic_now_ns() + o.connect_timeout_ns;
  while (!answered()) {
    if (monotonic_now_ns() > give_up) {
      stop.publish(msg);
      throw std::runtime_error("LCM ping-pong: no answer from the pong process within " +
                               std::to_string(o.connect_timeout_ns / 1'000'000) + " ms");
    }
    send();
    lcm.handle_until(monotonic_now_ns() + 5'000'000, ReceiveMode::kBlocking, answered);
  }
  answers.take();

  PeriodicClock clock(o.clock);
  const std::int64_t periods = o.duration_ns / o.clock.period_ns;
  LatencyHistogram& rtt = *r.round_trip;
  LatencyHistogram& lateness = *r.wakeup_lateness;
  clock.start();
  while (clock.schedule().periods_elapsed() < periods) {
    lateness.record(clock.wait_next().lateness_ns);
    send();
    ++r.sent;
    lcm.handle_until(clock.next_deadline_ns(), o.receive_mode, answered, msg.t_ns);
    const std::int64_t sent_ns = msg.t_ns;
    if (const actuator_command_t* a = answers.take()) {
      if (a->answers_seq == msg.seq) {
        rtt.record(answers.newest_received_ns() - sent_ns);
        ++r.answered;
      } else {
        ++r.late_answers;
      }
    }
  }
  r.overruns = clock.schedule().overruns();
  r.unanswered = r.sent - r.answered;
  // Answers to pings that were already given up, replaced by a newer one before taken.
  r.late_answers += answers.superseded();
  r.ping_drops = answers.drops();
  for (int i = 0; i < 3; ++i) stop.publish(msg);  // UDP: say it more than once
}

}  // namespace

PingPongResult run_pingpong_baseline(const PingPongOptions& options) {
  require_private_loopback_namespace("LCM ping-pong baseline");
  if (options.duration_ns < options.clock.period_ns)
    throw std::invalid_argument("ping-pong duration is shorter than one period");
  PeriodicClock check(options.clock);  // validates period and margin before forking
  (void)check;

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
      code = run_pong(options, pipe_fd[1]);
    } catch (const std::exception& e) {
      send_block(pipe_fd[1], std::string(kPongFailed) + e.what());
    }
    _exit(code);  // the parent's atexit handlers and buffers are not the child's to run
  }
  close(pipe_fd[1]);
  r.pong_setup = receive_block(pipe_fd[0]);  // also: the pong has subscribed
  try {
    if (r.pong_setup.rfind(kPongFailed, 0) == 0) throw std::runtime_error(r.pong_setup);
    run_ping(options, r);
  } catch (...) {
    reap_child(child, 2 * kNsPerSecond, 10'000'000);
    close(pipe_fd[0]);
    throw;
  }
  r.pong_summary = receive_block(pipe_fd[0]);
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
