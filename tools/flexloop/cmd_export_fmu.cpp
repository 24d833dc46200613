// SPDX-License-Identifier: BSD-3-Clause
// `flexloop export-fmu SCENE|LOOP.json -o PLANT.fmu [--rate HZ] [--form dense|modal]`: the loop's
// plant with its simulated hardware and floor as an FMI 2.0 Co-Simulation FMU
// (offline/pipeline/plant_fmu_export.hpp), for a user's own simulation tool.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "common/atomic_file.hpp"
#include "offline/pipeline/plant_fmu_export.hpp"
#include "offline/scene/loop_input.hpp"
#include "offline/scene/scene.hpp"
#include "online/plant_fmu/plant_fmu_variables.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

struct ExportArgs {
  std::string loop, output, form;
  double rate_hz = 0;
};

// The plant FMU library: where this build made it, else where it is installed relative to the
// flexloop executable (doc/install.md), else beside it.
std::filesystem::path plant_library() {
  const std::filesystem::path built = FLEXLOOP_PLANT_FMU_LIBRARY;
  if (std::filesystem::is_regular_file(built)) return built;
  std::error_code ec;
  const auto bin = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
  const std::string name = std::string(plant_fmu::kModelIdentifier) + ".so";
  const auto installed = bin / FLEXLOOP_PLANT_FMU_INSTALLED_DIR / name;
  if (std::filesystem::is_regular_file(installed)) return installed;
  return bin / name;
}

void run(const ExportArgs& args) {
  common::require_creatable(args.output);  // before the work, not after it
  const artefact::LoopArtefact a = scene::load_loop(
      args.loop, {.rate_hz = args.rate_hz,
                  .form = args.form.empty() ? std::nullopt
                                            : std::optional(artefact::parse_plant_form(args.form)),
                  .duration_s = 0});
  pipeline::export_plant_fmu(a, plant_library(), args.output);
  std::printf("plant FMU of loop %s: %s plant, %zu states, step %.6g s (%.6g Hz)\n", a.name.c_str(),
              artefact::to_string(a.plant.form).c_str(), a.plant.states.size(), a.dt(), a.rate_hz);
  std::printf(
      "inputs: %ld actuator commands; outputs: %ld sensors, %ld performance sensors; "
      "parameter start_at_rest (default false: the open loop's stationary start)\n",
      static_cast<long>(a.actuators()), static_cast<long>(a.sensors()),
      static_cast<long>(a.performance()));
  std::printf("wrote %s\n", args.output.c_str());
}

}  // namespace

void register_export_fmu(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand(
      "export-fmu",
      "Export the loop's plant, simulated hardware and floor as an FMI 2.0 Co-Simulation FMU");
  cmd->add_option("loop", args->loop, "Scene file (TOML) or loop artefact (JSON, flexloop build)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "The FMU to write (.fmu)")->required();
  cmd->add_option("--rate", args->rate_hz,
                  "Sample rate [Hz] of a scene (default: the scene's; an artefact has its own)")
      ->check(finite_range(1e-3, scene::kMaxLoopRateHz));
  cmd->add_option("--form", args->form,
                  "Plant form of a scene: dense or modal (default: dense; an artefact as built)")
      ->check(CLI::IsMember({"dense", "modal"}));
  cmd->footer(
      "Example:\n  flexloop export-fmu tools/scenes/metrology_frame.toml -o metrology_plant.fmu\n"
      "  (inputs actuator.<channel>, outputs sensor.<channel> and performance.<channel>; one "
      "fmi2DoStep per loop period)");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
