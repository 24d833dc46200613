// SPDX-License-Identifier: BSD-3-Clause
// `flexloop build SCENE -o LOOP.json [--rate HZ] [--form dense|modal]`: runs the offline pipeline
// of a scene once (model -> linearisation -> controller design -> discretisation) and writes the
// discrete loop artefact (artefact/loop_artefact.hpp, doc/loop_artefact.md) that `flexloop sim`,
// `plant`, `controller` and `hil` run without reading the model or the scene again.
#include <cstdio>
#include <memory>

#include "common/atomic_file.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

struct BuildArgs {
  std::string scene, output, form = "dense";
  double rate_hz = 0;
};

// One line per loop start: whether it exists, what it leaves out, and how well its data fix it.
void print_start(const char* which, const artefact::StationaryStart& s) {
  if (!s.exists()) {
    std::printf("start, %s: at rest (%s)\n", which, s.unavailable.c_str());
    return;
  }
  std::printf(
      "start, %s: stationary, covariance determined to about %.1e relative by the loop's "
      "matrix%s%s\n",
      which, s.sensitivity, s.note.empty() ? "" : "; ", s.note.c_str());
}

void run(const BuildArgs& args) {
  common::require_writable(args.output);  // before the work, not after it
  const artefact::LoopArtefact a = scene::load_loop(
      args.scene,
      {.rate_hz = args.rate_hz, .form = artefact::parse_plant_form(args.form), .duration_s = 0});
  artefact::write_loop_artefact(args.output, a);
  std::printf("loop %s: %s plant, %zu states, %.6g Hz (%s), controller %s\n", a.name.c_str(),
              artefact::to_string(a.plant.form).c_str(), a.plant.states.size(), a.rate_hz,
              artefact::to_string(a.method).c_str(), artefact::to_string(a.controller).c_str());
  std::printf("channels: %ld disturbances, %ld actuators, %ld performance outputs, %ld sensors\n",
              static_cast<long>(a.disturbances()), static_cast<long>(a.actuators()),
              static_cast<long>(a.performance()), static_cast<long>(a.sensors()));
  std::printf("spectral radius of Ad: %.12f\n", a.plant.spectral_radius);
  print_start("open loop", a.start.open_loop);
  print_start("closed loop", a.start.closed_loop);
  std::printf("wrote %s\n", args.output.c_str());
}

}  // namespace

void register_build(CLI::App& app) {
  auto args = std::make_shared<BuildArgs>();
  auto* cmd = app.add_subcommand(
      "build", "Build a scene's discrete loop artefact (the input of sim, plant, controller, hil)");
  cmd->add_option("scene", args->scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Loop artefact to write (JSON)")->required();
  cmd->add_option("--rate", args->rate_hz, "Sample rate [Hz] (default: the scene's)")
      ->check(finite_range(1e-3, scene::kMaxLoopRateHz));
  cmd->add_option("--form", args->form, "Plant form: dense or modal (real block-diagonal)")
      ->capture_default_str()
      ->check(CLI::IsMember({"dense", "modal"}));
  cmd->footer(
      "Example:\n  flexloop build tools/scenes/metrology_frame.toml -o out/metrology_loop.json\n"
      "  flexloop sim out/metrology_loop.json --duration 10");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
