// `flexloop linearise MODEL [--input NAME]... [--output NAME]... -o OUT.json`
// Linearises a model file about its stationary configuration and writes the labelled state
// space with the natural frequencies and provenance.
#include <cstdio>
#include <memory>

#include "plant/lti/modal_analysis.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/lti/state_space_json.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"
#include "tools/flexloop/provenance.hpp"
#include "tools/flexloop/subcommands.hpp"

namespace flexloop::cli {

namespace {

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

// Default channels: every prescribed coordinate as an acceleration and every actuated
// deformation as a stress in; every dynamic coordinate's position out.
void default_channels(const plant::model::Model& m, LineariseArgs& a) {
  if (a.inputs.empty()) {
    for (int i = m.nd(); i < m.nq(); ++i) a.inputs.push_back("acc:" + m.generalised[i]);
    for (const auto& el : m.elements)
      for (int k = 0; k < el.deformation_count(); ++k)
        if (el.actuated[k])
          a.inputs.push_back("stress:" + m.deformation_labels[el.first_deformation + k]);
  }
  if (a.outputs.empty())
    for (int i = 0; i < m.nd(); ++i) a.outputs.push_back("pos:" + m.generalised[i]);
}

void run(LineariseArgs a) {
  namespace model = plant::model;
  namespace lti = plant::lti;
  const model::Model m = model::load_model(a.model);
  default_channels(m, a);
  const model::Linearisation lin = model::linearise(m);
  const lti::StateSpace ss = lti::build_state_space(m, lin, a.inputs, a.outputs);
  const int nd = m.nd();
  const lti::Modes modes = lti::natural_modes(lin.M.topLeftCorner(nd, nd),
                                              (lin.K + lin.N + lin.G).topLeftCorner(nd, nd));

  nlohmann::json j = lti::to_json(ss, make_provenance(a.model, "flexloop linearise"));
  j["natural_frequencies_hz"] =
      std::vector<double>(modes.frequencies_hz.data(), modes.frequencies_hz.data() + nd);
  j["generalised_coordinates"] = m.generalised;
  j["dynamic_count"] = nd;
  j["matrices"] = {{"M", matrix_json(lin.M)}, {"C", matrix_json(lin.C)}, {"D", matrix_json(lin.D)},
                   {"K", matrix_json(lin.K)}, {"N", matrix_json(lin.N)}, {"G", matrix_json(lin.G)}};
  lti::write_json_atomically(a.output, j);

  std::printf("model      %s (%s, %d-D)\n", m.name.c_str(), a.model.c_str(), m.dim);
  std::printf(
      "size       %d nodal coordinates, %d deformations, %d dynamic + %d prescribed coordinates\n",
      m.nx(), m.ne(), nd, m.nr());
  std::printf("state      %ld states, %ld inputs, %ld outputs\n", static_cast<long>(ss.nx()),
              static_cast<long>(ss.nu()), static_cast<long>(ss.ny()));
  std::printf("frequencies (Hz):");
  for (int i = 0; i < nd; ++i) std::printf(" %.4g", modes.frequencies_hz(i));
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
