// SPDX-License-Identifier: BSD-3-Clause
// `flexloop baseline timer|pingpong|shm`: the same-run baselines of doc/design.md §7 on their
// own -- a bare periodic thread's wake-up lateness (cyclictest-style, rt/timer_baseline.hpp), the
// bare LCM round trip between two processes (rt/pingpong_baseline.hpp) and the shared-memory
// floor under any transport (rt/shm_pingpong_baseline.hpp). Prints min / p50 /
// p99 / p99.9 / max and counts; --json writes the same figures. The ping-pong sends multicast
// and refuses to run outside tools/netns-run's private loopback namespace (exit 1).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "common/atomic_file.hpp"
#include "online/hil/baseline_json.hpp"
#include "online/loop/latency_json.hpp"
#include "plant/lti/state_space_json.hpp"
#include "rt/iceoryx_pingpong_baseline.hpp"
#include "rt/loop_process_setup.hpp"
#include "rt/loop_transport.hpp"
#include "rt/message_validation.hpp"
#include "rt/pingpong_baseline.hpp"
#include "rt/shm_pingpong_baseline.hpp"
#include "rt/timer_baseline.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/loop_options_cli.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

struct BaselineArgs {
  double rate_hz = 1000;
  double duration_s = 2;
  std::string wait = "sleep";
  std::string receive;  // empty: follow --wait (sleep: block, hybrid: hybrid, spin: poll)
  std::string receive_path = rt::to_string(loop::LoopOptions{}.receive_path);
  double spin_margin_us = rt::kDefaultSpinMarginNs / 1e3;
  std::string overrun = "skip";
  std::string transport = "lcm";  // pingpong: lcm | iceoryx
  int cpu = 0;
  int priority = 80;
  bool no_mlock = false;
  std::string json;
};

rt::PeriodicClockOptions clock_options(const BaselineArgs& a) {
  return {.period_ns = static_cast<std::int64_t>(1e9 / a.rate_hz + 0.5),
          .wait_mode = rt::parse_wait_mode(a.wait),
          .spin_margin_ns = static_cast<std::int64_t>(a.spin_margin_us * 1e3),
          .overrun_policy = rt::parse_overrun_policy(a.overrun)};
}

rt::RealtimeOptions realtime_options(const BaselineArgs& a, int cpu) {
  return {.cpu = cpu, .lock_memory = !a.no_mlock, .fifo_priority = a.priority};
}

std::int64_t duration_ns(const BaselineArgs& a) {
  return static_cast<std::int64_t>(a.duration_s * 1e9);
}

nlohmann::json settings_json(const BaselineArgs& a, const rt::PeriodicClockOptions& c) {
  return {{"rate_hz", a.rate_hz},
          {"period_ns", c.period_ns},
          {"duration_s", a.duration_s},
          {"wait_mode", rt::to_string(c.wait_mode)},
          {"spin_margin_ns", rt::effective_spin_margin_ns(c)},  // as spun (<= half a period)
          {"overrun_policy", rt::to_string(c.overrun_policy)},
          {"cpu", a.cpu},
          {"fifo_priority", a.priority}};
}

void write_json(const std::string& path, const nlohmann::json& j) {
  if (path.empty()) return;
  plant::lti::write_json_atomically(path, j);
  std::printf("wrote %s\n", path.c_str());
}

void run_timer(const BaselineArgs& a) {
  if (!a.json.empty()) common::require_writable(a.json);  // before the run, not after it
  rt::TimerBaselineOptions o;
  o.clock = clock_options(a);
  o.duration_ns = duration_ns(a);
  o.realtime = realtime_options(a, a.cpu);
  std::printf("timer baseline: %.6g Hz for %.6g s, wait %s, CPU %d\n", a.rate_hz, a.duration_s,
              a.wait.c_str(), a.cpu);
  const rt::CpuDmaLatencyHold dma;  // as cyclictest, and as the loop processes do
  const rt::TimerBaselineResult r = rt::run_timer_baseline(o);
  std::printf("%s  %s  %s\n", r.setup.describe().c_str(), dma.active() ? "ok  " : "WARN",
              dma.message().c_str());
  loop::print_summary("wakeup lateness (ns)", *r.wakeup_lateness);
  std::printf("periods %lld, cycles %lld, overruns %lld, skipped periods %lld\n",
              static_cast<long long>(r.periods), static_cast<long long>(r.cycles),
              static_cast<long long>(r.overruns), static_cast<long long>(r.skipped_periods));
  nlohmann::json j = settings_json(a, o.clock);
  j.update(hil::timer_baseline_json(r));
  j["kind"] = "timer";
  j["cpu_dma_latency_held"] = dma.active();
  write_json(a.json, j);
}

