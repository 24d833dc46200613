// SPDX-License-Identifier: BSD-3-Clause
// `flexloop discretise IN.json --method M --rate HZ -o OUT.json`: continuous state-space JSON ->
// discrete state-space JSON (plant/lti/discretise.hpp has the equations, state_space_json.hpp
// the file format). Bad input files and refused discretisations exit 2.
#include <complex>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/pipeline/provenance.hpp"
#include "plant/lti/discretise.hpp"
#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/pole_text.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {

namespace {

namespace lti = plant::lti;

struct DiscretiseArgs {
  std::string input, output, method;
  double rate_hz = 0, prewarp_hz = 0;
  bool force = false;
};

// One line per interesting continuous eigenvalue: the one that sets the spectral radius and the
// fastest one, with where the method put it.
void print_mapping(const lti::StateSpace& c, const lti::DiscretisationOptions& o) {
  if (c.nx() == 0) return;
  // The poles as analyse computes them (balanced first); an integrator is printed as one.
  Eigen::VectorXcd lambda;
  try {
    lambda = lti::poles(c);
  } catch (const std::runtime_error&) {
    return;  // the eigensolver did not converge: nothing to say about the mapping
  }
  const double at_zero = lti::integrator_tolerance(lambda);
  Eigen::Index largest_z = 0, fastest = 0;
  for (Eigen::Index i = 1; i < lambda.size(); ++i) {
    if (std::abs(lti::map_eigenvalue(lambda(i), o)) >
        std::abs(lti::map_eigenvalue(lambda(largest_z), o)))
      largest_z = i;
    if (std::abs(lambda(i)) > std::abs(lambda(fastest))) fastest = i;
  }
  const auto line = [&](const char* what, std::complex<double> s) {
    const auto z = lti::map_eigenvalue(s, o);
    std::printf("%-16s %s -> |z| = %.9g\n", what, lti::pole_text(s, at_zero).c_str(), std::abs(z));
  };
  line("max |z| from", lambda(largest_z));
  if (fastest != largest_z) line("fastest mode", lambda(fastest));
}

void run(const DiscretiseArgs& args) {
  common::require_writable(args.output);  // before the work, not after it
  const auto in = lti::read_continuous(args.input);
  const lti::DiscretisationOptions opts{.method = lti::parse_discretisation_method(args.method),
                                        .dt = 1.0 / args.rate_hz,
                                        .prewarp_hz = args.prewarp_hz,
                                        .force = args.force};
  const lti::DiscreteStateSpace d = [&] {
    try {
      return lti::discretise(in.sys, opts);
    } catch (const std::invalid_argument& e) {
      // A refused or impossible discretisation is a problem with the user's choice: exit 2.
      throw common::InputError(args.input, e.what());
    }
  }();

  // Input path, its SHA-256 and the flexloop version/commit (shared helper), plus the settings
  // and the input's own provenance so the chain back to the model file is kept.
  nlohmann::json provenance = pipeline::make_provenance(args.input, "flexloop discretise");
  provenance["settings"] = {{"method", lti::to_string(opts.method)},
                            {"rate_hz", args.rate_hz},
                            {"prewarp_hz", args.prewarp_hz},
                            {"force", args.force}};
  if (!in.provenance.is_null()) provenance["source_provenance"] = in.provenance;
  lti::write_discrete(args.output, d, provenance);

  std::printf("%s -> %s: %lld states, %lld inputs, %lld outputs\n", args.input.c_str(),
              args.output.c_str(), static_cast<long long>(d.sys.nx()),
              static_cast<long long>(d.sys.nu()), static_cast<long long>(d.sys.ny()));
  std::printf("%-16s %s", "method", lti::to_string(d.method).c_str());
  if (d.prewarp_hz > 0) std::printf(" (pre-warped at %.6g Hz)", d.prewarp_hz);
  if (d.method == lti::DiscretisationMethod::kFirstOrderHold ||
      d.method == lti::DiscretisationMethod::kBackwardEuler)
    std::printf(" (shifted state, see plant/lti/discretise.hpp)");
  std::printf("\n%-16s %.9g s (%.9g Hz)\n", "dt", d.dt, args.rate_hz);
  std::printf("%-16s %.12g%s\n", "spectral radius", d.spectral_radius,
              d.spectral_radius > 1 ? "  (UNSTABLE)" : "");
  print_mapping(in.sys, opts);
}

}  // namespace

void register_discretise(CLI::App& app) {
  auto args = std::make_shared<DiscretiseArgs>();
  auto* cmd = app.add_subcommand("discretise",
                                 "Discretise a continuous state-space JSON file at a sample rate");
  cmd->add_option("input", args->input, "Continuous state-space JSON (A, B, C, D, labels)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--method", args->method, "zoh | foh | tustin | euler | backward-euler")
      ->required()
      ->check(CLI::Validator(
          [](std::string& name) -> std::string {
            try {
              lti::parse_discretisation_method(name);
              return {};
            } catch (const std::invalid_argument& e) {
              return e.what();
            }
          },
          "METHOD"));
  cmd->add_option("--rate", args->rate_hz, "Sample rate [Hz]")
      ->required()
      ->check(finite_positive());
  cmd->add_option("--prewarp-hz", args->prewarp_hz,
                  "Tustin only: frequency [Hz] where the discrete response matches exactly");
  cmd->add_flag("--force", args->force,
                "Keep a discretisation that turns a stable plant into an unstable one");
  cmd->add_option("-o,--output", args->output, "Discrete state-space JSON to write")->required();
  cmd->footer(
      "Example:\n"
      "  flexloop discretise plant.json --method zoh --rate 10000 -o plant_10k.json\n"
      "  flexloop discretise plant.json --method tustin --prewarp-hz 120 --rate 2000 -o t.json");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
