// SPDX-License-Identifier: BSD-3-Clause
// flexloop-controller: the controller process of the real-time loop for a loop artefact, as
// deployed. It links only online code (artefact, controller runtime, rt, msgs; the build and
// tests/link check it).
#include "tools/loop_cli/loop_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "flexloop-controller: the controller process of the real-time loop (answers each sensor\n"
      "sample), started from a loop artefact (flexloop build SCENE -o LOOP.json)."};
  flexloop::cli::configure_controller_command(&app, flexloop::cli::artefact_source());
  return flexloop::cli::run_command_line(app, argc, argv);
}
