// SPDX-License-Identifier: BSD-3-Clause
// `flexloop controller SCENE|LOOP.json` and `flexloop-controller LOOP.json` [--rate HZ]
// [--wait sleep|hybrid|spin] [--cpu N] [--safe-after N] [--duration S]: the controller process of
// the real-time loop (online/loop/controller_loop.hpp). Answers every FLEXLOOP_SENSOR sample with a
// FLEXLOOP_COMMAND until SIGINT / SIGTERM, then prints its counts. Give it the plant's --rate (the
// PI controller is sampled at it). Refuses to run outside the private network namespace (exit 1).
#include <cstdio>
#include <memory>

#include "online/loop/controller_loop.hpp"
#include "online/loop/latency_json.hpp"
#include "online/loop/run_verdict.hpp"
#include "tools/loop_cli/loop_commands.hpp"
#include "tools/loop_cli/loop_options_cli.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

void run(const LoopArgs& a, const LoopSource& source) {
  const loop::LoopOptions o = apply_loop_options(a);
  const loop::ControllerLoopResult r = loop::run_controller_loop(
      o, source.load(o.loop_path, {.rate_hz = o.rate_hz, .form = std::nullopt, .duration_s = 0}));
  loop::print_summary("compute (ns)", *r.compute);
  loop::print_summary("receive -> send (ns)", *r.response);
  std::printf(
      "answered %lld, superseded %lld, plant restarts followed %lld, bumpless resumes %lld, "
      "dropped %s\n",
      static_cast<long long>(r.answered), static_cast<long long>(r.superseded),
      static_cast<long long>(r.resyncs), static_cast<long long>(r.resumes),
      loop::drops_json(r.drops).dump().c_str());
  std::printf(
      "%s\n",
      loop::real_time_promises_json(loop::answer_watch(r))["summary"].get<std::string>().c_str());
  if (r.controller_warnings > 0)
    std::printf("warning: the controller FMU returned fmi2Warning %ld times; the first: %s\n",
                r.controller_warnings, r.first_warning.c_str());
  if (!r.controller_failure.empty())
    throw loop::VerdictFailure{3,
                               "verdict fail: the controller FMU failed: " + r.controller_failure +
                                   "; answered with the safe command (zero force) from then on"};
}

}  // namespace

void configure_controller_command(CLI::App* cmd, const LoopSource& source) {
  auto args = std::make_shared<LoopArgs>();
  add_loop_options(cmd, *args, 1, source.help, kRoudiNeeded);
  cmd->add_option("--duration", args->options.duration_s,
                  "Stop after this long [s] (default: until SIGINT / SIGTERM)")
      ->check(finite_positive());
  cmd->footer(
      "Example (inside tools/netns-run -- bash, with the plant started afterwards):\n"
      "  " +
      source.prefix + "controller " + source.example +
      " --rate 1000 --wait hybrid\n"
      "Over iceoryx (no namespace needed; RouDi first: flexloop roudi &):\n"
      "  " +
      source.prefix + "controller " + source.example + " --rate 20000 --transport iceoryx");
  cmd->callback([args, source] { run(*args, source); });
}

}  // namespace flexloop::cli