// The ping-pong over iceoryx, against a RouDi started for it (and stopped after it).
rt::PingPongResult run_iceoryx_pingpong(const rt::PingPongOptions& o) {
  rt::RoudiProcess roudi(rt::loop_roudi_options());
  return rt::run_iceoryx_pingpong_baseline(o, roudi);
}

void run_pingpong(const BaselineArgs& a) {
  if (!a.json.empty()) common::require_writable(a.json);  // before the run, not after it
  const bool iceoryx = a.transport == "iceoryx";
  if (!iceoryx)  // LCM sends multicast: only inside the private namespace, before any output
    rt::require_private_loopback_namespace("flexloop baseline pingpong");
  rt::PingPongOptions o;
  o.clock = clock_options(a);
  o.duration_ns = duration_ns(a);
  // Unless told otherwise, receive the way the clock waits: sleep -> block, hybrid, spin -> poll.
  o.receive_mode = a.receive.empty() ? rt::receive_mode_for(o.clock.wait_mode)
                                     : rt::parse_receive_mode(a.receive);
  o.receive_path = rt::parse_receive_path(a.receive_path);
  const int pong_cpu = a.cpu < 0 ? -1 : 1 - (a.cpu % 2);  // the other of the two cores
  o.ping_realtime = realtime_options(a, a.cpu);
  o.pong_realtime = realtime_options(a, pong_cpu);
  std::printf(
      "%s ping-pong baseline: %.6g Hz for %.6g s, wait %s, receive %s (%s), ping CPU %d, "
      "pong CPU %d\n",
      iceoryx ? "iceoryx" : "LCM", a.rate_hz, a.duration_s, a.wait.c_str(),
      rt::to_string(o.receive_mode), iceoryx ? "shared memory" : rt::to_string(o.receive_path),
      a.cpu, pong_cpu);
  const rt::CpuDmaLatencyHold dma;  // held by the parent for both processes
  const rt::PingPongResult r = iceoryx ? run_iceoryx_pingpong(o) : rt::run_pingpong_baseline(o);
  std::printf("ping:\n%spong:\n%s  %s  %s\n", r.ping_setup.c_str(), r.pong_setup.c_str(),
              dma.active() ? "ok  " : "WARN", dma.message().c_str());
  loop::print_summary("round trip (ns)", *r.round_trip);
  loop::print_summary("ping wakeup lateness", *r.wakeup_lateness);
  std::printf(
      "sent %lld, answered %lld, unanswered %lld, late answers %lld, dropped %lld, "
      "overruns %lld\npong: %s\n",
      static_cast<long long>(r.sent), static_cast<long long>(r.answered),
      static_cast<long long>(r.unanswered), static_cast<long long>(r.late_answers),
      static_cast<long long>(r.ping_drops.total()), static_cast<long long>(r.overruns),
      r.pong_summary.c_str());
  nlohmann::json j = settings_json(a, o.clock);
  j["kind"] = "pingpong";
  j["cpu_dma_latency_held"] = dma.active();
  j["receive_mode"] = rt::to_string(o.receive_mode);
  j["transport"] = a.transport;
  j["receive_path"] = iceoryx ? "shared memory" : rt::to_string(o.receive_path);
  j["pong_cpu"] = pong_cpu;
  j.update(hil::pingpong_baseline_json(r));
  write_json(a.json, j);
}

struct ShmArgs {
  long long round_trips = 200'000;
  int cpu = 0;
  int priority = 80;
  bool no_mlock = false;
  std::string json;
};

void run_shm(const ShmArgs& a) {
  if (!a.json.empty()) common::require_writable(a.json);  // before the run, not after it
  rt::ShmPingPongOptions o;
  o.round_trips = a.round_trips;
  const int pong_cpu = a.cpu < 0 ? -1 : 1 - (a.cpu % 2);  // the other of the two cores
  o.ping_realtime = {.cpu = a.cpu, .lock_memory = !a.no_mlock, .fifo_priority = a.priority};
  o.pong_realtime = {.cpu = pong_cpu, .lock_memory = !a.no_mlock, .fifo_priority = a.priority};
  std::printf("shared-memory floor: %lld round trips on one cache line, ping CPU %d, pong CPU %d\n",
              a.round_trips, a.cpu, pong_cpu);
  const rt::ShmPingPongResult r = rt::run_shm_pingpong_baseline(o);
  std::printf("ping:\n%spong:\n%s", r.ping_setup.c_str(), r.pong_setup.c_str());
  loop::print_summary("round trip (ns)", *r.round_trip);
  nlohmann::json j = {{"kind", "shm"},
                      {"cpu", a.cpu},
                      {"pong_cpu", pong_cpu},
                      {"fifo_priority", a.priority},
                      {"warm_up", o.warm_up}};
  j.update(hil::shm_pingpong_baseline_json(r));
  write_json(a.json, j);
}

