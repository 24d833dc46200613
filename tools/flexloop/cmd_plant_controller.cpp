// SPDX-License-Identifier: BSD-3-Clause
// `flexloop plant` and `flexloop controller`: the loop processes (tools/loop_cli) on a scene,
// built into its loop artefact first, or on an artefact. flexloop-plant and flexloop-controller
// (tools/online) are the same processes for artefacts alone, linking no offline code.
#include "offline/scene/loop_input.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/loop_commands.hpp"

namespace flexloop::cli {

namespace {

LoopSource scene_or_artefact() {
  return {"flexloop ", kSceneOrArtefactHelp, "tools/scenes/metrology_frame.toml",
          [](const std::string& path, const artefact::LoopOverrides& o) {
            return scene::load_loop(path, o);
          }};
}

}  // namespace

void register_plant(CLI::App& app) {
  configure_plant_command(
      app.add_subcommand("plant",
                         "The plant process of the real-time loop: owns the clock, plays the "
                         "hardware"),
      scene_or_artefact());
}

void register_controller(CLI::App& app) {
  configure_controller_command(
      app.add_subcommand("controller",
                         "The controller process of the real-time loop: answers each sensor "
                         "sample"),
      scene_or_artefact());
}

}  // namespace flexloop::cli
