// flexloop: finite-element multibody model -> linearised, discretised plant -> real-time loop.
#include <cstdio>
#include <exception>

#include "plant/model/input_error.hpp"
#include "tools/flexloop/subcommands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "flexloop: linearise a flexible multibody model, discretise it, and run plant and\n"
      "controller at a hard real-time rate over LCM.\n\n"
      "Example:\n  flexloop version\n  flexloop <subcommand> --help"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every subcommand");
  flexloop::cli::register_version(app);
  flexloop::cli::register_linearise(app);
  flexloop::cli::register_analyse(app);
  flexloop::cli::register_discretise(app);
  flexloop::cli::register_build(app);
  flexloop::cli::register_baseline(app);
  flexloop::cli::register_fit_metrology(app);
  flexloop::cli::register_sim(app);
  flexloop::cli::register_plant(app);
  flexloop::cli::register_controller(app);
  flexloop::cli::register_hil(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const flexloop::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
