// SPDX-License-Identifier: BSD-3-Clause
// flexloop-plant: the plant process of the real-time loop for a loop artefact, as deployed. It
// links only online code (artefact, plant runtime, controller runtime, rt, msgs; the build and
// tests/link check it), so it starts in milliseconds and carries no model or scene parser, and no
// controller FMU loader (nor libzip, nor pugixml): it runs no controller.
#include "tools/loop_cli/loop_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "flexloop-plant: the plant process of the real-time loop (owns the clock, plays the\n"
      "hardware), started from a loop artefact (flexloop build SCENE -o LOOP.json)."};
  flexloop::cli::configure_plant_command(&app, flexloop::cli::artefact_source());
  return flexloop::cli::run_command_line(app, argc, argv);
}
