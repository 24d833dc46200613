// SPDX-License-Identifier: BSD-3-Clause
// `flexloop linearise MODEL [--input NAME]... [--output NAME]... -o OUT.json`
// Linearises a model file about its stationary configuration and writes the labelled state
// space with the natural frequencies and provenance.
#include <cstdio>
#include <memory>

#include "common/atomic_file.hpp"
#include "offline/pipeline/linearised_model.hpp"
#include "offline/pipeline/provenance.hpp"
#include "offline/pipeline/superelement_provenance.hpp"
#include "plant/lti/state_space_json.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

namespace {

namespace lti = plant::lti;

struct LineariseArgs {
  std::string model, output;
  std::vector<std::string> inputs, outputs;
};

nlohmann::json matrix_json(const Eigen::MatrixXd& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < M.cols(); ++j) row.push_back(M(i, j));
    rows.push_back(row);
  }
  return rows;
}

// "a, b, c" for up to six names, then "... (n in all)".
std::string name_list(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < 6; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > 6) out += ", ... (" + std::to_string(names.size()) + " in all)";
  return out.empty() ? "none" : out;
}

void run(const LineariseArgs& a) {
  common::require_writable(a.output);  // before the work, not after it
  const pipeline::LinearisedModel r = pipeline::linearise_model_file(a.model, a.inputs, a.outputs);
  const auto& m = r.model;
  const auto& lin = r.lin;
  const auto& ss = r.ss;
  const int nd = m.nd();
  const Eigen::VectorXd& f = r.natural_frequencies_hz;

  nlohmann::json j = lti::to_json(ss, pipeline::make_provenance(a.model, "flexloop linearise"));
  if (!m.superelements.empty())
    j["provenance"]["superelements"] = pipeline::superelement_provenance(m);
  j["natural_frequencies_hz"] = std::vector<double>(f.data(), f.data() + f.size());
  j["generalised_coordinates"] = m.generalised;
  j["dynamic_count"] = nd;
  const lti::Condensation& c = r.condensation;
  if (c.massless_count > 0)
    j["condensation"] = {{"massless_directions", c.massless_count},
                         {"state_coordinates", c.state_coordinates},
                         {"condensed_coordinates", c.condensed},
                         {"damping_coupling", c.damping_coupling},
                         {"rate_terms_dropped", c.rate_terms_dropped}};
  j["matrices"] = {{"M", matrix_json(lin.M)}, {"C", matrix_json(lin.C)}, {"D", matrix_json(lin.D)},
                   {"K", matrix_json(lin.K)}, {"N", matrix_json(lin.N)}, {"G", matrix_json(lin.G)}};
  lti::write_json_atomically(a.output, j);

  std::printf("model      %s (%s, %d-D)\n", m.name.c_str(), a.model.c_str(), m.dim);
  std::printf(
      "size       %d nodal coordinates, %d deformations, %d dynamic + %d prescribed coordinates\n",
      m.nx(), m.ne(), nd, m.nr());
  std::printf("state      %ld states, %ld inputs, %ld outputs\n", static_cast<long>(ss.nx()),
              static_cast<long>(ss.nu()), static_cast<long>(ss.ny()));
  if (c.massless_count > 0) {
    std::printf(
        "condensed  %d massless directions statically; states pos/vel of %s; following %s\n",
        c.massless_count, name_list(c.state_coordinates).c_str(), name_list(c.condensed).c_str());
    if (c.damping_coupling > 1e-9)  // above rounding
      std::printf(
          "           damping on massless directions neglected (|Z^T C| / |C| = %.3g): their "
          "relaxation is taken as instantaneous\n",
          c.damping_coupling);
    if (!c.rate_terms_dropped.empty())
      std::printf(
          "           rates of %s act on massless directions: velocity/acceleration outputs and "
          "damping leave them out\n",
          name_list(c.rate_terms_dropped).c_str());
  }
  std::printf("frequencies (Hz):");
  for (Eigen::Index i = 0; i < f.size(); ++i) std::printf(" %.4g", f(i));
  if (r.massless_condensed > 0)
    std::printf(" (%d massless directions condensed)", r.massless_condensed);
  std::printf("\ngeometric stiffness |G|/|K| = %.3g\n",
              lin.G.norm() / std::max(lin.K.norm(), 1e-300));
  std::printf("wrote      %s\n", a.output.c_str());
}

}  // namespace

void register_linearise(CLI::App& app) {
  auto args = std::make_shared<LineariseArgs>();
  auto* cmd = app.add_subcommand(
      "linearise", "Linearise a finite-element multibody model into a labelled state space");
  cmd->add_option("model", args->model, "Model file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option(
      "--input,-i", args->inputs,
      "Input channel: force:<coordinate>, stress:<deformation>, pos|vel|acc:<prescribed "
      "coordinate> "
      "(default: acc of every prescribed coordinate and stress of every actuated deformation)");
  cmd->add_option(
      "--output,-O", args->outputs,
      "Output channel: pos|vel|acc:<coordinate>, pos:<deformation>, stress:<deformation> "
      "(default: pos of every dynamic coordinate)");
  cmd->add_option("-o,--out", args->output, "Output JSON file")->required();
  cmd->footer(
      "Example:\n  flexloop linearise tools/models/cart.toml --input acc:x.1 --input vel:x.1 "
      "--input pos:x.1 \\\n"
      "      --output pos:x.2 -o cart.json");
  cmd->callback([args] { run(*args); });
}

}  // namespace flexloop::cli
