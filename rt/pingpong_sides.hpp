// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The two sides of a ping-pong baseline (rt/pingpong_baseline.hpp), whatever carries the
// messages: `Carrier` opens the transport (Carrier::open(options, role) -> a pointer-like owner
// of a transport with subscribe() and handle_until()), names its publisher type
// (Carrier::Publisher<Msg>(transport, channel) with publish()), sets a process up
// (Carrier::set_up(transport, realtime) -> the set-up text) and names itself (Carrier::kName).
// LCM: rt/pingpong_baseline.cpp; iceoryx: rt/iceoryx_pingpong_baseline.cpp. Each side runs in
// a process of its own; see rt/pingpong_baseline.hpp for what is measured.
#include <unistd.h>

#include <cstdio>
#include <flexloop_msgs/actuator_command_t.hpp>
#include <flexloop_msgs/sensor_sample_t.hpp>
#include <stdexcept>
#include <string>

#include "rt/pingpong_baseline.hpp"

namespace flexloop::rt::pingpong {

using flexloop_msgs::actuator_command_t;
using flexloop_msgs::sensor_sample_t;

/// The checks both carriers make before forking: std::invalid_argument for a duration below one
/// period, or for a period and margin the clock refuses.
inline void check_options(const PingPongOptions& o) {
  if (o.duration_ns < o.clock.period_ns)
    throw std::invalid_argument("ping-pong duration is shorter than one period");
  PeriodicClock check(o.clock);  // validates period and margin
  (void)check;
}

// Channels of each kind in the ping-pong's messages: the size of the metrology frame's loop.
constexpr int kBaselineChannels = 6;

struct Channels {
  std::string ping, pong, stop;
  explicit Channels(const std::string& prefix)
      : ping(prefix + "_PING"), pong(prefix + "_PONG"), stop(prefix + "_STOP") {}
};

// A text block over a pipe, '\0'-terminated (the first one also says "ready").
inline void send_block(int fd, const std::string& text) {
  const std::string block = text + '\0';
  std::size_t done = 0;
  while (done < block.size()) {
    const ssize_t n = write(fd, block.data() + done, block.size() - done);
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

inline std::string receive_block(int fd) {
  std::string text;
  char c = 0;
  while (read(fd, &c, 1) == 1 && c != '\0') text += c;
  return text;
}

// The pong process: answer every ping until told to stop (or a generous time limit passes).
template <class Carrier>
int run_pong(const PingPongOptions& o, int report_fd) {
  const Channels ch(o.channel_prefix);
  const auto transport = Carrier::open(o, "pong");
  auto& carrier = *transport;
  MessageInbox<sensor_sample_t> pings;  // kFollow: a ping side's epoch is taken as it comes
  MessageInbox<sensor_sample_t> stop;
  carrier.subscribe(ch.ping, pings);
  carrier.subscribe(ch.stop, stop);
  typename Carrier::template Publisher<actuator_command_t> answer(carrier, ch.pong);
  send_block(report_fd, Carrier::set_up(carrier, o.pong_realtime));

  actuator_command_t cmd{};
  // The loop's message sizes (the metrology frame's 6 channels of each kind).
  cmd.n_commands = kBaselineChannels;
  cmd.commands.assign(kBaselineChannels, 0.0);
  const std::int64_t give_up =
      monotonic_now_ns() + o.connect_timeout_ns + o.duration_ns + 5 * kNsPerSecond;
  const auto wake = [&] { return pings.has_fresh() || stop.has_fresh(); };
  std::int64_t spin_from = 0;  // kHybrid: poll from shortly before the next ping is due
  while (!stop.has_fresh() && monotonic_now_ns() < give_up) {
    carrier.handle_until(give_up, o.receive_mode, wake, spin_from);
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

// The ping process: ping every period, account the answers.
template <class Carrier>
void run_ping(const PingPongOptions& o, PingPongResult& r) {
  const Channels ch(o.channel_prefix);
  const auto transport = Carrier::open(o, "ping");
  auto& carrier = *transport;
  const std::int64_t epoch = monotonic_now_ns() ^ (static_cast<std::int64_t>(getpid()) << 40);
  MessageInbox<actuator_command_t> answers(OrderGate(EpochPolicy::kFixed, epoch));
  carrier.subscribe(ch.pong, answers);
  typename Carrier::template Publisher<sensor_sample_t> ping(carrier, ch.ping);
  typename Carrier::template Publisher<sensor_sample_t> stop(carrier, ch.stop);
  r.ping_setup = Carrier::set_up(carrier, o.ping_realtime);

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
      throw std::runtime_error(std::string(Carrier::kName) +
                               " ping-pong: no answer from the pong process within " +
                               std::to_string(o.connect_timeout_ns / 1'000'000) + " ms");
    }
    send();
    carrier.handle_until(monotonic_now_ns() + 5'000'000, ReceiveMode::kBlocking, answered);
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
    carrier.handle_until(clock.next_deadline_ns(), o.receive_mode, answered, msg.t_ns);
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
  for (int i = 0; i < 3; ++i) stop.publish(msg);  // UDP may lose one: say it more than once
}

}  // namespace flexloop::rt::pingpong
