// `flexloop controller SCENE|LOOP.json [--rate HZ] [--wait sleep|hybrid|spin] [--cpu N]
// [--safe-after N]
//  [--duration S]`: the controller process of the real-time loop (tools/hil/controller_loop.hpp).
// Answers every FLEXLOOP_SENSOR sample with a FLEXLOOP_COMMAND until SIGINT / SIGTERM, then
// prints its counts. Give it the plant's --rate (the PI controller is sampled at it). Refuses to
// run outside the private network namespace (exit 1).
#include <cstdio>
#include <memory>

#include "tools/flexloop/loop_options_cli.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/hil/controller_loop.hpp"
#include "tools/hil/latency_json.hpp"
#include "tools/scene/loop_input.hpp"

namespace flexloop::cli {

namespace {

void run(const LoopArgs& a) {
  const hil::LoopOptions o = apply_loop_options(a);
  const hil::ControllerLoopResult r = hil::run_controller_loop(
      o, scene::load_loop(o.loop_path, {.rate_hz = o.rate_hz, .form = "", .duration_s = 0}));
  hil::print_summary("compute (ns)", *r.compute);
  hil::print_summary("receive -> send (ns)", *r.response);
  std::printf(
      "answered %lld, superseded %lld, plant restarts followed %lld, bumpless resumes %lld, "
      "dropped %s\n",
      static_cast<long long>(r.answered), static_cast<long long>(r.superseded),
      static_cast<long long>(r.resyncs), static_cast<long long>(r.resumes),
      hil::drops_json(r.drops).dump().c_str());
}

}  // namespace

void register_controller(CLI::App& app) {
  auto args = std::make_shared<LoopArgs>();
  auto* cmd = app.add_subcommand(
      "controller", "The controller process of the real-time loop: answers each sensor sample");
  add_loop_options(cmd, *args, 1);
  cmd->add_option("--duration", args->options.duration_s,
                  "Stop after this long [s] (default: until SIGINT / SIGTERM)")
      ->check(CLI::PositiveNumber);
  cmd->footer(
      "Example (inside tools/netns-run -- bash, with the plant started afterwards):\n"
      "  flexloop controller tools/scenes/metrology_frame.toml --rate 1000 --wait hybrid");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
