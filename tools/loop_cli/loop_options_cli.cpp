// SPDX-License-Identifier: BSD-3-Clause
#include "tools/loop_cli/loop_options_cli.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

void add_wait_options(CLI::App* cmd, std::string& wait, double& spin_margin_us) {
  cmd->add_option("--wait", wait,
                  "How to wait for a deadline: sleep | hybrid (sleep, then spin) | spin")
      ->capture_default_str()
      ->check(CLI::IsMember({"sleep", "hybrid", "spin"}));
  cmd->add_option("--spin-margin-us", spin_margin_us,
                  "hybrid: sleep until this long before the deadline, then spin [us]")
      ->capture_default_str()
      ->check(finite_range(0.0, 1e6));
}

void add_receive_path_option(CLI::App* cmd, std::string& path) {
  cmd->add_option("--receive-path", path,
                  "Who reads the LCM socket: lcm-thread (LCM's receive thread, handing over "
                  "through a pipe) | direct (the loop thread reads the multicast socket itself)")
      ->capture_default_str()
      ->check(CLI::IsMember({"lcm-thread", "direct"}));
}

void add_transport_option(CLI::App* cmd, std::string& transport, const std::string& iceoryx) {
  cmd->add_option("--transport", transport,
                  "The messages' carrier: lcm (UDP multicast, inside a private namespace) | "
                  "iceoryx (shared memory on this host; " +
                      iceoryx + ")")
      ->capture_default_str()
      ->check(CLI::IsMember({"lcm", "iceoryx"}));
}

void add_realtime_options(CLI::App* cmd, int& cpu, int& priority, bool& no_mlock) {
  cmd->add_option("--cpu", cpu, "CPU to pin to (-1: do not pin)")
      ->capture_default_str()
      ->check(CLI::Range(-1, 1023));
  cmd->add_option("--priority", priority,
                  "SCHED_FIFO priority 1..99 when permitted (0: normal scheduling)")
      ->capture_default_str()
      ->check(CLI::Range(0, 99));
  cmd->add_flag("--no-mlock", no_mlock, "Do not lock memory");
}

void add_loop_options(CLI::App* cmd, LoopArgs& a, int default_cpu, const std::string& loop_help,
                      const std::string& roudi_help) {
  loop::LoopOptions& o = a.options;
  o.realtime.cpu = default_cpu;
  cmd->add_option("loop", o.loop_path, loop_help)->required()->check(CLI::ExistingFile);
  cmd->add_option(
         "--rate", o.rate_hz,
         "Loop rate [Hz] (default: the scene's discretisation rate; an artefact runs at its own)")
      ->check(finite_range(1.0, 1e6));
  add_wait_options(cmd, a.wait, a.spin_margin_us);
  add_receive_path_option(cmd, a.receive_path);
  add_transport_option(cmd, a.transport, roudi_help);
  add_realtime_options(cmd, o.realtime.cpu, o.realtime.fifo_priority, a.no_mlock);
  cmd->add_option("--safe-after", o.safe_after,
                  "Consecutive missed answers before the plant applies the safe command (a ramp "
                  "to zero force, --safe-ramp); give plant and controller the same value")
      ->capture_default_str()
      ->check(CLI::Range(1, 1'000'000));
  cmd->add_option("--start", a.start,
                  "stationary: plant, hardware and controller start in a draw from the loop's "
                  "stationary distribution (the same seeds, the same draw, in the plant and the "
                  "controller process); rest: at rest, the floor stationary. Give plant and "
                  "controller the same")
      ->capture_default_str()
      ->check(CLI::IsMember({"stationary", "rest"}));
  cmd->add_option("--url", o.url,
                  "LCM URL (default: $LCM_DEFAULT_URL, else ttl=0 multicast on loopback)");
  cmd->add_option("--link", o.link,
                  "Allow this veth interface besides loopback (two namespaces joined by a veth "
                  "pair with private addresses; ttl <= 1)");
}

void add_safe_ramp_option(CLI::App* cmd, LoopArgs& a) {
  cmd->add_option("--safe-ramp", a.options.safe_ramp_s,
                  "The safe command is a controlled stop: it ramps the held command linearly to "
                  "zero over this time [s] (0: zero force at once). Make it several periods of the "
                  "machine's slowest mode: zero at once kicks a force-feedback loop")
      ->capture_default_str()
      ->check(finite_range(0.0, 3600.0));
}

void add_verdict_options(CLI::App* cmd, LoopArgs& a) {
  cmd->add_option("--max-miss-share", a.max_miss_percent,
                  "Verdict: the run fails (exit 3) when more than this share of its cycles missed "
                  "their answer's deadline [%]")
      ->capture_default_str()
      ->check(finite_range(0.0, 100.0));
  cmd->add_option("--stop-after-misses", a.options.limits.stop_after_misses,
                  "Overrun policy: stop the run at this many deadline misses, and fail it (0: go "
                  "on whatever misses)")
      ->capture_default_str()
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{1'000'000'000'000}));
}

loop::LoopOptions apply_loop_options(const LoopArgs& a) {
  loop::LoopOptions o = a.options;
  o.wait = rt::parse_wait_mode(a.wait);
  o.receive_path = rt::parse_receive_path(a.receive_path);
  o.transport = rt::parse_transport(a.transport);
  o.spin_margin_ns = static_cast<std::int64_t>(a.spin_margin_us * 1e3);
  o.realtime.lock_memory = !a.no_mlock;
  o.start = a.start == "rest" ? sim::StartKind::kRest : sim::StartKind::kStationary;
  o.limits.max_miss_share = a.max_miss_percent / 100;
  return o;
}

}  // namespace flexloop::cli