void register_shm(CLI::App* base) {
  auto args = std::make_shared<ShmArgs>();
  auto* shm = base->add_subcommand(
      "shm", "The shared-memory floor: two processes on the two cores spinning on one cache line");
  shm->add_option("--round-trips", args->round_trips,
                  "Recorded round trips (after 1000 unrecorded)")
      ->capture_default_str()
      ->check(CLI::Range(1LL, 1'000'000'000LL));
  add_realtime_options(shm, args->cpu, args->priority, args->no_mlock);
  shm->add_option("--json", args->json, "Write the figures as JSON to this file");
  shm->footer(
      "Back to back, no period and no transport: the floor an LCM or iceoryx round trip is read\n"
      "against. The ping side runs on --cpu, the pong side on the other of CPUs 0 and 1; the\n"
      "shared page is anonymous (no /dev/shm entry).\n"
      "Example:\n"
      "  flexloop baseline shm --round-trips 200000 --json shm.json");
  shm->callback([args] { run_shm(*args); });
}

// Options shared by both baselines.
void add_common_options(CLI::App* cmd, BaselineArgs& a) {
  cmd->add_option("--rate", a.rate_hz, "Loop rate [Hz]")
      ->capture_default_str()
      ->check(finite_range(1.0, 1e6));
  cmd->add_option("--duration", a.duration_s, "Measured time [s]")
      ->capture_default_str()
      ->check(finite_range(1e-3, 3600.0));
  add_wait_options(cmd, a.wait, a.spin_margin_us);
  cmd->add_option("--overrun", a.overrun,
                  "After a cycle starts a whole period late: skip (keep the grid) | reanchor")
      ->capture_default_str()
      ->check(CLI::IsMember({"skip", "reanchor"}));
  add_realtime_options(cmd, a.cpu, a.priority, a.no_mlock);
  cmd->add_option("--json", a.json, "Write the figures as JSON to this file");
}

}  // namespace

void register_baseline(CLI::App& app) {
  auto* base = app.add_subcommand(
      "baseline",
      "Same-run baselines: bare timer wake-up lateness, bare LCM round trip, shared-memory floor");
  base->require_subcommand(1);
  base->footer(
      "Example:\n"
      "  flexloop baseline timer --rate 10000 --wait hybrid --duration 5\n"
      "  tools/netns-run -- flexloop baseline pingpong --rate 1000 --receive poll");

  auto timer_args = std::make_shared<BaselineArgs>();
  auto* timer = base->add_subcommand(
      "timer", "A bare periodic thread's wake-up lateness (like cyclictest -m -p PRIO -i T)");
  add_common_options(timer, *timer_args);
  timer->footer(
      "Example:\n"
      "  flexloop baseline timer --rate 10000 --wait hybrid --cpu 1 --priority 80 --json t.json");
  timer->callback([timer_args] { run_timer(*timer_args); });

  auto pp_args = std::make_shared<BaselineArgs>();
  auto* pp = base->add_subcommand(
      "pingpong",
      "Bare LCM (inside tools/netns-run) or iceoryx round trip between two processes on the two "
      "cores");
  add_common_options(pp, *pp_args);
  pp->add_option("--receive", pp_args->receive,
                 "How to wait for a message: block (ppoll) | poll (spin on zero-timeout polls) | "
                 "hybrid (block, poll from --spin-margin-us before a message is due); "
                 "default: block for --wait sleep, hybrid for hybrid, poll for spin")
      ->check(CLI::IsMember({"block", "poll", "hybrid"}));
  add_receive_path_option(pp, pp_args->receive_path);
  pp->add_option("--transport", pp_args->transport,
                 "lcm (UDP multicast, inside tools/netns-run) | iceoryx (shared memory; starts "
                 "iox-roudi for the run and stops it, refuses when one already runs)")
      ->capture_default_str()
      ->check(CLI::IsMember({"lcm", "iceoryx"}));
  pp->footer(
      "The ping side runs on --cpu, the pong side on the other of CPUs 0 and 1.\n"
      "Example:\n"
      "  tools/netns-run -- build/release/tools/flexloop baseline pingpong --rate 10000 \\\n"
      "      --wait hybrid --receive poll --receive-path direct --duration 5 --json pp.json\n"
      "  build/release/tools/flexloop baseline pingpong --transport iceoryx --rate 10000 \\\n"
      "      --wait hybrid --receive poll --duration 5");
  pp->callback([pp_args] { run_pingpong(*pp_args); });

  register_shm(base);
}

}  // namespace flexloop::cli
