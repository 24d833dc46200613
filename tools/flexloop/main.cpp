// SPDX-License-Identifier: BSD-3-Clause
// flexloop: finite-element multibody model -> linearised, discretised plant -> real-time loop.
#include "tools/flexloop/blas_threads.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/loop_commands.hpp"

int main(int argc, char** argv) {
  flexloop::cli::set_blas_threads();  // one spinning BLAS thread per process (blas_threads.hpp)
  CLI::App app{
      "flexloop: linearise a flexible multibody model, discretise it, and run plant and\n"
      "controller as two real-time processes over LCM or iceoryx.\n\n"
      "Example:\n  flexloop version\n  flexloop <subcommand> --help"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every subcommand");
  flexloop::cli::register_version(app);
  flexloop::cli::register_linearise(app);
  flexloop::cli::register_analyse(app);
  flexloop::cli::register_discretise(app);
  flexloop::cli::register_reduce(app);
  flexloop::cli::register_export_fmu(app);
  flexloop::cli::register_build(app);
  flexloop::cli::register_baseline(app);
  flexloop::cli::register_fit_metrology(app);
  flexloop::cli::register_sim(app);
  flexloop::cli::register_plant(app);
  flexloop::cli::register_controller(app);
  flexloop::cli::register_hil(app);
  flexloop::cli::register_log(app);
  flexloop::cli::register_replay(app);
  flexloop::cli::register_tradeoff(app);
  flexloop::cli::register_campaign(app);
  flexloop::cli::register_roudi(app);
  return flexloop::cli::run_command_line(app, argc, argv);
}
