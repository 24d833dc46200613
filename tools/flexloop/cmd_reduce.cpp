// SPDX-License-Identifier: BSD-3-Clause
// `flexloop reduce PLANT.json --method balanced|modal|modal-dc (--order N | --below-hz F)
//  -o REDUCED.json`
// A continuous state-space JSON (as `flexloop linearise` writes it) reduced to fewer states with
// the same inputs and outputs (plant/lti/model_reduction.hpp), written in the same format, so
// that `discretise` and every other command that reads one takes it.
#include <cmath>
#include <cstdio>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "offline/pipeline/provenance.hpp"
#include "plant/lti/model_reduction.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tools/flexloop/subcommands.hpp"
#include "tools/loop_cli/number_checks.hpp"

namespace flexloop::cli {
namespace {

namespace lti = plant::lti;

struct ReduceArgs {
  std::string input, output, method = "balanced";
  int order = -1;
  double below_hz = 0, band_hz = 0;
};

void run(const ReduceArgs& a) {
  common::require_writable(a.output);  // before the work, not after it
  const auto in = lti::read_continuous(a.input);
  const int n = static_cast<int>(in.sys.nx());
  if (a.order > n)
    throw common::InputError("--order", std::to_string(a.order) + " is above the model's " +
                                            std::to_string(n) + " states");
  if (a.method == "balanced" && a.order < 0)
    throw common::InputError("--order",
                             "balanced truncation needs an order (--below-hz is for modal)");
  if (a.method != "balanced" && a.order < 0 && !(a.below_hz > 0))
    throw common::InputError("--order", "give an order or --below-hz");
  const lti::ReducedModel r = [&] {
    try {
      if (a.method == "balanced") return lti::balanced_truncation(in.sys, a.order);
      return lti::modal_truncation(
          in.sys,
          {.order = a.order, .below_hz = a.below_hz, .dc_correction = a.method == "modal-dc"});
    } catch (const std::invalid_argument& e) {
      throw common::InputError(a.input, e.what());
    }
  }();

  nlohmann::json provenance = pipeline::make_provenance(a.input, "flexloop reduce");
  provenance["settings"] = {{"method", a.method}, {"order", a.order}, {"below_hz", a.below_hz}};
  if (std::isfinite(r.error_bound)) provenance["error_bound_hinf"] = r.error_bound;
  if (!in.provenance.is_null()) provenance["source_provenance"] = in.provenance;
  lti::write_continuous(a.output, r.sys, provenance);

  std::printf("%s -> %s: %d -> %lld states (%s), %lld inputs, %lld outputs\n", a.input.c_str(),
              a.output.c_str(), n, static_cast<long long>(r.sys.nx()), r.method.c_str(),
              static_cast<long long>(r.sys.nu()), static_cast<long long>(r.sys.ny()));
  if (r.kept_unstable > 0)
    std::printf("kept whole: %d states with poles at the origin or unstable\n", r.kept_unstable);
  if (r.hankel_singular_values.size() > 0) {
    std::printf("Hankel singular values of the stable part:");
    for (Eigen::Index k = 0; k < r.hankel_singular_values.size(); ++k)
      std::printf("%s%.4g", k == r.sys.nx() - r.kept_unstable ? " | " : " ",
                  r.hankel_singular_values(k));
    std::printf("\nH-inf error bound 2 x (sum of those discarded): %.4g\n", r.error_bound);
  } else {
    for (const auto& m : lti::modal_contributions(in.sys, {.band_hz = a.band_hz}))
      if (m.at_origin)  // integrators: no frequency, no damping
        std::printf("  integrator%s at s = 0 (%d state%s), always kept\n", m.states == 1 ? "" : "s",
                    m.states, m.states == 1 ? "" : "s");
      else
        std::printf("  mode %10.4g Hz  damping %-8.3g contribution %.3g\n", m.frequency_hz,
                    m.damping, m.contribution);
  }
}

}  // namespace

void register_reduce(CLI::App& app) {
  auto args = std::make_shared<ReduceArgs>();
  auto* cmd = app.add_subcommand(
      "reduce",
      "Reduce a continuous state-space JSON file to fewer states (balanced or modal truncation), "
      "same inputs and outputs, same format");
  cmd->add_option("input", args->input, "Continuous state-space JSON (A, B, C, D, labels)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--method", args->method,
                  "balanced (SLICOT AB09MD, with the H-inf error bound), modal (the modes of "
                  "largest contribution), modal-dc (with static correction)")
      ->check(CLI::IsMember({"balanced", "modal", "modal-dc"}))
      ->capture_default_str();
  cmd->add_option("--order", args->order, "States to keep")->check(CLI::Range(0, 1'000'000));
  cmd->add_option("--below-hz", args->below_hz, "Modal: keep the modes below this frequency")
      ->check(finite_positive());
  cmd->add_option("--band-hz", args->band_hz,
                  "Modal: judge the modes' contributions below this frequency (a mode above it "
                  "counts with its quasi-static tail there)")
      ->check(finite_positive());
  cmd->add_option("-o,--output", args->output, "Continuous state-space JSON to write")->required();
  cmd->footer(
      "Example:\n"
      "  flexloop linearise tools/models/flexible_arm.toml -i acc:y.0 -i stress:e1.sa "
      "-O acc:y.25 -O stress:e1.sa -o arm.json\n"
      "  flexloop reduce arm.json --method balanced --order 20 -o arm_20.json\n"
      "  flexloop reduce arm.json --method modal-dc --order 16 --band-hz 500 -o arm_16.json\n"
      "  flexloop discretise arm_20.json --method zoh --rate 10000 -o arm_20_10k.json");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
