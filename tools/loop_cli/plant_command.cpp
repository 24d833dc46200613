// SPDX-License-Identifier: BSD-3-Clause
// `flexloop plant SCENE|LOOP.json` and `flexloop-plant LOOP.json` [--rate HZ] [--duration S]
// [--wait sleep|hybrid|spin] [--cpu N] [--safe-after N] [--safe-ramp S] [--json OUT.json]
// [--lcm-log LOG]: the
// plant process of the real-time loop (online/loop/plant_loop.hpp). Owns the clock, publishes
// FLEXLOOP_SENSOR every period and FLEXLOOP_STATS every second, applies the answers from
// FLEXLOOP_COMMAND, prints the figures at the end. Refuses to run outside the private network
// namespace (exit 1).
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/json_document.hpp"
#include "online/loop/latency_json.hpp"
#include "online/loop/plant_loop.hpp"
#include "online/loop/run_verdict.hpp"
#include "tools/loop_cli/loop_commands.hpp"
#include "tools/loop_cli/loop_options_cli.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

struct PlantArgs : LoopArgs {
  std::string json;
};

void run(const PlantArgs& a, const LoopSource& source) {
  const loop::LoopOptions o = apply_loop_options(a);
  if (!a.json.empty()) common::require_writable(a.json);  // before the run, not after it
  if (!o.lcm_log.empty()) common::require_writable(o.lcm_log);
  const loop::PlantLoopResult r = loop::run_plant_loop(
      o, source.load(o.loop_path, {.rate_hz = o.rate_hz, .form = std::nullopt, .duration_s = 0}));
  const loop::LoopAccounts& acc = r.accounts;
  loop::print_summary("round trip (ns)", *acc.round_trip);
  loop::print_summary("wakeup lateness (ns)", *acc.wakeup_lateness);
  loop::print_summary("plant compute (ns)", *acc.plant_compute);
  loop::print_summary("controller compute", *acc.controller_compute);
  std::printf(
      "cycles %lld, deadline misses %lld, late answers %lld, overruns %lld, safe-command cycles "
      "%lld, dropped %lld, stats published %lld\n",
      static_cast<long long>(r.cycles), static_cast<long long>(r.deadline_misses),
      static_cast<long long>(r.late_answers), static_cast<long long>(r.overruns),
      static_cast<long long>(r.safe_command_cycles), static_cast<long long>(r.drops.total()),
      static_cast<long long>(r.stats_published));
  const loop::PhysicalResults& ph = r.physical;
  std::printf("RMS performance outputs:");
  for (std::size_t i = 0; i < ph.performance.size(); ++i)
    std::printf(" %s %.4e %s%s", ph.performance[i].name.c_str(),
                ph.rms_performance(static_cast<Eigen::Index>(i)), ph.performance[i].unit.c_str(),
                i + 1 < ph.performance.size() ? "," : "\n");
  std::printf("RMS command (largest channel) %.4g, saturated in %.3f %% of the periods\n",
              ph.rms_command.size() ? ph.rms_command.maxCoeff() : 0.0, 100 * ph.saturated_share);
  if (!o.lcm_log.empty())
    std::printf("LCM log %s: %lld messages, %lld lost\n", o.lcm_log.c_str(),
                static_cast<long long>(r.lcm_log.recorded),
                static_cast<long long>(r.lcm_log.dropped));
  if (!a.json.empty()) {
    common::write_json_atomically(a.json, loop::plant_result_json(r, o, false));
    std::printf("wrote %s\n", a.json.c_str());
  }
  if (r.divergence.happened()) throw std::runtime_error(r.divergence_message);
  loop::throw_unless_pass(loop::plant_verdict(r, o));
}

}  // namespace

void configure_plant_command(CLI::App* cmd, const LoopSource& source) {
  auto args = std::make_shared<PlantArgs>();
  add_loop_options(cmd, *args, 0, source.help, kRoudiNeeded);
  cmd->add_option("--connect-timeout", args->options.connect_timeout_s,
                  "iceoryx: wait this long at start for the controller's subscription and answer "
                  "to be connected [s] (0: do not wait)")
      ->capture_default_str()
      ->check(finite_range(0.0, 3600.0));
  add_safe_ramp_option(cmd, *args);
  add_verdict_options(cmd, *args);
  cmd->add_option("--duration", args->options.duration_s,
                  "Run time [s] (default: the loop's [run] duration)")
      ->check(finite_positive());
  cmd->add_option("--json", args->json, "Write the figures as JSON to this file");
  cmd->add_option("--lcm-log", args->options.lcm_log,
                  "Record every message the plant sends and receives, after the loop's channel "
                  "map, into this LCM log file (flexloop log FILE -o OUT.csv|.mat)");
  cmd->footer(
      "Example (start the controller first, in the same namespace), inside one\n"
      "tools/netns-run -- bash:\n"
      "  " +
      source.prefix + "controller " + source.example +
      " --rate 1000 &\n"
      "  " +
      source.prefix + "plant " + source.example +
      " --rate 1000 --duration 10\n"
      "  kill %1\n"
      "Over iceoryx, shared memory on this host (no namespace needed):\n"
      "  flexloop roudi &\n"
      "  " +
      source.prefix + "controller " + source.example +
      " --rate 20000 --transport iceoryx &\n"
      "  " +
      source.prefix + "plant " + source.example +
      " --rate 20000 --transport iceoryx --duration 10\n"
      "  kill %2 %1\n"
      "Exit: 0 pass; 3 verdict fail (deadline misses above --max-miss-share, or stopped by "
      "--stop-after-misses, or the --lcm-log file could not be written or lost messages); 130 "
      "interrupted (SIGINT/SIGTERM: the figures cover what ran, "
      "\"partial\": true); 1 also when the plant diverged (|[z; u]| > 1e12 or not finite). --json "
      "is written in every case and says why (\"verdict\", \"divergence\").");
  cmd->callback([args, source] { run(*args, source); });
}

}  // namespace flexloop::cli
